/* The few STM32F103 registers this firmware uses, written from the reference manual
 * (RM0008) because no CMSIS/ST package is available from Debian or PyPI. Every offset
 * is checked by a static assert below, so a typo in a struct cannot go unnoticed. */
#ifndef OF_STM32F103_H
#define OF_STM32F103_H

#include <stddef.h>
#include <stdint.h>

#define REG volatile uint32_t

typedef struct {
    REG CR, CFGR, CIR, APB2RSTR, APB1RSTR, AHBENR, APB2ENR, APB1ENR, BDCR, CSR;
} rcc_t;

typedef struct {
    REG ACR, KEYR, OPTKEYR, SR, CR, AR, RESERVED, OBR, WRPR;
} flash_t;

typedef struct {
    REG CRL, CRH, IDR, ODR, BSRR, BRR, LCKR;
} gpio_t;

typedef struct {
    REG CR1, CR2, SMCR, DIER, SR, EGR, CCMR1, CCMR2, CCER, CNT, PSC, ARR, RCR;
    REG CCR1, CCR2, CCR3, CCR4, BDTR, DCR, DMAR;
} tim_t;

typedef struct {
    REG SR, DR, BRR, CR1, CR2, CR3, GTPR;
} usart_t;

typedef struct {
    REG KR, PR, RLR, SR;
} iwdg_t;

typedef struct {
    REG CPUID, ICSR, VTOR, AIRCR, SCR, CCR;
} scb_t;

_Static_assert(offsetof(rcc_t, CFGR) == 0x04, "RCC_CFGR");
_Static_assert(offsetof(rcc_t, APB2ENR) == 0x18, "RCC_APB2ENR");
_Static_assert(offsetof(rcc_t, APB1ENR) == 0x1C, "RCC_APB1ENR");
_Static_assert(offsetof(rcc_t, CSR) == 0x24, "RCC_CSR");
_Static_assert(offsetof(flash_t, ACR) == 0x00, "FLASH_ACR");
_Static_assert(offsetof(flash_t, WRPR) == 0x20, "FLASH_WRPR");
_Static_assert(offsetof(gpio_t, IDR) == 0x08, "GPIO_IDR");
_Static_assert(offsetof(gpio_t, BSRR) == 0x10, "GPIO_BSRR");
_Static_assert(offsetof(gpio_t, BRR) == 0x14, "GPIO_BRR");
_Static_assert(offsetof(tim_t, DIER) == 0x0C, "TIM_DIER");
_Static_assert(offsetof(tim_t, SR) == 0x10, "TIM_SR");
_Static_assert(offsetof(tim_t, EGR) == 0x14, "TIM_EGR");
_Static_assert(offsetof(tim_t, CCMR1) == 0x18, "TIM_CCMR1");
_Static_assert(offsetof(tim_t, CCER) == 0x20, "TIM_CCER");
_Static_assert(offsetof(tim_t, CNT) == 0x24, "TIM_CNT");
_Static_assert(offsetof(tim_t, PSC) == 0x28, "TIM_PSC");
_Static_assert(offsetof(tim_t, ARR) == 0x2C, "TIM_ARR");
_Static_assert(offsetof(tim_t, CCR1) == 0x34, "TIM_CCR1");
_Static_assert(offsetof(tim_t, CCR2) == 0x38, "TIM_CCR2");
_Static_assert(offsetof(tim_t, CCR3) == 0x3C, "TIM_CCR3");
_Static_assert(offsetof(tim_t, DMAR) == 0x4C, "TIM_DMAR");
_Static_assert(offsetof(usart_t, DR) == 0x04, "USART_DR");
_Static_assert(offsetof(usart_t, BRR) == 0x08, "USART_BRR");
_Static_assert(offsetof(usart_t, CR1) == 0x0C, "USART_CR1");
_Static_assert(offsetof(usart_t, GTPR) == 0x18, "USART_GTPR");
_Static_assert(offsetof(iwdg_t, SR) == 0x0C, "IWDG_SR");
_Static_assert(offsetof(scb_t, VTOR) == 0x08, "SCB_VTOR");
_Static_assert(offsetof(scb_t, SCR) == 0x10, "SCB_SCR");

#define TIM2   ((tim_t *)0x40000000u)
#define IWDG   ((iwdg_t *)0x40003000u)
#define GPIOA  ((gpio_t *)0x40010800u)
#define GPIOB  ((gpio_t *)0x40010C00u)
#define USART1 ((usart_t *)0x40013800u)
#define RCC    ((rcc_t *)0x40021000u)
#define FLASH  ((flash_t *)0x40022000u)
#define SCB    ((scb_t *)0xE000ED00u)
#define NVIC_ISER ((REG *)0xE000E100u)

/* IRQ numbers (vector table position minus 16). */
#define TIM2_IRQn 28u
#define USART1_IRQn 37u

/* RCC */
#define RCC_CR_HSEON (1u << 16)
#define RCC_CR_HSERDY (1u << 17)
#define RCC_CR_PLLON (1u << 24)
#define RCC_CR_PLLRDY (1u << 25)
#define RCC_CFGR_SW_PLL 2u
#define RCC_CFGR_SWS_MASK (3u << 2)
#define RCC_CFGR_SWS_PLL (2u << 2)
#define RCC_CFGR_PPRE1_DIV2 (4u << 8)
#define RCC_CFGR_PLLSRC_HSE (1u << 16)
#define RCC_CFGR_PLLMUL9 (7u << 18)
#define RCC_APB2ENR_AFIOEN (1u << 0)
#define RCC_APB2ENR_IOPAEN (1u << 2)
#define RCC_APB2ENR_IOPBEN (1u << 3)
#define RCC_APB2ENR_USART1EN (1u << 14)
#define RCC_APB1ENR_TIM2EN (1u << 0)
#define RCC_CSR_IWDGRSTF (1u << 29)
#define RCC_CSR_RMVF (1u << 24)
#define FLASH_ACR_LATENCY2 2u
#define FLASH_ACR_PRFTBE (1u << 4)

/* TIM */
#define TIM_CR1_CEN (1u << 0)
#define TIM_SR_UIF (1u << 0)
#define TIM_SR_CC1IF (1u << 1)
#define TIM_SR_CC2IF (1u << 2)
#define TIM_SR_CC3IF (1u << 3)
#define TIM_DIER_UIE (1u << 0)
#define TIM_DIER_CC1IE (1u << 1)
#define TIM_DIER_CC2IE (1u << 2)
#define TIM_DIER_CC3IE (1u << 3)
#define TIM_EGR_UG (1u << 0)
#define TIM_CCER_CC1E (1u << 0)
#define TIM_CCER_CC2E (1u << 4)
#define TIM_CCER_CC2P (1u << 5)

/* USART */
#define USART_SR_RXNE (1u << 5)
#define USART_SR_TXE (1u << 7)
#define USART_CR1_RE (1u << 2)
#define USART_CR1_TE (1u << 3)
#define USART_CR1_RXNEIE (1u << 5)
#define USART_CR1_TXEIE (1u << 7)
#define USART_CR1_UE (1u << 13)

static inline uint32_t irq_save(void)
{
    uint32_t primask;
    __asm__ volatile("mrs %0, primask\n\tcpsid i" : "=r"(primask) : : "memory");
    return primask;
}

static inline void irq_restore(uint32_t primask)
{
    __asm__ volatile("msr primask, %0" : : "r"(primask) : "memory");
}

#endif /* OF_STM32F103_H */
