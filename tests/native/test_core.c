/* Native tests of the portable firmware core against the fake board (fake_hal.c).
 * `test_core --list` names the tests; `test_core NAME` runs one and exits 0 on success.
 * tests/test_firmware_core.py builds this with the host gcc and runs each test. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fake_hal.h"
#include "hal.h"
#include "of_app.h"
#include "of_ring.h"
#include "of_ticks.h"

static int failures;

#define CHECK(cond)                                                                    \
    do {                                                                               \
        if (!(cond)) {                                                                 \
            printf("%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);            \
            failures++;                                                                \
            return;                                                                    \
        }                                                                              \
    } while (0)

#define CHECK_EQ(a, b)                                                                 \
    do {                                                                               \
        uint64_t a_ = (uint64_t)(a), b_ = (uint64_t)(b);                               \
        if (a_ != b_) {                                                                \
            printf("%s:%d: %s == %s failed: %" PRIu64 " != %" PRIu64 "\n", __FILE__,   \
                   __LINE__, #a, #b, a_, b_);                                          \
            failures++;                                                                \
            return;                                                                    \
        }                                                                              \
    } while (0)

/* ------------------------------------------------------------------ harness */

static of_app_t app;
static of_frame_t frames[2048];
static int nframes;
static int tx_errors;
static uint8_t host_seq;

/* The longest the simulated board sleeps between polls, in ticks: 4000 is the Uno's
 * 2 ms idle cap; a test may lower it to stand for a busy board (UART traffic, other
 * interrupts) that polls far more often than the firmware asks. */
static uint64_t max_sleep_ticks = 4000;

static void boot(uint64_t offset_ticks)
{
    max_sleep_ticks = 4000;
    fake_reset(offset_ticks);
    memset(&app, 0, sizeof app);
    of_app_init(&app);
    nframes = 0;
    tx_errors = 0;
    host_seq = 0;
}

/* Runs the main loop as the board does: poll, then sleep until the returned time (at
 * most 2 ms, like the Uno) or until an ECHO edge's capture interrupt wakes the CPU. */
static void run_us(uint64_t us)
{
    uint64_t end = fake.now + us * HAL_TICKS_PER_US;
    while (fake.now < end) {
        uint32_t wake = of_app_poll(&app);
        int32_t d = (int32_t)(wake - hal_micros());
        uint64_t dt = d < 40 ? 20 : (uint64_t)d * HAL_TICKS_PER_US;
        if (dt > max_sleep_ticks) {
            dt = max_sleep_ticks;
        }
        uint64_t next = fake.now + dt;
        uint64_t edge = fake.rise_at < fake.fall_at ? fake.rise_at : fake.fall_at;
        if (edge != FAKE_NEVER && edge + fake.capture_latency < next) {
            next = edge + fake.capture_latency;
        }
        if (next > end) {
            next = end;
        }
        if (next <= fake.now) {
            next = fake.now + 1;
        }
        fake_advance_to(next);
    }
}

/* Appends everything transmitted since the last call to frames[]. */
static void take(void)
{
    int errors = 0;
    nframes += fake_tx_take(frames + nframes, (int)(sizeof frames / sizeof frames[0]) - nframes,
                            &errors);
    tx_errors += errors;
}

static void clear_frames(void)
{
    take();
    nframes = 0;
}

static int count_id(uint8_t id)
{
    int n = 0;
    for (int i = 0; i < nframes; i++) {
        n += frames[i].msg_id == id;
    }
    return n;
}

/* The k-th frame with this id, or NULL. */
static const of_frame_t *nth(uint8_t id, int k)
{
    for (int i = 0; i < nframes; i++) {
        if (frames[i].msg_id == id && k-- == 0) {
            return &frames[i];
        }
    }
    return NULL;
}

static of_range_t range_at(int k)
{
    of_range_t r;
    memset(&r, 0xEE, sizeof r);
    const of_frame_t *f = nth(OF_MSG_RANGE, k);
    if (f) {
        of_range_unpack(&r, f->payload, f->len);
    }
    return r;
}

static void send_cmd(uint8_t id, const uint8_t *payload, uint8_t len)
{
    fake_rx_frame(id, host_seq++, payload, len);
}

static void send_set_config(uint16_t cycle_ms, uint8_t mask, uint32_t max_echo_us,
                            uint32_t timeout_us, uint16_t heartbeat_ms)
{
    of_set_config_t c = {cycle_ms, mask, max_echo_us, timeout_us, heartbeat_ms};
    uint8_t p[OF_MSG_SET_CONFIG_LEN];
    send_cmd(OF_MSG_SET_CONFIG, p, of_set_config_pack(&c, p));
}

/* The microsecond clock the core should see at true tick t. */
static uint32_t true_us(uint64_t t)
{
    return (uint32_t)((fake.start_offset + t) / HAL_TICKS_PER_US);
}

/* ------------------------------------------------------------------ tests */

static void test_ticks_pure(void)
{
    /* Overflow pending while a small capture is read: the capture is after the wrap. */
    CHECK_EQ(of_ticks_extend(5, 0x0003, true), (6u << 16) | 3u);
    /* Overflow pending, capture in the upper half: taken just before the wrap. */
    CHECK_EQ(of_ticks_extend(5, 0xFFF0, true), (5u << 16) | 0xFFF0u);
    CHECK_EQ(of_ticks_extend(5, 0x0003, false), (5u << 16) | 3u);
    CHECK_EQ(of_ticks_extend(0xFFFFu, 0x0001, true), 0x00000001u); /* 32-bit tick wrap */
    /* Microseconds agree with ticks/2 on a 64-bit clock, modulo 2^32, everywhere. */
    uint64_t x = 0x123456789ULL;
    for (int i = 0; i < 200000; i++) {
        x = x * 6364136223846793005ULL + 1442695040888963407ULL;
        uint64_t T = x >> 20; /* any raw tick time up to 2^44 */
        uint16_t v = (uint16_t)T;
        bool pending = (x & 1u) && v < 0x4000u;
        uint32_t ovf = (uint32_t)(T >> 16) - (pending ? 1u : 0u);
        CHECK_EQ(of_ticks_micros(ovf, v, pending, 1), (uint32_t)(T >> 1));
        CHECK_EQ(of_ticks_micros(ovf, v, pending, 3), (uint32_t)(T >> 3));
        CHECK_EQ(of_ticks_extend(ovf, v, pending), (uint32_t)T);
    }
    CHECK(of_time_reached(5u, 0xFFFFFFF0u));
    CHECK(!of_time_reached(0xFFFFFFF0u, 5u));
}

static void test_power_up(void)
{
    boot(0);
    run_us(1000);
    take();
    CHECK(nframes >= 2);
    CHECK_EQ(frames[0].msg_id, OF_MSG_HELLO);
    CHECK_EQ(frames[0].seq, 0);
    of_hello_t h;
    CHECK(of_hello_unpack(&h, frames[0].payload, frames[0].len));
    CHECK_EQ(h.protocol_version, OF_PROTOCOL_VERSION);
    CHECK_EQ(h.schema_fingerprint, OF_SCHEMA_FINGERPRINT);
    CHECK_EQ(h.board, OF_BOARD_UNO);
    CHECK_EQ(h.timer_hz, 2000000u);
    CHECK_EQ(h.sensor_count, 4);
    CHECK_EQ(frames[1].msg_id, OF_MSG_CONFIG);
    of_config_t c;
    CHECK(of_config_unpack(&c, frames[1].payload, frames[1].len));
    CHECK_EQ(c.cycle_ms, 60);
    CHECK_EQ(c.sensor_mask, 1);
    CHECK_EQ(c.max_echo_us, 23324);
    CHECK_EQ(c.echo_timeout_us, 40000);
    CHECK_EQ(c.heartbeat_ms, 1000);
    CHECK_EQ(c.state, OF_RUN_STATE_RUNNING);
    CHECK_EQ(fake.triggers, 0); /* the guard: ECHO low for 2 ms first */
    run_us(2000);
    CHECK_EQ(fake.triggers, 1);
    CHECK_EQ(count_id(OF_MSG_LOG), 0);
    /* The same when the clock is far from 0 at power-up (a slow start, a warm reset). */
    boot((uint64_t)5000000u * 2u);
    run_us(1900);
    CHECK_EQ(fake.triggers, 0);
    run_us(200);
    CHECK_EQ(fake.triggers, 1);

    /* After a watchdog reset the board says so, after HELLO and CONFIG. */
    fake_reset(0);
    fake.watchdog_reset = true;
    memset(&app, 0, sizeof app);
    of_app_init(&app);
    nframes = 0;
    run_us(1000);
    take();
    CHECK_EQ(frames[0].msg_id, OF_MSG_HELLO);
    CHECK_EQ(frames[1].msg_id, OF_MSG_CONFIG);
    CHECK_EQ(frames[2].msg_id, OF_MSG_LOG);
    of_log_t lg;
    CHECK(of_log_unpack(&lg, frames[2].payload, frames[2].len));
    CHECK_EQ(lg.level, OF_LOG_LEVEL_WARNING);
    CHECK_EQ(lg.text_len, 14);
    CHECK(memcmp(lg.text, "watchdog reset", 14) == 0);
}

