/* Arduino Uno HAL: Timer1 input capture on ICP1 (D8) for ECHO, TRIG on D9..D12, USART0
 * at 115200 8N1 with interrupt-driven rings, idle sleep, watchdog (interrupt, then reset).
 *
 * Timer1 runs free at 2 MHz (prescaler 8) in normal mode; its overflow interrupt counts
 * wraps (every 32.768 ms) and of_ticks.h extends every 16-bit reading with that count.
 * The firmware never writes TIFR1 (simavr 1.6 clears all Timer1 flags on such a write),
 * never leaves the CPU sleeping with interrupts off, and never relies on the instruction
 * after sei: see firmware/README.md. */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>
#include <avr/wdt.h>

#include "hal.h"
#include "of_ring.h"
#include "of_ticks.h"

#ifndef F_CPU
#error "F_CPU must be set by the Makefile"
#endif

#define US_SHIFT 1u               /* 2 ticks per microsecond */
#define TRIG_TICKS 20u            /* 10 us */
#define TRIG_FIRST_BIT PB1        /* sensor n drives PB(1+n) */
#define ECHO_BIT PB0              /* ICP1 */
#define IDLE_MAX_US 2000UL        /* longest sleep, bounds a wake-up lost to a race */
#define IDLE_MIN_US 40UL          /* closer deadlines are polled, not slept for */
#define BAUD_UBRR 16u             /* 115200 with U2X0 at 16 MHz (2.1% fast, as Arduino) */

enum { ECHO_OFF = 0, ECHO_WAIT_RISE, ECHO_WAIT_FALL, ECHO_DONE };

static volatile uint32_t t1_ovf;   /* Timer1 overflows counted by the ISR */
static volatile uint8_t echo_state;
static volatile uint32_t echo_rise;
static volatile uint32_t echo_fall;

static volatile uint8_t rx_buf[64];
static volatile uint8_t tx_buf[128];
static of_rx_ring_t rx_ring;
static of_ring_t tx_ring;

/* MCUSR as it was at reset; .noinit, since it is saved before RAM is initialised. */
static uint8_t reset_cause __attribute__((section(".noinit")));
/* r2 as the application found it: Optiboot >= 4.6 clears MCUSR before it starts the
 * application and hands the reset cause over in r2. */
static uint8_t boot_r2 __attribute__((section(".noinit")));
/* Left by the watchdog interrupt, read at the next start: the word of a hang that outlives
 * a bootloader which clears MCUSR and passes nothing (Optiboot 4.4, a stock Uno's). A
 * 16-bit magic and its complement, so power-on RAM is unlikely to fake it; .noinit (after
 * .bss, above Optiboot's page buffer at 0x100..0x17F) keeps it across the reset. */
#define WDT_MARK 0x5744u /* "WD" */
volatile uint8_t of_wdt_mark[4] __attribute__((section(".noinit")));
/* Interrupt and system reset mode, 250 ms: the first time-out runs WDT_vect (hardware
 * then clears WDIE), the second resets. 2 x 0.256 s from the last kick, as 0.5 s alone. */
#define WDT_MODE (_BV(WDIE) | _BV(WDE) | _BV(WDP2))

/* The very first code after the reset vector, before anything touches r2; then r2 is
 * cleared, and the Makefile keeps the compiler off it (-ffixed-r2), so a bootloader that
 * does not pass the cause (Optiboot < 4.6, e.g. the 4.4 of Arduino's own hex) hands over
 * 0 after a warm reset, not a stale value that could read as WDRF. */
void save_r2(void) __attribute__((naked, used, section(".init0")));
void save_r2(void)
{
    __asm__ volatile("sts %0, r2\n\tclr r2" : "=m"(boot_r2));
}

/* The watchdog stays on across a watchdog reset: turn it off before main runs. MCUSR is
 * 0 only when a bootloader cleared it (every reset sets one of its flags): then the cause
 * is the one the bootloader passed in r2, else (r2 0: nothing passed) the mark. */
