/* Blue pill HAL: TIM2 at 8 MHz with CH1 capturing ECHO's rise and CH2 its fall, both from
 * TI1 on PA0; TRIG on PB12..PB15; USART1 (PA9 TX, PA10 RX) at 115200 8N1 with interrupt
 * rings; WFI idle; the independent watchdog. Every wait on a hardware flag is bounded.
 *
 * TIM2 is 16 bits on the F103: its update interrupt counts wraps (every 8.192 ms) and
 * of_ticks.h extends readings exactly as on the Uno. Its status bits are cleared by
 * writing 0, so clearing one flag never disturbs another. */
#include "hal.h"
#include "of_ring.h"
#include "of_ticks.h"
#include "stm32f103.h"

#define HSE_HZ 8000000UL
#define HSI_HZ 8000000UL
#define US_SHIFT 3u             /* 8 ticks per microsecond */
#define TRIG_TICKS 80u          /* 10 us */
#define TRIG_FIRST_PIN 12u      /* sensor n drives PB(12+n) */
#define ECHO_PIN 0u             /* PA0 = TIM2_CH1 */
#define CLOCK_SPINS 200000UL    /* bound on each clock-ready wait (some ms) */
#define PULSE_SPINS 4000UL      /* bound on the 10 us wait should TIM2 not count */
#define IDLE_MAX_US 2000UL
#define IDLE_MIN_US 20UL
#define BAUD 115200UL
#define IC_FILTER 3u            /* 8 samples at the timer clock: the noise filter */

enum { ECHO_OFF = 0, ECHO_WAIT_RISE, ECHO_WAIT_FALL, ECHO_DONE };

static volatile uint32_t tim2_ovf;
static volatile uint8_t echo_state;
static volatile uint32_t echo_rise;
static volatile uint32_t echo_fall;
static uint32_t cpu_hz = HSI_HZ;
static bool reset_by_watchdog;

static volatile uint8_t rx_buf[128];
static volatile uint8_t tx_buf[128];
static of_rx_ring_t rx_ring;
static of_ring_t tx_ring;

/* 72 MHz from HSE x9 (APB1 36 MHz, TIM2 72 MHz, APB2 72 MHz). If the crystal or the PLL
 * does not come up in time, stay on the 8 MHz HSI: slower, but everything still works
 * because the prescaler and baud rate follow the clock actually running. */
static void clock_init(void)
{
    RCC->CR |= RCC_CR_HSEON;
    uint32_t n = 0;
    while (!(RCC->CR & RCC_CR_HSERDY) && ++n < CLOCK_SPINS) {
    }
    if (!(RCC->CR & RCC_CR_HSERDY)) {
        return;
    }
    FLASH->ACR = FLASH_ACR_PRFTBE | FLASH_ACR_LATENCY2;
    RCC->CFGR = RCC_CFGR_PLLSRC_HSE | RCC_CFGR_PLLMUL9 | RCC_CFGR_PPRE1_DIV2;
    RCC->CR |= RCC_CR_PLLON;
    n = 0;
    while (!(RCC->CR & RCC_CR_PLLRDY) && ++n < CLOCK_SPINS) {
    }
    if (!(RCC->CR & RCC_CR_PLLRDY)) {
        return;
    }
    RCC->CFGR |= RCC_CFGR_SW_PLL;
    n = 0;
    while ((RCC->CFGR & RCC_CFGR_SWS_MASK) != RCC_CFGR_SWS_PLL && ++n < CLOCK_SPINS) {
    }
    if ((RCC->CFGR & RCC_CFGR_SWS_MASK) == RCC_CFGR_SWS_PLL) {
        cpu_hz = HSE_HZ * 9u;
    }
}

/* Sets the 4-bit mode/config field of one pin. */
static void pin_mode(gpio_t *port, uint32_t pin, uint32_t mode)
{
    volatile uint32_t *cr = pin < 8u ? &port->CRL : &port->CRH;
    uint32_t shift = (pin & 7u) * 4u;
    *cr = (*cr & ~(0xFu << shift)) | (mode << shift);
}

