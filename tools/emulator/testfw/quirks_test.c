/* Probes two simavr 1.6 quirks and prints what the emulated chip did:
 *   "SEI ok" if a pending interrupt is taken after the one instruction following SEI,
 *   "TIFR ok" if writing TIFR1 = _BV(ICF1) keeps a pending TOV1 flag. */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <stdint.h>

static volatile uint8_t hits;

ISR(TIMER1_OVF_vect) { hits++; }

static void put(const char *s)
{
    while (*s) {
        while (!(UCSR0A & _BV(UDRE0))) {
        }
        UDR0 = (uint8_t)*s++;
    }
}

int main(void)
{
    UBRR0 = 16;
    UCSR0A = _BV(U2X0);
    UCSR0B = _BV(TXEN0);
    UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);

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
    put("DONE\n");
    for (;;) {
    }
}
