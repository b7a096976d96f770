/* The C frame decoder on a noisy stream: good frames come out, bad ones are reported,
 * an overlong run of bytes is dropped without overrunning the buffer. */
#include <stdio.h>
#include <string.h>

#include "of_frame.h"
#include "of_protocol.h"

static int failures;
#define CHECK(cond, what)                                   \
    do {                                                    \
        if (!(cond)) {                                      \
            printf("FAIL %s (line %d)\n", what, __LINE__);  \
            failures++;                                     \
        }                                                   \
    } while (0)

int main(void)
{
    uint8_t stream[1024];
    size_t n = 0;
    uint8_t payload[OF_MAX_PAYLOAD];

    of_time_sync_t ts = {.token = 0xDEADBEEFu};
    uint8_t len = of_time_sync_pack(&ts, payload);
    size_t first = of_frame_encode(stream + n, sizeof stream - n, OF_MSG_TIME_SYNC, 1, payload, len);
    CHECK(first > 0, "encode time_sync");
    n += first;

    /* A corrupted copy: one payload byte flipped. */
    size_t bad = of_frame_encode(stream + n, sizeof stream - n, OF_MSG_TIME_SYNC, 2, payload, len);
    stream[n + 3] ^= 0x40;
    n += bad;

    /* 300 bytes without a delimiter: must be dropped, not overrun anything. */
    memset(stream + n, 0x55, 300);
    n += 300;
    stream[n++] = 0x00;

    of_set_config_t cfg = {.cycle_ms = 60, .sensor_mask = 1, .max_echo_us = 23324,
                           .echo_timeout_us = 40000, .heartbeat_ms = 1000};
    len = of_set_config_pack(&cfg, payload);
    n += of_frame_encode(stream + n, sizeof stream - n, OF_MSG_SET_CONFIG, 3, payload, len);

    /* An unknown id cannot be encoded. */
    CHECK(of_frame_encode(stream + n, sizeof stream - n, 0x7F, 0, payload, 0) == 0, "unknown id");
    /* Too small an output buffer is refused. */
    uint8_t tiny[8];
    CHECK(of_frame_encode(tiny, sizeof tiny, OF_MSG_SET_CONFIG, 0, payload, len) == 0, "tiny buf");

    of_frame_decoder_t d;
    of_frame_decoder_init(&d);
    of_frame_t fr;
    int good = 0, errors = 0;
    uint8_t ids[4] = {0};
    for (size_t i = 0; i < n; i++) {
        of_feed_result_t r = of_frame_decoder_feed(&d, stream[i], &fr);
        if (r == OF_FEED_FRAME) {
            if (good < 4) ids[good] = fr.msg_id;
            good++;
        } else if (r == OF_FEED_ERROR) {
            errors++;
        }
    }
    CHECK(good == 2, "two good frames");
    CHECK(errors == 2, "two bad frames (corrupt, overlong)");
    CHECK(ids[0] == OF_MSG_TIME_SYNC && ids[1] == OF_MSG_SET_CONFIG, "frame order");
    of_set_config_t back;
    CHECK(of_set_config_unpack(&back, fr.payload, fr.len), "unpack");
    CHECK(back.echo_timeout_us == 40000u && back.cycle_ms == 60u, "fields");
    CHECK(!of_set_config_unpack(&back, fr.payload, (uint8_t)(fr.len - 1u)), "short payload");

    /* A good CRC on a wrong length reaches the caller, whose unpack refuses it (NACK). */
    size_t m = of_frame_encode(stream, sizeof stream, OF_MSG_SET_CONFIG, 4, payload, 3);
    of_frame_decoder_init(&d);
    int frames = 0;
    for (size_t i = 0; i < m; i++) {
        if (of_frame_decoder_feed(&d, stream[i], &fr) == OF_FEED_FRAME) frames++;
    }
    CHECK(frames == 1 && fr.len == 3u, "short frame passed up");
    CHECK(!of_set_config_unpack(&back, fr.payload, fr.len), "short frame refused by unpack");

    printf("stream test: %d failures\n", failures);
    return failures ? 1 : 0;
}