void wdt_init(void) __attribute__((naked, used, section(".init3")));
void wdt_init(void)
{
    reset_cause = MCUSR;
    if (reset_cause == 0u && (boot_r2 & 0xF0u) == 0u) { /* MCUSR's bits 7..4 read 0 */
        reset_cause = boot_r2;
    }
    if (reset_cause == 0u && of_wdt_mark[0] == (uint8_t)WDT_MARK &&
        of_wdt_mark[1] == (uint8_t)(WDT_MARK >> 8) && of_wdt_mark[2] == (uint8_t)~WDT_MARK &&
        of_wdt_mark[3] == (uint8_t)(~WDT_MARK >> 8)) {
        reset_cause = _BV(WDRF);
    }
    of_wdt_mark[0] = 0u;
    MCUSR = 0;
    wdt_disable();
}

/* The main loop missed its kick by 256 ms: leave the mark. It touches no flag, so no
 * SREG save; hardware has cleared WDIE, and the next time-out resets unless a late kick
 * comes first (then it clears the mark again). */
ISR(WDT_vect, ISR_NAKED)
{
    __asm__ volatile("push r24\n\t"
                     "ldi r24, %[b0]\n\tsts %[m0], r24\n\t"
                     "ldi r24, %[b1]\n\tsts %[m1], r24\n\t"
                     "ldi r24, %[b2]\n\tsts %[m2], r24\n\t"
                     "ldi r24, %[b3]\n\tsts %[m3], r24\n\t"
                     "pop r24\n\t"
                     "reti"
                     :
                     : [m0] "i"(&of_wdt_mark[0]), [m1] "i"(&of_wdt_mark[1]),
                       [m2] "i"(&of_wdt_mark[2]), [m3] "i"(&of_wdt_mark[3]), [b0] "M"(WDT_MARK & 0xFFu), [b1] "M"(WDT_MARK >> 8),
                       [b2] "M"(~WDT_MARK & 0xFFu), [b3] "M"((~WDT_MARK >> 8) & 0xFFu));
}

ISR(TIMER1_OVF_vect)
{
    t1_ovf++;
}

/* Wake-up only: hal_idle_until() aims OCR1A at the next deadline. */
EMPTY_INTERRUPT(TIMER1_COMPA_vect);

ISR(TIMER1_CAPT_vect)
{
    uint16_t icr = ICR1;
    bool ovf_pending = (TIFR1 & _BV(TOV1)) != 0;
    uint32_t t = of_ticks_extend(t1_ovf, icr, ovf_pending);
    bool high = (PINB & _BV(ECHO_BIT)) != 0;
    /* A capture whose pin level disagrees with the edge is the edge switch itself
     * (the datasheet's reason to clear ICF1, which we must not write): ignore it. */
    if (echo_state == ECHO_WAIT_RISE && high) {
        echo_rise = t;
        TCCR1B &= (uint8_t)~_BV(ICES1); /* now the falling edge */
        echo_state = ECHO_WAIT_FALL;
    } else if (echo_state == ECHO_WAIT_FALL && !high) {
        echo_fall = t;
        echo_state = ECHO_DONE;
    }
}

/* Callers hold interrupts off (or run in an ISR). TCNT1 is read before TOV1 so an
 * overflow between the two reads is attributed correctly. */
static inline void timer_read(uint16_t *count, bool *pending, uint32_t *ovf)
{
    *count = TCNT1;
    *pending = (TIFR1 & _BV(TOV1)) != 0;
    *ovf = t1_ovf;
}

/* The timer now, as microseconds (shift 1) or as 32-bit ticks (shift 0). */
static uint32_t timer_now(uint8_t shift)
{
    uint16_t c;
    bool p;
    uint32_t o;
    uint8_t sreg = SREG;
    cli();
    timer_read(&c, &p, &o);
    SREG = sreg;
    return of_ticks_micros(o, c, p, shift);
}

ISR(USART_RX_vect)
{
    uint8_t b = UDR0;
    /* A delimiter carries its arrival time (of_rx_put: a full ring drops a byte, and
     * keeps a delimiter for the next byte that finds room). */
    of_rx_put(&rx_ring, b, b == 0u ? timer_now(US_SHIFT) : 0u);
}

ISR(USART_UDRE_vect)
{
    uint8_t b;
    if (of_ring_get(&tx_ring, &b)) {
        UDR0 = b;
    } else {
        UCSR0B &= (uint8_t)~_BV(UDRIE0);
    }
}