static void test_normal_echo(void)
{
    boot(0);
    run_us(200000);
    take();
    CHECK_EQ(tx_errors, 0);
    CHECK_EQ(count_id(OF_MSG_RANGE), 4); /* triggers at ~2, 62, 122, 182 ms */
    for (int k = 0; k < 4; k++) {
        of_range_t r = range_at(k);
        CHECK_EQ(r.measurement, (uint32_t)k);
        CHECK_EQ(r.sensor_id, 0);
        CHECK_EQ(r.status, OF_RANGE_STATUS_OK);
        CHECK_EQ(r.echo_ticks, 11655); /* exact, to the tick */
        CHECK_EQ(r.trigger_us, true_us(fake.trigger_at[k]));
        if (k > 0) {
            uint64_t gap = fake.trigger_at[k] - fake.trigger_at[k - 1];
            CHECK(gap >= 120000 - 1 && gap <= 120000 + 40); /* 60 ms from the last trigger (1 us clock) */
        }
    }
    CHECK_EQ(fake.ignored_triggers, 0);
}

static void test_status_boundaries(void)
{
    /* width in ticks -> status, default max_echo_us 23324 (46648 ticks) */
    static const struct { uint32_t w; uint8_t st; } cases[] = {
        {232, OF_RANGE_STATUS_OK},          {46648, OF_RANGE_STATUS_OK},
        {46649, OF_RANGE_STATUS_OUT_OF_RANGE}, {59999, OF_RANGE_STATUS_OUT_OF_RANGE},
        {60000, OF_RANGE_STATUS_NO_ECHO},   {76000, OF_RANGE_STATUS_NO_ECHO},
        {79999, OF_RANGE_STATUS_NO_ECHO},
    };
    for (unsigned i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        boot(0);
        fake.sensor[0].width_ticks = cases[i].w;
        run_us(50000);
        take();
        CHECK_EQ(count_id(OF_MSG_RANGE), 1);
        of_range_t r = range_at(0);
        CHECK_EQ(r.echo_ticks, cases[i].w);
        CHECK_EQ(r.status, cases[i].st);
    }
}

static void test_no_echo(void)
{
    /* The sensor's own ~38 ms pulse: reported as no_echo with its width, never a zero. */
    boot(0);
    fake.sensor[0].width_ticks = 76000;
    run_us(300000);
    take();
    CHECK(count_id(OF_MSG_RANGE) >= 4);
    for (int k = 0; k < count_id(OF_MSG_RANGE); k++) {
        of_range_t r = range_at(k);
        CHECK_EQ(r.status, OF_RANGE_STATUS_NO_ECHO);
        CHECK_EQ(r.echo_ticks, 76000);
    }
    /* ECHO never rises (sensor missing): timeout with 0 ticks, after echo_timeout_us. */
    boot(0);
    fake.sensor[0].width_ticks = FAKE_NEVER;
    run_us(150000);
    take();
    CHECK(count_id(OF_MSG_RANGE) >= 2);
    of_range_t r = range_at(0);
    CHECK_EQ(r.status, OF_RANGE_STATUS_TIMEOUT);
    CHECK_EQ(r.echo_ticks, 0);
    CHECK_EQ(range_at(1).measurement, 1);
}

static void test_echo_never_falls(void)
{
    /* ECHO rises and stays high 120 ms: timeout after 40 ms of high time with the
     * ticks measured so far; no trigger while it is high; then normal again. */
    boot(0);
    fake.width_queue[0] = 240000;
    fake.width_queue[1] = 11655;
    fake.width_queue[2] = 11655;
    fake.queue_len = 3;
    run_us(40000);
    take();
    CHECK_EQ(count_id(OF_MSG_RANGE), 0); /* 38 ms into the echo: still measuring */
    run_us(10000);
    take();
    CHECK_EQ(count_id(OF_MSG_RANGE), 1);
    of_range_t r = range_at(0);
    CHECK_EQ(r.status, OF_RANGE_STATUS_TIMEOUT);
    CHECK(r.echo_ticks > 80000 && r.echo_ticks <= 80000 + 200);
    run_us(300000);
    take();
    CHECK_EQ(fake.ignored_triggers, 0);
    CHECK(fake.triggers >= 3);
    /* The second trigger waited for ECHO to fall, plus the guard. */
    CHECK(fake.trigger_at[1] >= fake.trigger_at[0] + 20 + 900 + 240000 + 4000);
    CHECK(fake.trigger_at[1] <= fake.trigger_at[0] + 20 + 900 + 240000 + 4000 + 2100);
    r = range_at(1);
    CHECK_EQ(r.measurement, 1);
    CHECK_EQ(r.status, OF_RANGE_STATUS_OK);
    CHECK_EQ(r.echo_ticks, 11655);
    /* Then the normal period again, from the late trigger. */
    CHECK(fake.trigger_at[2] - fake.trigger_at[1] >= 120000 - 2);
    CHECK(fake.trigger_at[2] - fake.trigger_at[1] <= 120000 + 2);

    /* ECHO stuck high for good (a hung sensor, a floating line): the firmware keeps
     * triggering at a bounded rate and reports timeouts, never silence. */
    boot(0);
    fake.sensor[0].width_ticks = 20000000; /* 10 s */
    run_us(1000000);
    take();
    int n = count_id(OF_MSG_RANGE);
    CHECK(n >= 5 && n <= 8);
    CHECK_EQ(range_at(0).status, OF_RANGE_STATUS_TIMEOUT);
    CHECK(range_at(0).echo_ticks > 80000);
    for (int k = 1; k < n; k++) {
        CHECK_EQ(range_at(k).status, OF_RANGE_STATUS_TIMEOUT);
        CHECK_EQ(range_at(k).echo_ticks, 0); /* the rise it waits for never comes */
    }
}

