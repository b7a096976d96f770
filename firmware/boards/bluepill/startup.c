/* Reset handler and vector table for the STM32F103: point VTOR at this image's vector
 * table, copy .data, clear .bss, run main. */
#include <stdint.h>

#include "stm32f103.h"

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;
extern int main(void);

void Reset_Handler(void);
void Default_Handler(void);
void TIM2_IRQHandler(void);
void USART1_IRQHandler(void);

extern void (*const vectors[16 + 43])(void);

void Reset_Handler(void)
{
    /* Before anything can raise an interrupt: the vectors are ours, wherever we were
     * started from. After `stm32flash -g 0x0` (BOOT0 still latched) address 0 shows the
     * ROM bootloader and VTOR is still 0, so the first interrupt would go through the
     * ROM's table. */
    SCB->VTOR = (uint32_t)(uintptr_t)vectors;
    __asm__ volatile("dsb" : : : "memory");
    uint32_t *src = &_sidata;
    for (uint32_t *dst = &_sdata; dst < &_edata;) {
        *dst++ = *src++;
    }
    for (uint32_t *dst = &_sbss; dst < &_ebss;) {
        *dst++ = 0;
    }
    main();
    for (;;) {
    }
}

/* An unexpected interrupt or fault: stop here and let the watchdog reset the chip. */
void Default_Handler(void)
{
    for (;;) {
    }
}

/* Cortex-M3 system vectors, then the F103's 43 interrupts (TIM2 = 28, USART1 = 37). */
#define D Default_Handler
#define D4 D, D, D, D
#define D8 D4, D4

__attribute__((section(".isr_vector"), used))
void (*const vectors[16 + 43])(void) = {
    (void (*)(void))(uintptr_t)&_estack, Reset_Handler,
    D4, D8, D, D,            /* NMI .. SysTick (2..15) */
    D8, D8, D8, D4,          /* IRQ 0..27 */
    TIM2_IRQHandler,         /* IRQ 28 */
    D8,                      /* IRQ 29..36 */
    USART1_IRQHandler,       /* IRQ 37 */
    D4, D,                   /* IRQ 38..42 */
};

_Static_assert(sizeof vectors / sizeof vectors[0] == 16 + 43, "vector table length");
