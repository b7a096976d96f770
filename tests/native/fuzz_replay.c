/* The fuzz target's oracles (fuzz_core.c) on a fixed, seeded set of generated inputs,
 * without libFuzzer: any C compiler runs it, in the suite and in each mutant of
 * tools/mutate_firmware.py. Inputs are streams of real frames (known and unknown ids,
 * random payloads of every length, commands with valid and invalid settings) damaged in
 * the ways a serial line damages them: flipped bits, lost and extra bytes, lost or extra
 * delimiters, long runs without one.
 *
 *   fuzz_replay [PARSER_INPUTS [APP_INPUTS [SEED]]]   exits 0, or traps on a violation */
#include <stdio.h>

#include "fuzz_core.c"

static uint32_t rng_state;

static uint32_t rnd(void)
{
    uint32_t x = rng_state; /* xorshift32 */
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    rng_state = x;
    return x;
}

static const uint8_t ids[] = {
    OF_MSG_HELLO, OF_MSG_RANGE, OF_MSG_HEARTBEAT, OF_MSG_TIME_SYNC_REPLY, OF_MSG_ACK,
    OF_MSG_NACK, OF_MSG_LOG, OF_MSG_CONFIG, OF_MSG_GET_INFO, OF_MSG_START, OF_MSG_STOP,
    OF_MSG_SET_CONFIG, OF_MSG_TIME_SYNC, 0x00, 0x09, 0x3F, 0x45, 0xFF,
};

/* A SET_CONFIG near the validation boundaries (often valid). */
static uint8_t set_config_payload(uint8_t *p)
{
    static const uint16_t cycles[] = {28, 29, 30, 60, 100, 10000, 10001};
    static const uint32_t timeouts[] = {999, 1000, 25000, 28000, 40000, 60000, 60001};
    static const uint16_t beats[] = {0, 99, 100, 1000};
    of_set_config_t c;
    c.cycle_ms = cycles[rnd() % 7];
    c.sensor_mask = (uint8_t)(rnd() % 17);
    c.echo_timeout_us = timeouts[rnd() % 7];
    c.max_echo_us = (rnd() & 1) ? c.echo_timeout_us : rnd() % 70000u;
    c.heartbeat_ms = beats[rnd() % 4];
    return of_set_config_pack(&c, p);
}

static size_t make_input(uint8_t *buf, size_t cap)
{
    size_t n = 0;
    unsigned frames = 1u + rnd() % 12u;
    for (unsigned k = 0; k < frames; k++) {
        uint8_t payload[OF_MAX_PAYLOAD + 8];
        uint8_t id = ids[rnd() % sizeof ids];
        size_t len = rnd() % (OF_MAX_PAYLOAD + 3u);
        for (size_t i = 0; i < len; i++) {
            payload[i] = (rnd() % 4u == 0) ? 0 : (uint8_t)rnd();
        }
        if (id == OF_MSG_SET_CONFIG && rnd() % 4u) {
            len = set_config_payload(payload);
        } else if ((id == OF_MSG_GET_INFO || id == OF_MSG_START || id == OF_MSG_STOP)
                   && rnd() % 2u) {
            len = 0;
        } else if (id == OF_MSG_TIME_SYNC && rnd() % 2u) {
            len = 4;
        }
        uint8_t frame[OF_MAX_FRAME + 8];
        size_t f = of_frame_encode(frame, sizeof frame, id, (uint8_t)rnd(), payload, len);
        if (f == 0) { /* unknown id or too long: make the bytes by hand */
            f = 1u + rnd() % (OF_MAX_FRAME + 8u);
            for (size_t i = 0; i + 1u < f; i++) {
                frame[i] = (uint8_t)(1u + rnd() % 255u);
            }
            frame[f - 1u] = 0;
        }
        for (size_t i = 0; i < f && n < cap; i++) {
            buf[n++] = frame[i];
        }
    }
    unsigned damage = rnd() % 4u; /* 0: clean */
    for (unsigned d = 0; d < damage && n > 0; d++) {
        size_t at = rnd() % n;
        switch (rnd() % 5u) {
        case 0: buf[at] ^= (uint8_t)(1u << (rnd() % 8u)); break;
        case 1: memmove(buf + at, buf + at + 1, n - at - 1u); n--; break;
        case 2:
            if (n < cap) {
                memmove(buf + at + 1, buf + at, n - at);
                buf[at] = (uint8_t)rnd();
                n++;
            }
            break;
        case 3: buf[at] = 0; break;
        default: /* a long run without a delimiter */
            for (size_t i = at; i < n && i < at + 80u; i++) {
                buf[i] = (uint8_t)(1u + rnd() % 255u);
            }
            break;
        }
    }
    return n;
}

int main(int argc, char **argv)
{
    long parser_inputs = argc > 1 ? atol(argv[1]) : 20000;
    long app_inputs = argc > 2 ? atol(argv[2]) : 2000;
    rng_state = argc > 3 ? (uint32_t)atol(argv[3]) : 2026u;
    if (rng_state == 0) {
        rng_state = 1;
    }
    static uint8_t buf[1024];
    for (long i = 0; i < parser_inputs; i++) {
        size_t n = make_input(buf, sizeof buf);
        fuzz_parser(buf, n);
    }
    for (long i = 0; i < app_inputs; i++) {
        size_t n = make_input(buf, sizeof buf);
        fuzz_app(buf, n);
    }
    printf("fuzz_replay: %ld parser inputs, %ld app inputs: ok\n", parser_inputs, app_inputs);
    return 0;
}