static void test_overflow_during_echo(void)
{
    /* Edges on every side of a Timer1 wrap, with the overflow interrupt serviced
     * promptly or held off for up to 10 ms: every width must be exact. */
    static const uint32_t widths[] = {232, 11655, 65535, 65536, 65537, 76000};
    static const uint32_t delays[] = {1, 6, 200, 20000};
    uint32_t pending_seen = 0;
    for (unsigned d = 0; d < sizeof delays / sizeof delays[0]; d++) {
        for (unsigned w = 0; w < sizeof widths / sizeof widths[0]; w++) {
            for (int32_t shift = -300; shift <= 300; shift += 7) {
                /* Place the first rise `shift` ticks from a wrap (rise = 4020 + 920). */
                uint64_t rise = 4000 + 20 + 20 + 900;
                uint64_t offset = (5ull << 16) - rise + (uint64_t)(int64_t)shift;
                if (w % 2) {
                    offset = (5ull << 16) - rise - widths[w] + (uint64_t)(int64_t)shift;
                }
                fake_reset(offset);
                fake.ovf_isr_delay = delays[d];
                fake.sensor[0].width_ticks = widths[w];
                memset(&app, 0, sizeof app);
                of_app_init(&app);
                nframes = 0;
                run_us(42000);
                take();
                CHECK(count_id(OF_MSG_RANGE) >= 1);
                of_range_t r = range_at(0);
                if (r.echo_ticks != widths[w]) {
                    printf("delay %u width %u shift %d: got %u\n", delays[d], widths[w],
                           (int)shift, (unsigned)r.echo_ticks);
                }
                CHECK_EQ(r.echo_ticks, widths[w]);
                CHECK_EQ(r.trigger_us, true_us(fake.trigger_at[0]));
                pending_seen += fake.pending_captures;
            }
        }
    }
    CHECK(pending_seen > 100); /* the delicate case really happened */
}

static void test_micros_wrap(void)
{
    /* Start 100 ms before the 32-bit microsecond clock wraps, then 100 ms before the
     * 32-bit tick count wraps: the period, stamps and widths stay exact across both. */
    static const uint64_t offsets[] = {(1ull << 33) - 200000, (1ull << 32) - 200000,
                                       (1ull << 33) - 120001};
    for (unsigned i = 0; i < 3; i++) {
        boot(offsets[i]);
        run_us(400000);
        take();
        CHECK_EQ(tx_errors, 0);
        int n = count_id(OF_MSG_RANGE);
        CHECK(n >= 6);
        for (int k = 0; k < n; k++) {
            of_range_t r = range_at(k);
            CHECK_EQ(r.status, OF_RANGE_STATUS_OK);
            CHECK_EQ(r.echo_ticks, 11655);
            CHECK_EQ(r.trigger_us, true_us(fake.trigger_at[k]));
            if (k > 0) {
                uint32_t gap = r.trigger_us - range_at(k - 1).trigger_us;
                CHECK(gap >= 60000 && gap <= 60020);
            }
        }
        if (i == 0) {
            CHECK(range_at(0).trigger_us > 0xFFF00000u);
            CHECK(range_at(n - 1).trigger_us < 0x00100000u);
        }
    }
}

static void test_back_to_back(void)
{
    /* Shortest cycle with the sensor's 38 ms no-echo pulse longer than the timeout:
     * triggers wait for ECHO low + guard, none is ignored by the sensor, and no stale
     * edge of one measurement leaks into the next. */
    boot(0);
    send_set_config(29, 1, 20000, 25000, 0);
    for (int i = 0; i < 16; i++) {
        fake.width_queue[i] = (i % 2) ? 11655 : 76000;
    }
    fake.queue_len = 16;
    run_us(1000000);
    take();
    CHECK_EQ(fake.ignored_triggers, 0);
    int n = count_id(OF_MSG_RANGE);
    CHECK(n >= 16);
    for (int k = 0; k < n; k++) {
        of_range_t r = range_at(k);
        CHECK_EQ(r.measurement, (uint32_t)k);
        if (k % 2) {
            CHECK_EQ(r.status, OF_RANGE_STATUS_OK);
            CHECK_EQ(r.echo_ticks, 11655);
        } else {
            CHECK_EQ(r.status, OF_RANGE_STATUS_TIMEOUT);
            CHECK(r.echo_ticks > 50000 && r.echo_ticks < 50400);
        }
    }
    for (uint32_t k = 1; k < fake.triggers && k < 64; k++) {
        CHECK(fake.trigger_at[k] - fake.trigger_at[k - 1] >= 58000 - 2); /* 1 us = 2 ticks */
    }

    /* Round robin over sensors 0, 1 and 3 at the 60 ms cycle, each trigger at least the
     * guard after the previous echo fell. */
    boot(0);
    fake.sensor[1].width_ticks = 20000;
    fake.sensor[3].width_ticks = 30000;
    send_set_config(60, 0x0B, 23324, 40000, 1000);
    run_us(700000);
    take();
    CHECK_EQ(fake.ignored_triggers, 0);
    static const uint8_t order[] = {0, 1, 3};
    int first = -1;
    for (uint32_t k = 0; k < fake.triggers; k++) {
        if (first < 0 && fake.trigger_sensor[k] == 0 && k > 0) {
            first = (int)k;
        }
    }
    CHECK(first > 0);
    for (uint32_t k = (uint32_t)first; k + 1 < fake.triggers; k++) {
        CHECK_EQ(fake.trigger_sensor[k], order[(k - (uint32_t)first) % 3]);
        CHECK(fake.trigger_at[k + 1] - fake.trigger_at[k] >= 120000 - 2);
    }
    for (int k = 0; k < count_id(OF_MSG_RANGE); k++) {
        of_range_t r = range_at(k);
        uint32_t want = r.sensor_id == 0 ? 11655 : (r.sensor_id == 1 ? 20000 : 30000);
        CHECK_EQ(r.echo_ticks, want);
        CHECK(r.sensor_id != 2);
    }

    /* STOP in the middle of an echo, START at once: the abandoned echo's fall must not
     * end the next measurement. */
    boot(0);
    fake.sensor[0].width_ticks = 30000;
    run_us(3000); /* triggered at ~2 ms, echo rises ~0.5 ms later */
    CHECK_EQ(fake.triggers, 1);
    CHECK(fake.echo_high);
    send_cmd(OF_MSG_STOP, NULL, 0);
    run_us(100);
    send_cmd(OF_MSG_START, NULL, 0);
    run_us(200000);
    take();
    CHECK_EQ(fake.ignored_triggers, 0);
    CHECK(count_id(OF_MSG_RANGE) >= 2);
    for (int k = 0; k < count_id(OF_MSG_RANGE); k++) {
        CHECK_EQ(range_at(k).echo_ticks, 30000);
        CHECK_EQ(range_at(k).measurement, (uint32_t)k + 1); /* 0 was abandoned */
    }
}

struct cfg_case {
    uint16_t cycle;
    uint8_t mask;
    uint32_t max_echo, timeout;
    uint16_t hb;
    uint8_t err;
};

