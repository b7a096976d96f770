/* USART0 <-> pseudo-terminal, paced at the line rate, with optional fault injection. */
#ifndef OF_EMU_UART_BRIDGE_H
#define OF_EMU_UART_BRIDGE_H

#include <stdint.h>

#include "sim_avr.h"
#include "avr_uart.h"

#include "rng.h"

#define BRIDGE_TX_SIZE 65536u   /* bytes queued towards the host; power of two */
#define BRIDGE_RX_SIZE 4096u    /* bytes queued towards the MCU; power of two */

enum { FAULT_TX = 1, FAULT_RX = 2 };

typedef struct {
    double drop_p;      /* a byte vanishes */
    double corrupt_p;   /* one bit of a byte flips */
    double insert_p;    /* a random byte appears after a byte */
    int dirs;           /* FAULT_TX | FAULT_RX */
} uart_faults_t;

typedef struct {
    uint64_t tx_bytes;          /* bytes the firmware wrote to UDR0 */
    uint64_t tx_written;        /* bytes written to the pty */
    uint64_t tx_no_client;      /* discarded: nobody had the port open */
    uint64_t tx_overflow;       /* discarded: host not reading, queue full */
    uint64_t rx_bytes;          /* bytes read from the pty */
    uint64_t rx_fed;            /* bytes given to the USART */
    uint64_t rx_overruns;       /* lost as the real 2-byte receive buffer would lose them */
    uint64_t rx_overflow;       /* host wrote faster than we queue */
    uint64_t dropped, corrupted, inserted;
    uint64_t client_opens;
} bridge_stats_t;

typedef struct {
    avr_t *avr;
    avr_uart_t *uart;
    avr_irq_t *in_irq;
    rng_t *rng;
    uart_faults_t faults;
    int model_rx_overrun;
    int master;
    char path[256];
    int client;             /* a client has the slave side open */
    uint8_t tx_buf[BRIDGE_TX_SIZE];
    avr_cycle_count_t tx_due[BRIDGE_TX_SIZE];
    uint32_t tx_head, tx_tail;
    uint8_t rx_buf[BRIDGE_RX_SIZE];
    uint32_t rx_head, rx_tail;
    int rx_scheduled;
    bridge_stats_t st;
} uart_bridge_t;

/* Create the pty; returns -1 with errno set. */
int bridge_open_pty(uart_bridge_t *b);
/* Connect to the MCU's USART0; returns -1 if it has none. */
int bridge_attach(uart_bridge_t *b, avr_t *avr, rng_t *rng, const uart_faults_t *f,
                  int model_rx_overrun);
/* Poll the pty: deliver due TX bytes, take RX bytes. Returns 1 if a client just opened. */
int bridge_service(uart_bridge_t *b);
/* The same; deliver_tx = 0 only takes host bytes (used while simulated time is ahead of
 * the wall clock, so that no byte reaches the host before its time). */
int bridge_service_ex(uart_bridge_t *b, int deliver_tx);
/* Whether a client has the pty open right now. */
int bridge_client_present(uart_bridge_t *b);
/* At exit: send what is queued and wait (up to timeout_s) until the client has read it.
 * Advances the cycle counter: the simulation must be over. */
void bridge_drain(uart_bridge_t *b, double timeout_s);
/* Forget queued bytes in both directions (MCU reset). */
void bridge_flush(uart_bridge_t *b);
/* Cycles per byte at the configured baud: 11 bit times for 8N1 (simavr counts a parity
 * bit in every frame, and times UDRE by it, so we pace by the same figure). */
avr_cycle_count_t bridge_cycles_per_byte(const uart_bridge_t *b);

#endif
