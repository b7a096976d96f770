/* Framing of the obstacle-fusion wire protocol: COBS, CRC-16 with a per-message seed,
 * 0x00 delimiter. Portable C99, no malloc; see protocol/README.md for the format. */
#ifndef OF_FRAME_H
#define OF_FRAME_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "of_protocol.h"

/* Frame body before COBS: msg_id, seq, payload, crc16 little-endian. */
#define OF_FRAME_BODY_MAX (2u + OF_MAX_PAYLOAD + 2u)

typedef struct {
    uint8_t msg_id;
    uint8_t seq;
    uint8_t len; /* payload length */
    uint8_t payload[OF_MAX_PAYLOAD];
} of_frame_t;

typedef struct {
    uint8_t buf[OF_MAX_FRAME]; /* COBS bytes of the frame being received */
    uint8_t len;
    uint8_t overflow; /* set when the current frame outgrew buf; it is dropped at 0x00 */
} of_frame_decoder_t;

typedef enum {
    OF_FEED_ERROR = -1, /* a bad frame was dropped (COBS, CRC, length, unknown id) */
    OF_FEED_NONE = 0,   /* nothing complete yet */
    OF_FEED_FRAME = 1   /* *out holds a valid frame */
} of_feed_result_t;

/* CRC-16/CCITT-FALSE update with one byte. */
uint16_t of_crc16_update(uint16_t crc, uint8_t byte);

/* Writes one complete frame (COBS bytes then the 0x00 delimiter) into out.
 * Returns the number of bytes written, or 0 when msg_id is unknown, len is too long,
 * or cap is too small (nothing useful is written then). */
size_t of_frame_encode(uint8_t *out, size_t cap, uint8_t msg_id, uint8_t seq,
                       const uint8_t *payload, size_t len);

void of_frame_decoder_init(of_frame_decoder_t *d);

/* Feeds one received byte. Returns OF_FEED_FRAME when a frame with a known id and a good
 * CRC completed (copied into *out), OF_FEED_ERROR when a bad frame was dropped, else
 * OF_FEED_NONE. The payload length is NOT checked here: a frame whose CRC is good but whose
 * length does not fit its message reaches the caller, whose of_<name>_unpack() refuses it,
 * so that the device can answer NACK(bad_length) instead of staying silent. */
of_feed_result_t of_frame_decoder_feed(of_frame_decoder_t *d, uint8_t byte, of_frame_t *out);

#endif /* OF_FRAME_H */