static void test_config_validation(void)
{
    static const struct cfg_case cases[] = {
        {60, 1, 23324, 40000, 1000, OF_ERROR_NONE},
        {29, 1, 999, 1000, 100, OF_ERROR_NONE},
        {10000, 15, 60000, 60000, 0, OF_ERROR_NONE},
        {60, 1, 500, 999, 1000, OF_ERROR_BAD_TIMEOUT},
        {60, 1, 500, 60001, 1000, OF_ERROR_BAD_TIMEOUT},
        {60, 1, 500, 0, 1000, OF_ERROR_BAD_TIMEOUT},
        {28, 1, 500, 1000, 1000, OF_ERROR_BAD_CYCLE},
        {10001, 1, 500, 40000, 1000, OF_ERROR_BAD_CYCLE},
        {40, 1, 500, 40000, 1000, OF_ERROR_BAD_CYCLE}, /* cycle*1000 must exceed timeout */
        {41, 1, 500, 40000, 1000, OF_ERROR_NONE},
        {60, 1, 500, 59999, 1000, OF_ERROR_NONE},   /* 60 ms is 60000 us, not 59940 */
        {60, 1, 500, 60000, 1000, OF_ERROR_BAD_CYCLE},
        {60, 1, 1, 40000, 1000, OF_ERROR_NONE},     /* the smallest max_echo_us */
        {60, 1, 0, 40000, 1000, OF_ERROR_BAD_MAX_ECHO},
        {60, 1, 40001, 40000, 1000, OF_ERROR_BAD_MAX_ECHO},
        {60, 1, 40000, 40000, 1000, OF_ERROR_NONE},
        {60, 0, 500, 40000, 1000, OF_ERROR_BAD_SENSOR_MASK},
        {60, 0x10, 500, 40000, 1000, OF_ERROR_BAD_SENSOR_MASK},
        {60, 0x81, 500, 40000, 1000, OF_ERROR_BAD_SENSOR_MASK},
        {60, 1, 500, 40000, 99, OF_ERROR_BAD_HEARTBEAT},
        {60, 1, 500, 40000, 1, OF_ERROR_BAD_HEARTBEAT},
        {60, 1, 500, 40000, 100, OF_ERROR_NONE},
        /* several bad fields: the first in the documented order wins */
        {5, 0, 0, 70000, 5, OF_ERROR_BAD_TIMEOUT},
        {5, 0, 0, 40000, 5, OF_ERROR_BAD_CYCLE},
        {60, 0, 0, 40000, 5, OF_ERROR_BAD_MAX_ECHO},
        {60, 0, 10, 40000, 5, OF_ERROR_BAD_SENSOR_MASK},
    };
    for (unsigned i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const struct cfg_case *c = &cases[i];
        of_set_config_t sc = {c->cycle, c->mask, c->max_echo, c->timeout, c->hb};
        CHECK_EQ(of_app_validate(&sc, 4), c->err);

        /* Over the wire: NACK with that code and nothing applied, or ACK then CONFIG. */
        boot(0);
        run_us(1000);
        clear_frames();
        send_set_config(c->cycle, c->mask, c->max_echo, c->timeout, c->hb);
        send_cmd(OF_MSG_GET_INFO, NULL, 0);
        run_us(1000);
        take();
        of_config_t got;
        if (c->err != OF_ERROR_NONE) {
            CHECK_EQ(frames[0].msg_id, OF_MSG_NACK);
            of_nack_t nk;
            CHECK(of_nack_unpack(&nk, frames[0].payload, frames[0].len));
            CHECK_EQ(nk.command_id, OF_MSG_SET_CONFIG);
            CHECK_EQ(nk.command_seq, 0);
            CHECK_EQ(nk.error, c->err);
            CHECK_EQ(frames[1].msg_id, OF_MSG_HELLO);
            CHECK_EQ(frames[2].msg_id, OF_MSG_CONFIG);
            CHECK(of_config_unpack(&got, frames[2].payload, frames[2].len));
            CHECK_EQ(got.cycle_ms, 60);
            CHECK_EQ(got.sensor_mask, 1);
            CHECK_EQ(got.max_echo_us, 23324);
            CHECK_EQ(got.echo_timeout_us, 40000);
            CHECK_EQ(got.heartbeat_ms, 1000);
        } else {
            CHECK_EQ(frames[0].msg_id, OF_MSG_ACK);
            CHECK_EQ(frames[1].msg_id, OF_MSG_CONFIG);
            CHECK(of_config_unpack(&got, frames[1].payload, frames[1].len));
            CHECK_EQ(got.cycle_ms, c->cycle);
            CHECK_EQ(got.sensor_mask, c->mask);
            CHECK_EQ(got.max_echo_us, c->max_echo);
            CHECK_EQ(got.echo_timeout_us, c->timeout);
            CHECK_EQ(got.heartbeat_ms, c->hb);
            CHECK_EQ(got.state, OF_RUN_STATE_RUNNING);
        }
    }

    /* An accepted config changes the rate: 100 ms cycle -> triggers 100 ms apart. */
    boot(0);
    send_set_config(100, 1, 23324, 40000, 1000);
    run_us(1000000);
    take();
    CHECK(fake.triggers >= 9 && fake.triggers <= 11);
    for (uint32_t k = 2; k < fake.triggers; k++) {
        uint64_t gap = fake.trigger_at[k] - fake.trigger_at[k - 1];
        CHECK(gap >= 200000 - 2 && gap <= 200040);
    }

    /* A rejected config leaves the rate alone. */
    boot(0);
    send_set_config(100, 1, 23324, 40000, 50);
    run_us(1000000);
    CHECK(fake.triggers >= 16 && fake.triggers <= 17);

    /* Wrong payload length and a device-to-host id sent to the device. */
    boot(0);
    clear_frames();
    of_frame_t f;
    memset(&f, 0, sizeof f);
    f.msg_id = OF_MSG_SET_CONFIG;
    f.seq = 9;
    f.len = 12;
    of_app_handle_frame(&app, &f, 0);
    f.msg_id = OF_MSG_TIME_SYNC;
    f.len = 3;
    of_app_handle_frame(&app, &f, 0);
    f.msg_id = OF_MSG_START;
    f.len = 1;
    of_app_handle_frame(&app, &f, 0);
    send_cmd(OF_MSG_HELLO, (const uint8_t *)"012345678901234567", 18);
    run_us(1000);
    take();
    static const uint8_t want[][2] = {{OF_MSG_SET_CONFIG, OF_ERROR_BAD_LENGTH},
                                      {OF_MSG_TIME_SYNC, OF_ERROR_BAD_LENGTH},
                                      {OF_MSG_START, OF_ERROR_BAD_LENGTH},
                                      {OF_MSG_HELLO, OF_ERROR_UNKNOWN_COMMAND}};
    for (int i = 0; i < 4; i++) {
        const of_frame_t *nf = nth(OF_MSG_NACK, i);
        CHECK(nf != NULL);
        CHECK_EQ(nf->payload[0], want[i][0]);
        CHECK_EQ(nf->payload[2], want[i][1]);
    }
}

static void test_tx_overrun(void)
{
    /* A burst of GET_INFO answers (44 bytes each) overflows the 128-byte TX ring: the
     * extra frames are dropped whole and counted, measurements go on, and the counter
     * equals the frames the host sees missing. */
    boot(0);
    run_us(5000);
    for (int i = 0; i < 12; i++) {
        send_cmd(OF_MSG_GET_INFO, NULL, 0);
    }
    run_us(1500000);
    take();
    CHECK_EQ(tx_errors, 0); /* never a partial frame on the wire */
    int hellos = count_id(OF_MSG_HELLO) - 1;
    CHECK(hellos < 12);
    CHECK(app.tx_overruns > 0);
    /* Seq gaps on the wire equal the drops. */
    uint32_t missing = 0;
    for (int i = 1; i < nframes; i++) {
        missing += (uint8_t)(frames[i].seq - frames[i - 1].seq - 1u);
    }
    CHECK_EQ(missing, app.tx_overruns);
    CHECK_EQ(app.frames_sent, (uint32_t)nframes);
    const of_frame_t *hb = nth(OF_MSG_HEARTBEAT, 0);
    CHECK(hb != NULL);
    of_heartbeat_t h;
    CHECK(of_heartbeat_unpack(&h, hb->payload, hb->len));
    CHECK_EQ(h.tx_overruns, app.tx_overruns);
    CHECK(count_id(OF_MSG_RANGE) >= 20);
    for (int k = 0; k < count_id(OF_MSG_RANGE); k++) {
        CHECK_EQ(range_at(k).echo_ticks, 11655);
    }
    /* Measurement numbers count triggers, so a dropped RANGE shows as a gap too. */
    uint32_t last = range_at(count_id(OF_MSG_RANGE) - 1).measurement;
    CHECK(last + 1u == fake.triggers || last + 2u == fake.triggers);
    for (int k = 1; k < count_id(OF_MSG_RANGE); k++) {
        CHECK(range_at(k).measurement > range_at(k - 1).measurement);
    }
}

static void test_time_sync(void)
{
    boot((1ull << 33) - 3000); /* near the microsecond wrap */
    run_us(500);
    clear_frames();
    uint8_t p[OF_MSG_TIME_SYNC_LEN];
    of_time_sync_t ts = {0xCAFEF00Du};
    uint32_t at = hal_micros();
    send_cmd(OF_MSG_TIME_SYNC, p, of_time_sync_pack(&ts, p));
    run_us(5000);
    take();
    const of_frame_t *f = nth(OF_MSG_TIME_SYNC_REPLY, 0);
    CHECK(f != NULL);
    of_time_sync_reply_t r;
    CHECK(of_time_sync_reply_unpack(&r, f->payload, f->len));
    CHECK_EQ(r.token, 0xCAFEF00Du);
    CHECK_EQ(r.rx_us, at);
    CHECK(r.tx_us - r.rx_us < 100);
}