void hal_init(void)
{
    of_rx_init(&rx_ring, rx_buf, sizeof rx_buf);
    of_ring_init(&tx_ring, tx_buf, sizeof tx_buf);

    /* TRIG pins low outputs; ECHO (PB0) input without pull-up: the sensor drives it. */
    PORTB &= (uint8_t)~(0x0Fu << TRIG_FIRST_BIT | _BV(ECHO_BIT));
    DDRB |= (uint8_t)(0x0Fu << TRIG_FIRST_BIT);
    DDRB &= (uint8_t)~_BV(ECHO_BIT);

    /* Timer1: normal mode, noise canceller, rising edge, clk/8. */
    TCCR1A = 0;
    TCNT1 = 0;
    OCR1A = 0xFFFFu;
    TIMSK1 = _BV(ICIE1) | _BV(TOIE1) | _BV(OCIE1A);
    TCCR1B = _BV(ICNC1) | _BV(ICES1) | _BV(CS11);

    UBRR0 = BAUD_UBRR;
    UCSR0A = _BV(U2X0);
    UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
    UCSR0B = _BV(RXCIE0) | _BV(RXEN0) | _BV(TXEN0);

    set_sleep_mode(SLEEP_MODE_IDLE);
    wdt_enable(WDTO_250MS);
    WDTCSR = WDT_MODE; /* WDE and the prescaler unchanged: no timed sequence */
    sei();
}

uint32_t hal_cpu_hz(void)
{
    return F_CPU;
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
    uint8_t bit = (uint8_t)(1u << (TRIG_FIRST_BIT + (sensor & 3u)));
    uint16_t c;
    bool p;
    uint32_t o;
    uint8_t sreg = SREG;
    cli();
    echo_state = ECHO_WAIT_RISE;
    TCCR1B |= _BV(ICES1);
    PORTB |= bit;
    timer_read(&c, &p, &o);
    /* The one busy wait: 10 us on the free-running timer, interrupts held off so the
     * pulse is not stretched and the stamp above is the edge's. */
    while ((uint16_t)(TCNT1 - c) < TRIG_TICKS) {
    }
    PORTB &= (uint8_t)~bit;
    SREG = sreg;
    return of_ticks_micros(o, c, p, US_SHIFT);
}

uint8_t hal_echo_edges(uint32_t *rise_ticks, uint32_t *fall_ticks)
{
    uint8_t sreg = SREG;
    cli();
    uint8_t st = echo_state;
    *rise_ticks = echo_rise;
    *fall_ticks = echo_fall;
    SREG = sreg;
    return st == ECHO_DONE ? 2u : (st == ECHO_WAIT_FALL ? 1u : 0u);
}

void hal_echo_disarm(void)
{
    echo_state = ECHO_OFF;
}

bool hal_echo_is_high(void)
{
    return (PINB & _BV(ECHO_BIT)) != 0;
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
    uint8_t sreg = SREG;
    cli();
    UCSR0B |= _BV(UDRIE0);
    SREG = sreg;
    return true;
}

void hal_idle_until(uint32_t wake_us)
{
    uint32_t now = hal_micros();
    int32_t wait = (int32_t)(wake_us - now);
    if (wait < (int32_t)IDLE_MIN_US) {
        return;
    }
    if (wait > (int32_t)IDLE_MAX_US) {
        wait = (int32_t)IDLE_MAX_US;
    }
    uint8_t sreg = SREG;
    cli();
    OCR1A = (uint16_t)(TCNT1 + (uint16_t)((uint32_t)wait << US_SHIFT));
    SREG = sreg;
    if (of_ring_count(&rx_ring.ring) != 0u) {
        return;
    }
    /* Interrupts are on: if one slips in between the check and SLEEP, the compare
     * match above still ends the nap within IDLE_MAX_US. */
    sleep_enable();
    sleep_cpu();
    sleep_disable();
}

bool hal_reset_by_watchdog(void)
{
    return (reset_cause & _BV(WDRF)) != 0;
}

/* A kick that finds WDIE cleared follows a late loop (the interrupt ran, the reset had not
 * come yet): the mark goes, the interrupt is armed again. */
void hal_watchdog_kick(void)
{
    wdt_reset();
    if ((WDTCSR & _BV(WDIE)) == 0u) {
        of_wdt_mark[0] = 0u;
        WDTCSR = WDT_MODE;
    }
}
