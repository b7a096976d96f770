/* libFuzzer target for the firmware core's input path (tools/fuzz_firmware.py builds it
 * with clang -fsanitize=fuzzer,address,undefined and runs it).
 *
 * Each input is used twice:
 *  1. Frame parser, differentially: the bytes go through of_frame_decoder_feed() and,
 *     independently, through a plain reference (split at 0x00, textbook COBS decode,
 *     CRC with the message's seed). Both must accept the same frames with the same
 *     contents and reject the same ones; every accepted frame re-encodes to its bytes.
 *  2. Command decoder: the bytes arrive on the fake board's UART (tests/native/fake_hal.c)
 *     while the application runs, in chunks between polls. Whatever arrives, every frame
 *     the firmware transmits must decode cleanly, the configuration in force must stay
 *     valid, and the sanitizers must stay quiet. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fake_hal.h"
#include "hal.h"
#include "of_app.h"
#include "of_frame.h"

#define REQUIRE(cond)                                                                  \
    do {                                                                               \
        if (!(cond)) {                                                                 \
            __builtin_trap();                                                          \
        }                                                                              \
    } while (0)

/* The reference: what protocol/README.md says a frame is, written the obvious way. */
static int ref_decode(const uint8_t *seg, size_t n, of_frame_t *out)
{
    if (n > OF_MAX_FRAME) {
        return 0; /* longer than the receive buffer: dropped */
    }
    uint8_t body[256];
    size_t m = 0;
    size_t i = 0;
    while (i < n) {
        uint8_t code = seg[i++];
        if (code == 0 || i + code - 1u > n) {
            return 0;
        }
        for (uint8_t k = 1; k < code; k++) {
            body[m++] = seg[i++];
        }
        if (code != 0xFFu && i < n) {
            body[m++] = 0;
        }
    }
    if (m < 4u || m > OF_MAX_BODY) {
        return 0;
    }
    int extra = of_crc_extra(body[0]);
    if (extra < 0) {
        return 0;
    }
    uint16_t crc = OF_CRC_INIT;
    crc = of_crc16_update(crc, (uint8_t)extra);
    for (size_t k = 0; k < m - 2u; k++) {
        crc = of_crc16_update(crc, body[k]);
    }
    if (crc != (uint16_t)(body[m - 2u] << 8 | body[m - 1u])) {
        return 0;
    }
    out->msg_id = body[0];
    out->seq = body[1];
    out->len = (uint8_t)(m - 4u);
    memcpy(out->payload, body + 2, out->len);
    return 1;
}

static void fuzz_parser(const uint8_t *data, size_t size)
{
    of_frame_decoder_t d;
    of_frame_decoder_init(&d);
    size_t start = 0;
    for (size_t i = 0; i < size; i++) {
        of_frame_t got;
        of_feed_result_t r = of_frame_decoder_feed(&d, data[i], &got);
        if (data[i] != 0) {
            REQUIRE(r == OF_FEED_NONE);
            continue;
        }
        of_frame_t want;
        size_t seg_len = i - start;
        int ok = ref_decode(data + start, seg_len, &want);
        if (seg_len == 0) {
            REQUIRE(r == OF_FEED_NONE); /* an empty frame (0x00 0x00) is no error */
        } else if (ok) {
            REQUIRE(r == OF_FEED_FRAME);
            REQUIRE(got.msg_id == want.msg_id && got.seq == want.seq && got.len == want.len);
            REQUIRE(memcmp(got.payload, want.payload, want.len) == 0);
            /* Re-encoding gives a frame that decodes to the same thing (COBS has one
             * canonical form; the input may have used another, so compare decoded). */
            uint8_t enc[OF_MAX_FRAME + 8];
            size_t n = of_frame_encode(enc, sizeof enc, got.msg_id, got.seq, got.payload,
                                       got.len);
            REQUIRE(n >= 6u && n <= OF_MAX_FRAME + 1u && enc[n - 1] == 0);
            REQUIRE(of_frame_encode(enc, n - 1u, got.msg_id, got.seq, got.payload,
                                    got.len) == 0); /* one byte short of room: refused */
            of_frame_t back;
            REQUIRE(ref_decode(enc, n - 1u, &back) == 1);
            REQUIRE(back.msg_id == got.msg_id && back.seq == got.seq && back.len == got.len);
            REQUIRE(memcmp(back.payload, got.payload, got.len) == 0);
        } else {
            REQUIRE(r == OF_FEED_ERROR);
        }
        start = i + 1;
    }
}

static of_app_t app;
static of_frame_t out[512];

static void take_and_check(void)
{
    int errors = 0;
    int n = fake_tx_take(out, (int)(sizeof out / sizeof out[0]), &errors);
    REQUIRE(errors == 0);
    for (int k = 0; k < n; k++) {
        REQUIRE(out[k].msg_id >= 0x01u && out[k].msg_id <= 0x08u); /* device-to-host ids */
    }
}

static void fuzz_app(const uint8_t *data, size_t size)
{
    fake_reset((uint64_t)(size * 7919u) & 0x3FFFFu);
    memset(&app, 0, sizeof app);
    of_app_init(&app);
    take_and_check();
    const size_t chunk = 48;
    for (size_t pos = 0; pos < size; pos += chunk) {
        size_t n = size - pos < chunk ? size - pos : chunk;
        fake_rx_bytes(data + pos, (uint16_t)n);
        for (int k = 0; k < 4; k++) {
            (void)of_app_poll(&app);
            fake_advance_to(fake.now + 700u); /* 350 us */
        }
        REQUIRE(of_app_validate(&app.cfg, HAL_SENSOR_COUNT) == OF_ERROR_NONE);
        take_and_check();
    }
    /* Let the ranger and the heartbeat run on whatever configuration was accepted. */
    for (int k = 0; k < 200; k++) {
        uint32_t wake = of_app_poll(&app);
        int32_t dt = (int32_t)(wake - hal_micros());
        uint64_t ticks = dt < 20 ? 40u : (uint64_t)dt * HAL_TICKS_PER_US;
        fake_advance_to(fake.now + (ticks > 4000u ? 4000u : ticks));
        if (k % 16 == 0) {
            take_and_check();
        }
    }
    take_and_check();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 4096u) {
        return 0;
    }
    fuzz_parser(data, size);
    fuzz_app(data, size);
    return 0;
}