static void test_heartbeat_and_state(void)
{
    boot(0);
    run_us(3500000);
    take();
    CHECK_EQ(count_id(OF_MSG_HEARTBEAT), 3);
    for (int k = 0; k < 3; k++) {
        of_heartbeat_t h;
        const of_frame_t *f = nth(OF_MSG_HEARTBEAT, k);
        CHECK(of_heartbeat_unpack(&h, f->payload, f->len));
        CHECK_EQ(h.uptime_ms, 1000u * (uint32_t)(k + 1));
        CHECK_EQ(h.state, OF_RUN_STATE_RUNNING);
        CHECK_EQ(h.rx_errors, 0);
        CHECK_EQ(h.tx_overruns, 0);
        CHECK_EQ(h.frames_sent, (uint32_t)(f - frames)); /* every frame before it, none lost */
        CHECK_EQ(f->seq, (uint8_t)(f - frames));
    }
    /* STOP: ACK, no RANGE afterwards, heartbeat says stopped; START resumes. */
    clear_frames();
    send_cmd(OF_MSG_STOP, NULL, 0);
    run_us(1000);
    take();
    CHECK_EQ(frames[0].msg_id, OF_MSG_ACK);
    CHECK_EQ(frames[0].payload[0], OF_MSG_STOP);
    clear_frames();
    uint32_t triggers = fake.triggers;
    run_us(1500000);
    take();
    CHECK_EQ(count_id(OF_MSG_RANGE), 0);
    CHECK_EQ(fake.triggers, triggers);
    of_heartbeat_t h;
    CHECK(of_heartbeat_unpack(&h, nth(OF_MSG_HEARTBEAT, 0)->payload, OF_MSG_HEARTBEAT_LEN));
    CHECK_EQ(h.state, OF_RUN_STATE_STOPPED);
    clear_frames();
    send_cmd(OF_MSG_START, NULL, 0);
    run_us(200000);
    take();
    CHECK_EQ(frames[0].msg_id, OF_MSG_ACK);
    CHECK_EQ(frames[0].payload[0], OF_MSG_START);
    CHECK(count_id(OF_MSG_RANGE) >= 3);

    /* A corrupted frame is counted in rx_errors; heartbeat_ms 0 turns heartbeats off. */
    static const uint8_t junk[] = {0x05, 0x43, 0x11, 0x22, 0x33, 0x00};
    fake_rx_bytes(junk, sizeof junk);
    run_us(1000);
    CHECK_EQ(app.rx_errors, 1);
    send_set_config(60, 1, 23324, 40000, 0);
    run_us(1000);
    clear_frames();
    run_us(3000000);
    take();
    CHECK_EQ(count_id(OF_MSG_HEARTBEAT), 0);
    CHECK(count_id(OF_MSG_RANGE) >= 45);
}

/* Feeds the whole encoded frame (COBS + 0x00) to the receive ring, each 0x00 stamped. */
static void rx_put_frame(of_rx_ring_t *rx, uint8_t id, uint8_t seq, uint32_t stamp)
{
    uint8_t buf[OF_MAX_FRAME];
    size_t n = of_frame_encode(buf, sizeof buf, id, seq, NULL, 0);
    for (size_t i = 0; i < n; i++) {
        of_rx_put(rx, buf[i], stamp);
    }
}

/* Drains the ring through a frame decoder; counts frames and errors, keeps the last. */
static void rx_drain(of_rx_ring_t *rx, of_frame_decoder_t *d, int *good, int *bad,
                     of_frame_t *last, uint32_t *last_stamp)
{
    uint8_t b;
    uint32_t stamp = 0;
    while (of_rx_get(rx, &b, &stamp)) {
        of_feed_result_t r = of_frame_decoder_feed(d, b, last);
        if (r == OF_FEED_FRAME) {
            (*good)++;
            *last_stamp = stamp;
        } else if (r == OF_FEED_ERROR) {
            (*bad)++;
        }
    }
}

static void test_ring_basics(void)
{
    /* A fresh ring is empty; it holds exactly its size; all-or-nothing puts; FIFO order
     * across the index wrap. */
    static volatile uint8_t buf[8];
    for (int i = 0; i < 8; i++) {
        buf[i] = 0xEE; /* what a fresh ring must never hand out */
    }
    of_ring_t r;
    uint8_t b;
    of_ring_init(&r, buf, sizeof buf);
    CHECK_EQ(of_ring_count(&r), 0);
    CHECK_EQ(of_ring_free(&r), 8);
    CHECK(!of_ring_get(&r, &b));
    uint8_t next_in = 0, next_out = 0;
    for (int round = 0; round < 100; round++) {
        uint8_t n = (uint8_t)(1 + round % 8);
        uint8_t data[8];
        for (uint8_t i = 0; i < n; i++) {
            data[i] = next_in++;
        }
        CHECK(of_ring_put(&r, data, n));
        CHECK(!of_ring_put(&r, data, (uint8_t)(of_ring_free(&r) + 1u)));
        CHECK_EQ(of_ring_count(&r), n);
        for (uint8_t i = 0; i < n; i++) {
            CHECK(of_ring_get(&r, &b));
            CHECK_EQ(b, next_out++);
        }
        CHECK(!of_ring_get(&r, &b));
    }
}

static void test_rx_flood(void)
{
    /* A host flood overflows the 64-byte receive ring: frames are lost, but a delimiter
     * that found no room still ends its frame, so the command after the flood is decoded
     * (issue 13, defect 1: every later command is answered). */
    static volatile uint8_t buf[64];
    of_rx_ring_t rx;
    of_frame_decoder_t d;
    of_frame_t f;
    int good = 0, bad = 0;
    uint32_t stamp = 0;
    of_rx_init(&rx, buf, sizeof buf);
    of_frame_decoder_init(&d);
    /* 12 GET_INFO frames of 5 bytes, 5-byte delimiter records: 64 bytes hold 6 of them. */
    for (uint8_t i = 0; i < 12; i++) {
        rx_put_frame(&rx, OF_MSG_GET_INFO, i, 1000u + i);
    }
    CHECK(rx.delim_lost);
    CHECK_EQ(rx.delim_us, 1011u); /* the newest lost delimiter's own stamp */
    rx_drain(&rx, &d, &good, &bad, &f, &stamp);
    CHECK(good >= 5);
    /* The next command arrives: the remembered delimiter goes in first and ends the
     * frame cut short, so the command decodes on its own, with its own stamp. */
    rx_put_frame(&rx, OF_MSG_TIME_SYNC, 0x77, 5000u);
    CHECK(!rx.delim_lost);
    int good2 = 0;
    rx_drain(&rx, &d, &good2, &bad, &f, &stamp);
    CHECK_EQ(good2, 1);
    CHECK_EQ(f.msg_id, OF_MSG_TIME_SYNC);
    CHECK_EQ(f.seq, 0x77);
    CHECK_EQ(stamp, 5000u);
    CHECK(bad >= 1); /* the cut frame is counted, not lost silently */
    /* A byte that meets a full ring is dropped; a single put never overfills it. */
    for (int i = 0; i < 100; i++) {
        of_rx_put(&rx, 0x55, 0);
    }
    CHECK_EQ(of_ring_count(&rx.ring), 64u);
    /* A delimiter arriving while a lost one still waits keeps the newer stamp. */
    of_rx_put(&rx, 0, 7000u);
    of_rx_put(&rx, 0, 7100u);
    CHECK(rx.delim_lost);
    CHECK_EQ(rx.delim_us, 7100u);
    uint8_t b;
    for (int i = 0; i < 10; i++) {
        CHECK(of_rx_get(&rx, &b, &stamp));
    }
    of_rx_put(&rx, 0x42, 0);
    CHECK(!rx.delim_lost);
    uint8_t seen[64];
    int n = 0;
    while (of_rx_get(&rx, &b, &stamp)) {
        seen[n++] = b;
    }
    CHECK_EQ(n, 54 + 1 + 1);       /* 54 old bytes, the delimiter (its stamp read), 0x42 */
    CHECK_EQ(seen[54], 0);
    CHECK_EQ(stamp, 7100u);
    CHECK_EQ(seen[55], 0x42);
    /* Every byte of a stamp survives the ring, and a data byte leaves the stamp alone. */
    static const uint32_t stamps[] = {0xF1E2D3C4u, 0x01020304u, 0x80000001u, 0xFFFFFFFFu};
    for (unsigned k = 0; k < 4; k++) {
        of_rx_put(&rx, 0x33, 0xDEADBEEFu);
        of_rx_put(&rx, 0, stamps[k]);
        stamp = 0x55555555u;
        CHECK(of_rx_get(&rx, &b, &stamp));
        CHECK_EQ(b, 0x33);
        CHECK_EQ(stamp, 0x55555555u);
        CHECK(of_rx_get(&rx, &b, &stamp));
        CHECK_EQ(b, 0);
        CHECK_EQ(stamp, stamps[k]);
        CHECK(!of_rx_get(&rx, &b, &stamp));
    }
}