void TIM2_IRQHandler(void)
{
    uint32_t sr = TIM2->SR;
    uint16_t rise = 0;
    uint16_t fall = 0;
    if (sr & TIM_SR_CC1IF) {
        rise = (uint16_t)TIM2->CCR1; /* reading clears CC1IF */
    }
    if (sr & TIM_SR_CC2IF) {
        fall = (uint16_t)TIM2->CCR2;
    }
    /* The update flag read after the captures tells which side of a wrap they fell. */
    bool wrapped = (TIM2->SR & TIM_SR_UIF) != 0;
    uint32_t ovf = tim2_ovf;
    if ((sr & TIM_SR_CC1IF) && echo_state == ECHO_WAIT_RISE) {
        echo_rise = of_ticks_extend(ovf, rise, wrapped);
        echo_state = ECHO_WAIT_FALL;
    }
    if ((sr & TIM_SR_CC2IF) && echo_state == ECHO_WAIT_FALL) {
        echo_fall = of_ticks_extend(ovf, fall, wrapped);
        echo_state = ECHO_DONE;
    }
    if (wrapped) {
        tim2_ovf = ovf + 1u;
        TIM2->SR = ~TIM_SR_UIF;
    }
    if (sr & TIM_SR_CC3IF) {
        TIM2->SR = ~TIM_SR_CC3IF; /* wake-up compare: nothing else to do */
    }
    /* Over-capture flags (an edge while the previous one was unread) are of no use. */
    TIM2->SR = ~((1u << 9) | (1u << 10));
}

void USART1_IRQHandler(void)
{
    uint32_t sr = USART1->SR;
    if (sr & USART_SR_RXNE) {
        uint8_t b = (uint8_t)USART1->DR; /* also clears an overrun flag */
        /* A delimiter carries its arrival time (of_rx_put: a full ring drops a byte, and
         * keeps a delimiter for the next byte that finds room). */
        of_rx_put(&rx_ring, b, b == 0u ? hal_micros() : 0u);
    }
    if ((sr & USART_SR_TXE) && (USART1->CR1 & USART_CR1_TXEIE)) {
        uint8_t b;
        if (of_ring_get(&tx_ring, &b)) {
            USART1->DR = b;
        } else {
            USART1->CR1 &= ~USART_CR1_TXEIE;
        }
    }
}

void hal_init(void)
{
    of_rx_init(&rx_ring, rx_buf, sizeof rx_buf);
    of_ring_init(&tx_ring, tx_buf, sizeof tx_buf);
    reset_by_watchdog = (RCC->CSR & RCC_CSR_IWDGRSTF) != 0;
    RCC->CSR |= RCC_CSR_RMVF; /* clear the reset flags for next time */
    clock_init();
    uint32_t apb1_hz = cpu_hz == HSI_HZ ? cpu_hz : cpu_hz / 2u;
    uint32_t tim2_hz = apb1_hz == cpu_hz ? apb1_hz : apb1_hz * 2u; /* x2 when APB1 divides */

    RCC->APB2ENR |= RCC_APB2ENR_IOPAEN | RCC_APB2ENR_IOPBEN | RCC_APB2ENR_AFIOEN
        | RCC_APB2ENR_USART1EN;
    RCC->APB1ENR |= RCC_APB1ENR_TIM2EN;

    /* PB12..15 push-pull outputs (2 MHz), low. PA0 floating input. PA9 AF push-pull,
     * PA10 input with pull-up. */
    GPIOB->BRR = 0xFu << TRIG_FIRST_PIN;
    for (uint32_t i = 0; i < HAL_SENSOR_COUNT; i++) {
        pin_mode(GPIOB, TRIG_FIRST_PIN + i, 0x2u);
    }
    pin_mode(GPIOA, ECHO_PIN, 0x4u);
    pin_mode(GPIOA, 9u, 0xBu);
    pin_mode(GPIOA, 10u, 0x8u);
    GPIOA->BSRR = 1u << 10;

    /* TIM2: free-running 16-bit at 8 MHz. CH1 = TI1 rising, CH2 = TI1 falling. */
    TIM2->PSC = tim2_hz / HAL_TIMER_HZ - 1u;
    TIM2->ARR = 0xFFFFu;
    TIM2->CCMR1 = (1u << 0) | (IC_FILTER << 4) | (2u << 8) | (IC_FILTER << 12);
    TIM2->CCER = TIM_CCER_CC1E | TIM_CCER_CC2E | TIM_CCER_CC2P;
    TIM2->EGR = TIM_EGR_UG; /* load the prescaler */
    TIM2->SR = 0;
    TIM2->DIER = TIM_DIER_UIE | TIM_DIER_CC1IE | TIM_DIER_CC2IE | TIM_DIER_CC3IE;
    TIM2->CR1 = TIM_CR1_CEN;

    USART1->BRR = (cpu_hz + BAUD / 2u) / BAUD; /* APB2 runs at the CPU clock */
    USART1->CR1 = USART_CR1_UE | USART_CR1_TE | USART_CR1_RE | USART_CR1_RXNEIE;

    /* Watchdog: LSI 40 kHz / 64, reload 312: about 0.5 s. */
    IWDG->KR = 0x5555u;
    IWDG->PR = 4u;
    IWDG->RLR = 312u;
    IWDG->KR = 0xCCCCu;

    NVIC_ISER[0] = 1u << TIM2_IRQn;
    NVIC_ISER[1] = 1u << (USART1_IRQn - 32u);
    __asm__ volatile("cpsie i" : : : "memory");
}

