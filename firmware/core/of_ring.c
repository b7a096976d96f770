/* SPSC byte ring; see of_ring.h. */
#include "of_ring.h"

void of_ring_init(of_ring_t *r, volatile uint8_t *buf, uint8_t size)
{
    r->buf = buf;
    r->head = 0;
    r->tail = 0;
    r->mask = (uint8_t)(size - 1u);
}

bool of_ring_put(of_ring_t *r, const uint8_t *data, uint8_t n)
{
    if (n > of_ring_free(r)) {
        return false;
    }
    uint8_t h = r->head;
    for (uint8_t i = 0; i < n; i++) {
        r->buf[(uint8_t)(h + i) & r->mask] = data[i];
    }
    r->head = (uint8_t)(h + n); /* publish after the data */
    return true;
}

bool of_ring_get(of_ring_t *r, uint8_t *byte)
{
    uint8_t t = r->tail;
    if (t == r->head) {
        return false;
    }
    *byte = r->buf[t & r->mask];
    r->tail = (uint8_t)(t + 1u);
    return true;
}