static void test_gap_never_under_cycle(void)
{
    /* Issue 13, defect 10 c: a trigger held back a little (here 0.7 ms, by the guard
     * after a long echo) must not keep its phase, or the next, on-time trigger follows
     * it by less than the cycle (28.3 ms at 29 ms). Widths alternate long / short so
     * late and on-time triggers alternate. */
    boot(0);
    max_sleep_ticks = 200; /* a busy board: polled every 100 us, the guard must still hold */
    send_set_config(29, 1, 23324, 28000, 0);
    /* rise 460 us after TRIG's start; fall + 2 ms guard = 0.7 ms past the next due time */
    const uint32_t late_width = (29000u + 700u - 2000u - 460u) * 2u;
    for (int i = 0; i < 16; i++) {
        fake.width_queue[i] = (i % 2) ? 2000u : late_width;
    }
    fake.queue_len = 16;
    run_us(700000);
    take();
    CHECK_EQ(fake.ignored_triggers, 0);
    CHECK(fake.triggers >= 20);
    uint64_t shortest = UINT64_MAX, longest = 0;
    for (uint32_t k = 2; k < fake.triggers && k < 64; k++) {
        uint64_t gap = fake.trigger_at[k] - fake.trigger_at[k - 1];
        shortest = gap < shortest ? gap : shortest;
        longest = gap > longest ? gap : longest;
    }
    CHECK(shortest >= 58000u);          /* never under 29 ms (2 ticks per us) */
    CHECK(longest >= 58000u + 1200u);   /* the late ones really were held back ~0.7 ms */
    CHECK(longest <= 58000u + 1600u);   /* ...and no more than that */
}

static void test_encode_bounds(void)
{
    /* of_frame_encode() needs len + 6 bytes (COBS overhead and delimiter): exactly that
     * is enough, one byte less is refused with nothing written past it, for every length
     * up to OF_MAX_PAYLOAD; longer payloads and unknown ids are refused. */
    uint8_t payload[OF_MAX_PAYLOAD + 1];
    uint8_t buf[OF_MAX_FRAME + 16];
    for (size_t i = 0; i < sizeof payload; i++) {
        payload[i] = (uint8_t)(0x11u + i); /* no zero: the frame is exactly len + 6 */
    }
    for (size_t len = 0; len <= OF_MAX_PAYLOAD; len++) {
        memset(buf, 0xA5, sizeof buf);
        CHECK_EQ(of_frame_encode(buf, len + 5u, OF_MSG_LOG, 7, payload, len), 0);
        CHECK_EQ(buf[len + 5u], 0xA5);
        size_t n = of_frame_encode(buf, len + 6u, OF_MSG_LOG, 7, payload, len);
        CHECK_EQ(n, len + 6u);
        CHECK_EQ(buf[n - 1u], 0);
        CHECK_EQ(buf[n], 0xA5); /* nothing past the frame */
        of_frame_decoder_t d;
        of_frame_t f;
        of_frame_decoder_init(&d);
        of_feed_result_t r = OF_FEED_NONE;
        for (size_t i = 0; i < n; i++) {
            r = of_frame_decoder_feed(&d, buf[i], &f);
        }
        CHECK_EQ(r, OF_FEED_FRAME);
        CHECK_EQ(f.len, len);
        CHECK(memcmp(f.payload, payload, len) == 0);
    }
    CHECK_EQ(of_frame_encode(buf, sizeof buf, OF_MSG_LOG, 7, payload, OF_MAX_PAYLOAD + 1u), 0);
    CHECK_EQ(of_frame_encode(buf, sizeof buf, 0x7F, 7, payload, 1), 0);
    /* The largest frame fits OF_MAX_FRAME + delimiter: the receive buffer takes it. */
    CHECK_EQ(of_frame_encode(buf, sizeof buf, OF_MSG_LOG, 7, payload, OF_MAX_PAYLOAD),
             OF_MAX_FRAME + 0u);
}

static void test_timeout_boundaries(void)
{
    /* The ranger's timeouts to the microsecond and the tick, polled by hand: ECHO not
     * risen `echo_timeout_us` after the trigger is not yet a timeout, one microsecond
     * later it is; high for exactly the timeout's ticks is not yet, one tick more is. */
    of_ranger_t r;
    of_ranger_config_t cfg = {60000u, 23324u, 40000u, 1u};
    of_range_t out;
    uint32_t wake;

    fake_reset(0);
    fake.sensor[0].width_ticks = FAKE_NEVER; /* ECHO never rises */
    of_ranger_init(&r);
    fake_advance_to(10000);
    of_ranger_start(&r, hal_micros());
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake)); /* ECHO seen low: the guard starts */
    CHECK_EQ(fake.triggers, 0);
    fake_advance_to(10000u + OF_GUARD_US * 2u);
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake)); /* guard over: triggers */
    CHECK_EQ(fake.triggers, 1);
    uint64_t t0 = fake.trigger_at[0];
    CHECK_EQ(wake, r.trigger_us + 40000u + 1u);
    fake_advance_to(t0 + 40000u * 2u);
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake));
    fake_advance_to(t0 + 40000u * 2u + 2u);
    CHECK(of_ranger_poll(&r, &cfg, &out, &wake));
    CHECK_EQ(out.status, OF_RANGE_STATUS_TIMEOUT);
    CHECK_EQ(out.echo_ticks, 0);

    fake_reset(0);
    fake.sensor[0].width_ticks = 200000u; /* rises, falls far too late */
    fake.capture_latency = 0;
    of_ranger_init(&r);
    fake_advance_to(10000);
    of_ranger_start(&r, hal_micros());
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake));
    fake_advance_to(10000u + OF_GUARD_US * 2u);
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake));
    CHECK_EQ(fake.triggers, 1);
    uint64_t rise = fake.trigger_at[0] + 20u + fake.sensor[0].burst_ticks;
    fake_advance_to(rise + 80000u); /* high for exactly 40000 us */
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake));
    CHECK_EQ(r.state, OF_RANGER_WAIT_FALL);
    CHECK_EQ(wake, hal_micros() + 1u);
    fake_advance_to(rise + 80001u);
    CHECK(of_ranger_poll(&r, &cfg, &out, &wake));
    CHECK_EQ(out.status, OF_RANGE_STATUS_TIMEOUT);
    CHECK_EQ(out.echo_ticks, 80001u); /* the ticks measured so far */
}

