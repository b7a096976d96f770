/* Test firmware for the emulator alone (no protocol): triggers the HC-SR04 on D9 every
 * 60 ms, measures ECHO on D8 with Timer1 input capture (2 MHz ticks, overflow counting)
 * and prints "R <n> <trigger_tick> <echo_ticks>\n" at 115200 baud. Every byte received is
 * answered with "E <hex>\n". Sleeps (idle) between events. */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>
#include <stdint.h>
#include <util/delay.h>

#define CYCLE_TICKS 120000UL /* 60 ms at 2 MHz */

static volatile uint16_t ovf;
static volatile uint32_t rise_tick;
static volatile uint32_t fall_tick;
static volatile uint8_t edge_state; /* 0 idle, 1 wait rise, 2 wait fall, 3 done */
static volatile uint8_t rx_buf[16];
static volatile uint8_t rx_head, rx_tail;
static volatile uint8_t tx_buf[128];
static volatile uint8_t tx_head, tx_tail;

ISR(TIMER1_OVF_vect) { ovf++; }

/* Only wakes the CPU for the next trigger time. */
ISR(TIMER1_COMPA_vect) {}

ISR(TIMER1_CAPT_vect)
{
    uint16_t icr = ICR1;
    uint16_t hi = ovf;
    if ((TIFR1 & _BV(TOV1)) && icr < 0x8000)
        hi++;
    uint32_t t = ((uint32_t)hi << 16) | icr;
    if (edge_state == 1) {
        rise_tick = t;
        TCCR1B &= (uint8_t)~_BV(ICES1);
        TIFR1 = _BV(ICF1);
        edge_state = 2;
    } else if (edge_state == 2) {
        fall_tick = t;
        edge_state = 3;
    }
}

ISR(USART_RX_vect)
{
    uint8_t c = UDR0;
    uint8_t n = (uint8_t)((rx_head + 1) & 15);
    if (n != rx_tail) {
        rx_buf[rx_head] = c;
        rx_head = n;
    }
}

ISR(USART_UDRE_vect)
{
    if (tx_head == tx_tail) {
        UCSR0B &= (uint8_t)~_BV(UDRIE0);
        return;
    }
    UDR0 = tx_buf[tx_tail];
    tx_tail = (uint8_t)((tx_tail + 1) & 127);
}

static void putc_(char c)
{
    uint8_t n = (uint8_t)((tx_head + 1) & 127);
    while (n == tx_tail) {
    }
    tx_buf[tx_head] = (uint8_t)c;
    tx_head = n;
    UCSR0B |= _BV(UDRIE0);
}

static void put_u32(uint32_t v)
{
    char d[10];
    uint8_t n = 0;
    do {
        d[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    while (n)
        putc_(d[--n]);
}

static void put_hex(uint8_t v)
{
    const char *h = "0123456789abcdef";
    putc_(h[v >> 4]);
    putc_(h[v & 15]);
}

static uint32_t now_ticks(void)
{
    uint8_t s = SREG;
    cli();
    uint16_t lo = TCNT1;
    uint16_t hi = ovf;
    if ((TIFR1 & _BV(TOV1)) && lo < 0x8000)
        hi++;
    SREG = s;
    return ((uint32_t)hi << 16) | lo;
}

int main(void)
{
    DDRB |= _BV(PB1);
    UBRR0 = 16; /* 115200 with U2X */
    UCSR0A = _BV(U2X0);
    UCSR0B = _BV(RXEN0) | _BV(TXEN0) | _BV(RXCIE0);
    UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
    TCCR1A = 0;
    TCCR1B = _BV(ICNC1) | _BV(CS11);
    TIMSK1 = _BV(ICIE1) | _BV(TOIE1) | _BV(OCIE1A);
    sei();
    const char *hello = "HELLO echo_test\n";
    while (*hello)
        putc_(*hello++);
    uint32_t n = 0;
    uint32_t next = now_ticks() + 2000;
    OCR1A = (uint16_t)next;
    uint32_t trig = 0;
    for (;;) {
        if (edge_state == 0 && (int32_t)(now_ticks() - next) >= 0) {
            next += CYCLE_TICKS;
            OCR1A = (uint16_t)next;
            TCCR1B |= _BV(ICES1);
            TIFR1 = _BV(ICF1);
            edge_state = 1;
            trig = now_ticks();
            PORTB |= _BV(PB1);
            _delay_us(12);
            PORTB &= (uint8_t)~_BV(PB1);
        }
        if (edge_state == 3) {
            uint32_t w = fall_tick - rise_tick;
            edge_state = 0;
            putc_('R');
            putc_(' ');
            put_u32(n++);
            putc_(' ');
            put_u32(trig);
            putc_(' ');
            put_u32(w);
            putc_('\n');
        }
        if (edge_state == 1 || edge_state == 2) {
            /* 60 ms of nothing: give up on this measurement */
            if ((int32_t)(now_ticks() - trig) > 100000L) {
                edge_state = 0;
                putc_('T');
                putc_('\n');
            }
        }
        while (rx_tail != rx_head) {
            uint8_t c = rx_buf[rx_tail];
            rx_tail = (uint8_t)((rx_tail + 1) & 15);
            putc_('E');
            putc_(' ');
            put_hex(c);
            putc_('\n');
        }
        cli();
        if (rx_tail == rx_head && edge_state != 3) {
            sleep_enable();
            sei();
            sleep_cpu();
            sleep_disable();
        }
        sei();
    }
}