uint32_t hal_cpu_hz(void)
{
    return cpu_hz;
}

/* The timer now, as microseconds (shift 3) or as 32-bit ticks (shift 0). */
static uint32_t timer_now(uint8_t shift)
{
    uint32_t m = irq_save();
    uint16_t c = (uint16_t)TIM2->CNT;
    bool p = (TIM2->SR & TIM_SR_UIF) != 0;
    uint32_t o = tim2_ovf;
    irq_restore(m);
    return of_ticks_micros(o, c, p, shift);
}

uint32_t hal_micros(void)
{
    return timer_now(US_SHIFT);
}

uint32_t hal_ticks(void)
{
    return timer_now(0);
}

uint32_t hal_trigger(uint8_t sensor)
{
    uint32_t bit = 1u << (TRIG_FIRST_PIN + (sensor & 3u));
    uint32_t m = irq_save();
    /* Drop edges captured before this measurement (reading a capture clears its flag). */
    (void)TIM2->CCR1;
    (void)TIM2->CCR2;
    echo_state = ECHO_WAIT_RISE;
    GPIOB->BSRR = bit;
    uint16_t c = (uint16_t)TIM2->CNT;
    bool p = (TIM2->SR & TIM_SR_UIF) != 0;
    uint32_t o = tim2_ovf;
    uint32_t n = 0;
    while ((uint16_t)((uint16_t)TIM2->CNT - c) < TRIG_TICKS && ++n < PULSE_SPINS) {
    }
    GPIOB->BRR = bit;
    irq_restore(m);
    return of_ticks_micros(o, c, p, US_SHIFT);
}

uint8_t hal_echo_edges(uint32_t *rise_ticks, uint32_t *fall_ticks)
{
    uint32_t m = irq_save();
    uint8_t st = echo_state;
    *rise_ticks = echo_rise;
    *fall_ticks = echo_fall;
    irq_restore(m);
    return st == ECHO_DONE ? 2u : (st == ECHO_WAIT_FALL ? 1u : 0u);
}

void hal_echo_disarm(void)
{
    echo_state = ECHO_OFF;
}

bool hal_echo_is_high(void)
{
    return (GPIOA->IDR & (1u << ECHO_PIN)) != 0;
}

bool hal_uart_read(uint8_t *byte, uint32_t *stamp_us)
{
    return of_rx_get(&rx_ring, byte, stamp_us);
}

bool hal_uart_write(const uint8_t *data, uint8_t n)
{
    if (!of_ring_put(&tx_ring, data, n)) {
        return false;
    }
    uint32_t m = irq_save();
    USART1->CR1 |= USART_CR1_TXEIE;
    irq_restore(m);
    return true;
}

void hal_idle_until(uint32_t wake_us)
{
    int32_t wait = (int32_t)(wake_us - hal_micros());
    if (wait < (int32_t)IDLE_MIN_US) {
        return;
    }
    if (wait > (int32_t)IDLE_MAX_US) {
        wait = (int32_t)IDLE_MAX_US;
    }
    /* With interrupts masked, WFI still wakes on a pending one: no lost wake-up. */
    uint32_t m = irq_save();
    /* Hand the UART what it can take right now (one or two bytes on silicon, where the
     * TXE interrupt does the rest; all of it under QEMU, which models no TXE interrupt). */
    uint8_t b;
    while ((USART1->SR & USART_SR_TXE) && of_ring_get(&tx_ring, &b)) {
        USART1->DR = b;
    }
    TIM2->CCR3 = (uint16_t)(TIM2->CNT + ((uint32_t)wait << US_SHIFT));
    if (of_ring_count(&rx_ring.ring) == 0u) {
        __asm__ volatile("wfi" : : : "memory");
    }
    irq_restore(m);
}

bool hal_reset_by_watchdog(void)
{
    return reset_by_watchdog;
}

void hal_watchdog_kick(void)
{
    IWDG->KR = 0xAAAAu;
}