static void test_next_sensor_exhaustive(void)
{
    /* From power-up, the round robin starts with the lowest sensor of the mask. */
    for (uint8_t mask = 1; mask < 16; mask++) {
        of_ranger_t r;
        of_ranger_init(&r);
        uint8_t lowest = 0;
        while (!(mask & (1u << lowest))) {
            lowest++;
        }
        CHECK_EQ(of_ranger_next_sensor(mask, r.last_sensor), lowest);
    }
    /* Round robin against a reference for every mask and position, including a mask of
     * one sensor only (the next after `last` is `last` itself). */
    for (uint8_t mask = 1; mask < 16; mask++) {
        for (uint8_t last = 0; last < 4; last++) {
            uint8_t want = 0xFF;
            for (uint8_t i = 1; i <= 4 && want == 0xFF; i++) {
                uint8_t s = (uint8_t)((last + i) % 4);
                if (mask & (1u << s)) {
                    want = s;
                }
            }
            CHECK_EQ(of_ranger_next_sensor(mask, last), want);
        }
    }
}

static void test_ranger_wake_times(void)
{
    /* The ranger's answer to "when must I be called again?" in each state, exactly: a
     * later wake delays a trigger or a report, an earlier one wastes a poll. */
    of_ranger_t r;
    of_ranger_config_t cfg = {60000u, 23324u, 40000u, 1u};
    of_range_t out;
    uint32_t wake;

    fake_reset(0);
    of_ranger_init(&r);
    fake_advance_to(10000);
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake)); /* not running */
    CHECK_EQ(wake, hal_micros() + 1000000u);
    of_ranger_start(&r, hal_micros() + 300u);
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake)); /* not due yet */
    CHECK_EQ(wake, r.next_due_us);
    fake_advance_to(10000u + 600u);                /* due, low for 300 us only */
    uint32_t low_since = r.low_since_us;
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake));
    CHECK_EQ(fake.triggers, 0);
    CHECK_EQ(wake, low_since + OF_GUARD_US);
    fake.echo_high = true;                         /* the line goes high: look again in 1 ms */
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake));
    CHECK_EQ(wake, hal_micros() + 1000u);
    fake.echo_high = false;
    uint32_t seen_low = hal_micros();
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake));
    CHECK_EQ(wake, seen_low + OF_GUARD_US);
    fake_advance_to(fake.now + OF_GUARD_US * 2u);
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake)); /* triggers */
    CHECK_EQ(fake.triggers, 1);
    CHECK_EQ(wake, r.trigger_us + 40000u + 1u);
    CHECK_EQ(r.next_due_us, r.trigger_us + 60000u);
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake)); /* waiting for the rise */
    CHECK_EQ(wake, r.trigger_us + 40000u + 1u);
    fake_advance_to(fake.now + 1000u);             /* risen 450 us after the pulse */
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake));
    CHECK_EQ(r.state, OF_RANGER_WAIT_FALL);
    uint32_t high_for = hal_ticks() - r.rise_ticks;
    CHECK_EQ(wake, hal_micros() + (80000u - high_for) / 2u + 1u);
}

static void test_rise_between_two_looks(void)
{
    /* The echo timeout is due, but the rise is captured between the ranger's two looks
     * at the edges: it is judged on the next poll (an echo), not reported as a timeout. */
    of_ranger_t r;
    of_ranger_config_t cfg = {60000u, 23324u, 40000u, 1u};
    of_range_t out;
    uint32_t wake;
    fake_reset(0);
    fake.sensor[0].width_ticks = FAKE_NEVER;
    of_ranger_init(&r);
    fake_advance_to(10000);
    of_ranger_start(&r, hal_micros());
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake));
    fake_advance_to(10000u + OF_GUARD_US * 2u);
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake));
    CHECK_EQ(fake.triggers, 1);
    fake_advance_to(fake.trigger_at[0] + 40001u * 2u);
    fake.rise_in_edges_call = 2;
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake));
    CHECK_EQ(wake, hal_micros());
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake));
    CHECK_EQ(r.state, OF_RANGER_WAIT_FALL);
}

static void test_stuck_echo_boundary(void)
{
    /* ECHO high all the time (a hung sensor, a floating line): the firmware triggers
     * anyway exactly OF_STUCK_ECHO_US after the due time, not a microsecond earlier. */
    of_ranger_t r;
    of_ranger_config_t cfg = {60000u, 23324u, 40000u, 1u};
    of_range_t out;
    uint32_t wake;
    fake_reset(0);
    of_ranger_init(&r);
    fake.echo_high = true;
    fake_advance_to(10000);
    uint32_t due = hal_micros();
    of_ranger_start(&r, due);
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake));
    fake_advance_to(10000u + (OF_STUCK_ECHO_US - 1u) * 2u);
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake));
    CHECK_EQ(fake.triggers, 0);
    fake_advance_to(10000u + OF_STUCK_ECHO_US * 2u);
    CHECK(!of_ranger_poll(&r, &cfg, &out, &wake));
    CHECK_EQ(fake.triggers, 1);
    CHECK_EQ(r.trigger_us, due + OF_STUCK_ECHO_US);
}

static void test_app_poll_limits_and_wake(void)
{
    /* At most OF_RX_BYTES_PER_POLL received bytes are decoded per poll (a flood cannot
     * hold the ranger off), and the poll asks to be woken for the earlier of the ranger's
     * and the heartbeat's next deadline. */
    boot(0);
    run_us(1000);
    static uint8_t junk[100];
    memset(junk, 0x41, sizeof junk);
    uint16_t before = fake.rx_tail;
    fake_rx_bytes(junk, sizeof junk);
    (void)of_app_poll(&app);
    CHECK_EQ((uint16_t)(fake.rx_tail - before), OF_RX_BYTES_PER_POLL);
    (void)of_app_poll(&app);
    CHECK_EQ((uint16_t)(fake.rx_tail - before), 2u * OF_RX_BYTES_PER_POLL);

    /* uptime_ms counts whole milliseconds since power-up, to the microsecond */
    boot(0);
    fake_advance_to(1999u * 2u);
    (void)of_app_poll(&app);
    CHECK_EQ(app.uptime_ms, 1);
    fake_advance_to(2000u * 2u);
    (void)of_app_poll(&app);
    CHECK_EQ(app.uptime_ms, 2);

    boot(0);
    send_cmd(OF_MSG_STOP, NULL, 0);
    run_us(1000);
    uint32_t wake = of_app_poll(&app); /* stopped: the heartbeat is the only deadline */
    CHECK_EQ(wake, app.next_heartbeat_us);
    CHECK_EQ(app.next_heartbeat_us, true_us(0) + 1000000u);
    send_set_config(60, 1, 23324, 40000, 0); /* no heartbeat: the ranger's idle second */
    run_us(1000);
    send_cmd(OF_MSG_STOP, NULL, 0);
    run_us(1000);
    wake = of_app_poll(&app);
    CHECK_EQ(wake, hal_micros() + 1000000u);
    send_cmd(OF_MSG_START, NULL, 0);
    uint32_t t_start = hal_micros(); /* the next poll takes START and looks at the line */
    run_us(100);
    wake = of_app_poll(&app); /* due now; STOP forgot the line's history: the guard */
    CHECK_EQ(wake, t_start + OF_GUARD_US);
    run_us(OF_GUARD_US);
    CHECK_EQ(fake.triggers, 1);
    wake = of_app_poll(&app); /* waiting for the rise */
    CHECK_EQ(wake, app.ranger.trigger_us + 40000u + 1u);
}

