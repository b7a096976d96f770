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

void of_rx_init(of_rx_ring_t *rx, volatile uint8_t *buf, uint8_t size)
{
    of_ring_init(&rx->ring, buf, size);
    rx->delim_lost = 0;
    rx->delim_us = 0;
}

static bool put_delimiter(of_ring_t *r, uint32_t us)
{
    uint8_t rec[5] = {0, (uint8_t)us, (uint8_t)(us >> 8), (uint8_t)(us >> 16),
                      (uint8_t)(us >> 24)};
    return of_ring_put(r, rec, sizeof rec);
}

void of_rx_put(of_rx_ring_t *rx, uint8_t byte, uint32_t stamp_us)
{
    if (rx->delim_lost) {
        if (!put_delimiter(&rx->ring, rx->delim_us)) {
            /* Still full: this byte is lost too; a 0x00 is newer, keep its stamp. */
            if (byte == 0u) {
                rx->delim_us = stamp_us;
            }
            return;
        }
        rx->delim_lost = 0;
    }
    if (byte == 0u) {
        if (!put_delimiter(&rx->ring, stamp_us)) {
            rx->delim_lost = 1;
            rx->delim_us = stamp_us;
        }
    } else {
        (void)of_ring_put(&rx->ring, &byte, 1); /* full: dropped; the frame's CRC will tell */
    }
}

bool of_rx_get(of_rx_ring_t *rx, uint8_t *byte, uint32_t *stamp_us)
{
    if (!of_ring_get(&rx->ring, byte)) {
        return false;
    }
    if (*byte == 0u) {
        uint8_t s[4] = {0, 0, 0, 0};
        for (uint8_t i = 0; i < 4u; i++) {
            (void)of_ring_get(&rx->ring, &s[i]); /* written with the 0x00, always there */
        }
        *stamp_us = (uint32_t)s[0] | (uint32_t)s[1] << 8 | (uint32_t)s[2] << 16
            | (uint32_t)s[3] << 24;
    }
    return true;
}
