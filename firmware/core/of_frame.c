/* Framing of the obstacle-fusion wire protocol; see of_frame.h and protocol/README.md. */
#include "of_frame.h"

uint16_t of_crc16_update(uint16_t crc, uint8_t byte)
{
    crc ^= (uint16_t)((uint16_t)byte << 8);
    for (uint8_t bit = 0; bit < 8u; bit++) {
        crc = (crc & 0x8000u) ? (uint16_t)((crc << 1) ^ 0x1021u) : (uint16_t)(crc << 1);
    }
    return crc;
}

size_t of_frame_encode(uint8_t *out, size_t cap, uint8_t msg_id, uint8_t seq,
                       const uint8_t *payload, size_t len)
{
    int extra = of_crc_extra(msg_id);
    if (extra < 0 || len > OF_MAX_PAYLOAD || cap < len + 6u) {
        return 0;
    }
    /* The body is msg_id, seq, payload, crc (big-endian, so the CRC over the whole body
     * of a good frame is zero). It is COBS-encoded on the fly: code_at marks the byte
     * that will hold the distance to the next zero. */
    uint16_t crc = of_crc16_update(OF_CRC_INIT, (uint8_t)extra);
    size_t body_len = len + 4u;
    size_t code_at = 0;
    size_t w = 1;
    uint8_t code = 1;
    for (size_t i = 0; i < body_len; i++) {
        uint8_t b;
        if (i == 0) {
            b = msg_id;
        } else if (i == 1) {
            b = seq;
        } else if (i < len + 2u) {
            b = payload[i - 2u];
        } else if (i == len + 2u) {
            b = (uint8_t)(crc >> 8);
        } else {
            b = (uint8_t)crc;
        }
        if (i < len + 2u) {
            crc = of_crc16_update(crc, b);
        }
        if (b == 0) {
            out[code_at] = code;
            code_at = w++;
            code = 1;
        } else {
            out[w++] = b;
            code++;
            /* Bodies are at most OF_MAX_BODY (< 254) bytes: no 0xFF block split needed. */
        }
    }
    out[code_at] = code;
    out[w++] = 0x00;
    return w;
}

void of_frame_decoder_init(of_frame_decoder_t *d)
{
    d->len = 0;
    d->overflow = 0;
}

/* Decodes the COBS bytes of d->buf in place into out; false if they are not a frame. */
static bool decode_frame(const of_frame_decoder_t *d, of_frame_t *out)
{
    uint8_t body[OF_MAX_BODY];
    uint8_t n = 0;
    uint8_t i = 0;
    while (i < d->len) {
        uint8_t code = d->buf[i++];
        if (code == 0 || (uint16_t)i + code - 1u > d->len) {
            return false;
        }
        for (uint8_t k = 1; k < code; k++) {
            if (n >= sizeof body) {
                return false;
            }
            body[n++] = d->buf[i++];
        }
        if (code < 0xFFu && i < d->len) {
            if (n >= sizeof body) {
                return false;
            }
            body[n++] = 0;
        }
    }
    if (n < 4u) {
        return false;
    }
    int extra = of_crc_extra(body[0]);
    uint8_t len = (uint8_t)(n - 4u);
    if (extra < 0 || len > OF_MAX_PAYLOAD) {
        return false;
    }
    uint16_t crc = of_crc16_update(OF_CRC_INIT, (uint8_t)extra);
    for (uint8_t k = 0; k < n; k++) {
        crc = of_crc16_update(crc, body[k]);
    }
    if (crc != 0) {
        return false;
    }
    out->msg_id = body[0];
    out->seq = body[1];
    out->len = len;
    for (uint8_t k = 0; k < len; k++) {
        out->payload[k] = body[2u + k];
    }
    return true;
}

of_feed_result_t of_frame_decoder_feed(of_frame_decoder_t *d, uint8_t byte, of_frame_t *out)
{
    if (byte != 0) {
        if (d->len < sizeof d->buf) {
            d->buf[d->len++] = byte;
        } else {
            d->overflow = 1;
        }
        return OF_FEED_NONE;
    }
    of_feed_result_t result = OF_FEED_NONE;
    if (d->overflow) {
        result = OF_FEED_ERROR;
    } else if (d->len > 0) {
        result = decode_frame(d, out) ? OF_FEED_FRAME : OF_FEED_ERROR;
    }
    of_frame_decoder_init(d);
    return result;
}