static void test_heartbeat_schedule(void)
{
    /* SET_CONFIG restarts the heartbeat period from its own arrival; after a stall of
     * several periods (no poll), one heartbeat goes out and the next follows a whole
     * period later: no burst. */
    boot(0);
    run_us(300000);
    send_set_config(60, 1, 23324, 40000, 250);
    uint32_t t_cfg = hal_micros(); /* the next poll takes it */
    run_us(2);
    CHECK_EQ(app.next_heartbeat_us, t_cfg + 250000u);
    clear_frames();
    run_us(1000000);
    take();
    CHECK_EQ(count_id(OF_MSG_HEARTBEAT), 4);
    for (int k = 0; k < 4; k++) {
        of_heartbeat_t h;
        CHECK(of_heartbeat_unpack(&h, nth(OF_MSG_HEARTBEAT, k)->payload, OF_MSG_HEARTBEAT_LEN));
        uint32_t at = t_cfg + 250000u * (uint32_t)(k + 1);
        /* uptime counts whole ms since power-up (true_us(0)); a heartbeat may wait up to
         * 1 ms for a trigger that is due */
        CHECK(h.uptime_ms >= (at - true_us(0)) / 1000u);
        CHECK(h.uptime_ms <= (at - true_us(0)) / 1000u + 2u);
    }
    clear_frames();
    uint64_t stall_from = fake.now;
    fake_advance_to(fake.now + 2u * 1100000u); /* 1.1 s without a poll */
    run_us(100);
    take();
    CHECK_EQ(count_id(OF_MSG_HEARTBEAT), 1);
    of_heartbeat_t h;
    CHECK(of_heartbeat_unpack(&h, nth(OF_MSG_HEARTBEAT, 0)->payload, OF_MSG_HEARTBEAT_LEN));
    CHECK_EQ(h.uptime_ms, (uint32_t)(fake_us(stall_from + 2u * 1100000u) / 1000u));
    clear_frames();
    run_us(240000);
    take();
    CHECK_EQ(count_id(OF_MSG_HEARTBEAT), 0);
    run_us(20000);
    take();
    CHECK_EQ(count_id(OF_MSG_HEARTBEAT), 1);
}

static void test_decoder_edges(void)
{
    /* An unknown id is an error whatever its CRC (here one seeded as if its extra were
     * 0xFF, i.e. -1), and the firmware answers nothing. */
    of_frame_decoder_t d;
    of_frame_t f;
    uint8_t body[6] = {0x30, 0x05, 0xAA, 0xBB, 0, 0};
    uint16_t crc = of_crc16_update(OF_CRC_INIT, 0xFF);
    for (int i = 0; i < 4; i++) {
        crc = of_crc16_update(crc, body[i]);
    }
    body[4] = (uint8_t)(crc >> 8);
    body[5] = (uint8_t)crc;
    uint8_t cobs[8];
    size_t w = 1, code_at = 0;
    uint8_t code = 1;
    for (int i = 0; i < 6; i++) {
        if (body[i] == 0) {
            cobs[code_at] = code;
            code_at = w++;
            code = 1;
        } else {
            cobs[w++] = body[i];
            code++;
        }
    }
    cobs[code_at] = code;
    of_frame_decoder_init(&d);
    for (size_t i = 0; i < w; i++) {
        CHECK_EQ(of_frame_decoder_feed(&d, cobs[i], &f), OF_FEED_NONE);
    }
    CHECK_EQ(of_frame_decoder_feed(&d, 0x00, &f), OF_FEED_ERROR);
    /* ...and the firmware stays silent about it, counting an rx error. */
    boot(0);
    run_us(1000);
    clear_frames();
    fake_rx_bytes(cobs, (uint16_t)w);
    static const uint8_t zero = 0;
    fake_rx_bytes(&zero, 1);
    run_us(1000);
    take();
    CHECK_EQ(app.rx_errors, 1);
    CHECK_EQ(count_id(OF_MSG_NACK), 0);
}

static void test_heartbeat_waits_for_a_due_trigger(void)
{
    /* A heartbeat due less than 1 ms before a trigger goes out after it (on the Uno,
     * encoding it takes a few hundred us, which would push the trigger). Here the
     * heartbeat period restarts 0.5 ms before the ranging period does, because the guard
     * holds the trigger after SET_CONFIG back by that much. */
    boot(0);
    while (fake.last_fall_at == 0) {
        run_us(100);
    }
    uint64_t fall_us = fake_us(fake.last_fall_at);
    run_us(fall_us + 1500u - fake_us(fake.now));
    CHECK_EQ(fake.triggers, 1);
    send_set_config(100, 1, 23324, 40000, 100);
    clear_frames();
    while (fake.triggers < 3) {
        run_us(5);
        take();
        CHECK(fake.triggers == 3 || count_id(OF_MSG_HEARTBEAT) == 0);
    }
    CHECK_EQ(fake.triggers, 3);
    run_us(50);
    take();
    CHECK_EQ(count_id(OF_MSG_HEARTBEAT), 1); /* right after the trigger */
    /* A trigger due in 1 ms or more does not hold the heartbeat back: force the case by
     * polling by hand at exactly 1000 us before the next due time, heartbeat overdue. */
    while (app.ranger.state != OF_RANGER_IDLE) { /* the echo ends */
        run_us(100);
    }
    clear_frames();
    app.next_heartbeat_us = hal_micros();
    fake_advance_to(fake.now + 2u * (app.ranger.next_due_us - hal_micros() - 1000u));
    CHECK_EQ(app.ranger.next_due_us - hal_micros(), 1000u);
    (void)of_app_poll(&app);
    take();
    CHECK_EQ(count_id(OF_MSG_HEARTBEAT), 1);
    /* the trigger kept its period from the one the guard held back */
    CHECK(fake.trigger_at[2] - fake.trigger_at[1] >= 200000u - 1u);
    CHECK(fake.trigger_at[2] - fake.trigger_at[1] <= 200000u + 40u);
}

/* ------------------------------------------------------------------ runner */

struct test {
    const char *name;
    void (*fn)(void);
};

static const struct test tests[] = {
    {"ticks_pure", test_ticks_pure},
    {"power_up", test_power_up},
    {"normal_echo", test_normal_echo},
    {"status_boundaries", test_status_boundaries},
    {"no_echo", test_no_echo},
    {"echo_never_falls", test_echo_never_falls},
    {"overflow_during_echo", test_overflow_during_echo},
    {"micros_wrap", test_micros_wrap},
    {"back_to_back", test_back_to_back},
    {"config_validation", test_config_validation},
    {"tx_overrun", test_tx_overrun},
    {"time_sync", test_time_sync},
    {"heartbeat_and_state", test_heartbeat_and_state},
    {"ring_basics", test_ring_basics},
    {"rx_flood", test_rx_flood},
    {"gap_never_under_cycle", test_gap_never_under_cycle},
    {"encode_bounds", test_encode_bounds},
    {"timeout_boundaries", test_timeout_boundaries},
    {"next_sensor_exhaustive", test_next_sensor_exhaustive},
    {"ranger_wake_times", test_ranger_wake_times},
    {"stuck_echo_boundary", test_stuck_echo_boundary},
    {"rise_between_two_looks", test_rise_between_two_looks},
    {"app_poll_limits_and_wake", test_app_poll_limits_and_wake},
    {"heartbeat_schedule", test_heartbeat_schedule},
    {"decoder_edges", test_decoder_edges},
    {"heartbeat_waits_for_a_due_trigger", test_heartbeat_waits_for_a_due_trigger},
};

int main(int argc, char **argv)
{
    size_t n = sizeof tests / sizeof tests[0];
    if (argc == 2 && strcmp(argv[1], "--list") == 0) {
        for (size_t i = 0; i < n; i++) {
            printf("%s\n", tests[i].name);
        }
        return 0;
    }
    int ran = 0;
    for (size_t i = 0; i < n; i++) {
        if (argc < 2 || strcmp(argv[1], tests[i].name) == 0) {
            tests[i].fn();
            ran++;
            printf("%s: %s\n", tests[i].name, failures ? "FAIL" : "ok");
            if (failures) {
                return 1;
            }
        }
    }
    if (ran == 0) {
        printf("no test named %s\n", argv[1]);
        return 2;
    }
    return 0;
}
