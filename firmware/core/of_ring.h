/* Single-producer single-consumer byte ring shared between an interrupt and the main
 * loop. Free-running uint8_t indices, so a size of 2..128 that is a power of two needs no
 * lock: each side writes only its own index, after the data. */
#ifndef OF_RING_H
#define OF_RING_H

#include <stdbool.h>
#include <stdint.h>

typedef struct {
    volatile uint8_t *buf;
    volatile uint8_t head; /* written by the producer only */
    volatile uint8_t tail; /* written by the consumer only */
    uint8_t mask;          /* size - 1 */
} of_ring_t;

/* size: a power of two from 2 to 128. */
void of_ring_init(of_ring_t *r, volatile uint8_t *buf, uint8_t size);

static inline uint8_t of_ring_count(const of_ring_t *r)
{
    return (uint8_t)(r->head - r->tail);
}

static inline uint8_t of_ring_free(const of_ring_t *r)
{
    return (uint8_t)(r->mask + 1u - of_ring_count(r));
}

/* Producer: appends all n bytes or none; false if they do not fit. */
bool of_ring_put(of_ring_t *r, const uint8_t *data, uint8_t n);

/* Consumer: takes the oldest byte; false if empty. */
bool of_ring_get(of_ring_t *r, uint8_t *byte);

/* The receive side of a UART: a ring the receive interrupt fills and the main loop reads.
 * A frame delimiter (0x00) is stored with its arrival time: 0x00 then 4 stamp bytes
 * (little-endian microseconds), written together or not at all. */
typedef struct {
    of_ring_t ring;
    volatile uint8_t delim_lost; /* a 0x00 found no room; stored ahead of the next byte */
    uint32_t delim_us;           /* its arrival time */
} of_rx_ring_t;

void of_rx_init(of_rx_ring_t *rx, volatile uint8_t *buf, uint8_t size);

/* Producer (the receive interrupt): stores one received byte; stamp_us (the clock when it
 * arrived) is only used for a 0x00. A byte that finds the ring full is dropped: its frame
 * fails its CRC. A 0x00 that finds no room is not forgotten: it goes in, with its own
 * stamp, ahead of the next byte that finds room, so the frame cut short still ends there
 * and the next command is not swallowed with it (a flood from the host loses frames, never
 * the ones after it). */
void of_rx_put(of_rx_ring_t *rx, uint8_t byte, uint32_t stamp_us);

/* Consumer: the oldest byte (false if none); for a 0x00, *stamp_us gets its stamp. */
bool of_rx_get(of_rx_ring_t *rx, uint8_t *byte, uint32_t *stamp_us);

#endif /* OF_RING_H */
