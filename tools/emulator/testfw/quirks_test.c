/* Probes two simavr 1.6 quirks and prints what the emulated chip did:
 *   "SEI ok" if a pending interrupt is taken after the one instruction following SEI,
 *   "TIFR ok" if writing TIFR1 = _BV(ICF1) keeps a pending TOV1 flag,
 *   "PCIFR ok" / "EIFR ok" if writing one to a pin-change / external interrupt flag
 *   cancels the pending interrupt,
 *   "INT ok" if INT1, its pin low while in (default) low-level mode, stays quiet once
 *   EICRA selects the rising edge,
 *   "WDT wdr ok" then (after the reset) "WDT reset" if the watchdog in interrupt and
 *   system reset mode, its interrupt pending with interrupts off, resets at the next
 *   time-out and not before (WDR restarts the count); "WDT bad" if it never resets. */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/wdt.h>
#include <stdint.h>

static volatile uint8_t hits;
static volatile uint8_t pc_hits;
static volatile uint8_t int0_hits;
static volatile uint16_t int1_hits;

ISR(TIMER1_OVF_vect) { hits++; }
ISR(PCINT0_vect) { pc_hits++; }
ISR(INT0_vect) { int0_hits++; }
ISR(INT1_vect) { int1_hits++; }

static void put(const char *s)
{
    while (*s) {
        while (!(UCSR0A & _BV(UDRE0))) {
        }
        UDR0 = (uint8_t)*s++;
    }
}

/* n Timer1 overflows at clk/1 (4.1 ms each), interrupts off. */
static void wait_ovf(uint8_t n)
{
    while (n--) {
        TIFR1 = _BV(TOV1);
        while (!(TIFR1 & _BV(TOV1))) {
        }
    }
}

int main(void)
{
    uint8_t mcusr = MCUSR;
    MCUSR = 0;
    wdt_disable();
    UBRR0 = 16;
    UCSR0A = _BV(U2X0);
    UCSR0B = _BV(TXEN0);
    UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
    if (mcusr & _BV(WDRF)) { /* the end of the WDT probe below */
        put("WDT reset\n");
        put("DONE\n");
        for (;;) {
        }
    }

    /* TIFR: wait for an overflow flag with interrupts off, then clear only ICF1. */
    TCCR1A = 0;
    TCCR1B = _BV(CS10);
    TIFR1 = _BV(TOV1);
    while (!(TIFR1 & _BV(TOV1))) {
    }
    TIFR1 = _BV(ICF1);
    put((TIFR1 & _BV(TOV1)) ? "TIFR ok\n" : "TIFR bad\n");
    TIFR1 = _BV(TOV1);

    /* SEI: an overflow interrupt is pending; `sei; nop; cli` must take it after the nop. */
    TIMSK1 = _BV(TOIE1);
    while (!(TIFR1 & _BV(TOV1))) {
    }
    hits = 0;
    __asm__ __volatile__("sei\n\tnop\n\tcli\n\t" ::: "memory");
    put(hits ? "SEI ok\n" : "SEI bad\n");

    /* PCIFR: a pin change on PB5 (an output: the pin follows PORTB) makes PCIF0 pending;
     * writing one to PCIF0 must cancel it. */
    DDRB |= _BV(PB5);
    PCMSK0 = _BV(PCINT5);
    PCICR = _BV(PCIE0);
    PORTB |= _BV(PB5);
    PCIFR = _BV(PCIF0);
    pc_hits = 0;
    __asm__ __volatile__("sei\n\tnop\n\tnop\n\tcli\n\t" ::: "memory");
    put(pc_hits ? "PCIFR bad\n" : "PCIFR ok\n");

    /* EIFR: a rising edge on INT0 (PD2, an output) makes INTF0 pending; clear it. */
    DDRD |= _BV(PD2);
    EICRA = _BV(ISC01) | _BV(ISC00);
    EIFR = _BV(INTF0);
    EIMSK = _BV(INT0);
    PORTD |= _BV(PD2);
    EIFR = _BV(INTF0);
    int0_hits = 0;
    __asm__ __volatile__("sei\n\tnop\n\tnop\n\tcli\n\t" ::: "memory");
    put(int0_hits ? "EIFR bad\n" : "EIFR ok\n");

    /* INT1 on PD3 (an output) goes low while INT1 is in low-level mode, then EICRA selects
     * the rising edge: no edge follows, so no interrupt may fire. */
    DDRD |= _BV(PD3);
    PORTD |= _BV(PD3);
    PORTD &= (uint8_t)~_BV(PD3);
    EICRA |= _BV(ISC11) | _BV(ISC10);
    EIMSK |= _BV(INT1);
    int1_hits = 0;
    sei();
    for (volatile uint8_t i = 0; i < 100; i++) {
    }
    cli();
    put(int1_hits ? "INT bad\n" : "INT ok\n");

    /* WDT: interrupt and reset mode at 16 ms, interrupts off. After the first time-out
     * (WDIF, the interrupt pending), two WDRs 12 ms apart keep the chip alive; then no
     * more: it must reset 16 ms later (into the MCUSR branch above). */
    EIMSK = 0;
    TIMSK1 = 0;
    wdt_enable(WDTO_15MS);
    WDTCSR = _BV(WDIE) | _BV(WDE);
    while (!(WDTCSR & _BV(WDIF))) {
    }
    wdt_reset();
    wait_ovf(3);
    wdt_reset();
    wait_ovf(3);
    put("WDT wdr ok\n");
    wait_ovf(25);
    put("WDT bad\n");
    put("DONE\n");
    for (;;) {
    }
}
