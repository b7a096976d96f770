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

#endif /* OF_RING_H */
