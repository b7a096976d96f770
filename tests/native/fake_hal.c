/* The simulated board behind hal.h; see fake_hal.h. Timer readings go through the same
 * of_ticks.h arithmetic as the Uno's ISRs, with the overflow interrupt's service delayed
 * by fake.ovf_isr_delay ticks, so a pending overflow is exercised for real. */
#include "fake_hal.h"

#include <string.h>

#include "hal.h"
#include "of_ticks.h"

#define TRIG_TICKS 20u  /* the 10 us pulse */
#define TX_BYTE_TICKS 174u /* one 8N1 byte at 115200 baud, in 0.5 us ticks */

fake_board_t fake;
static uint64_t tx_next_done;
static uint16_t tx_level;

void fake_reset(uint64_t start_offset_ticks)
{
    memset(&fake, 0, sizeof fake);
    fake.start_offset = start_offset_ticks;
    fake.capture_latency = 12;
    fake.ovf_isr_delay = 6;
    for (int i = 0; i < 4; i++) {
        fake.sensor[i].burst_ticks = 900;     /* 450 us, as an HC-SR04 */
        fake.sensor[i].width_ticks = 11655;   /* about 1 m */
    }
    fake.busy_sensor = 0xFF;
    fake.rise_at = FAKE_NEVER;
    fake.fall_at = FAKE_NEVER;
    fake.tx_capacity = 128;
    tx_next_done = 0;
    tx_level = 0;
}

uint64_t fake_us(uint64_t ticks)
{
    return ticks / HAL_TICKS_PER_US;
}

/* The timer seen at raw time T: counter, overflows serviced, overflow pending. */
static void timer_at(uint64_t T, uint16_t *count, uint32_t *ovf, bool *pending)
{
    uint64_t serviced = T >= fake.ovf_isr_delay ? (T - fake.ovf_isr_delay) >> 16 : 0;
    *count = (uint16_t)T;
    *ovf = (uint32_t)serviced;
    *pending = (T >> 16) > serviced;
}

static uint64_t raw(uint64_t t)
{
    return fake.start_offset + t;
}

/* The Uno's capture interrupt for an edge at true time t, new level `high`. It runs
 * capture_latency ticks after the edge; an overflow whose interrupt had not run by the
 * edge is still pending then, because the capture vector has the higher priority. */
static void capture(uint64_t t, bool high)
{
    uint64_t T = raw(t);
    uint16_t value = (uint16_t)T;
    uint16_t ignored;
    uint32_t ovf;
    bool pending;
    timer_at(T, &ignored, &ovf, &pending);
    pending = ((T + fake.capture_latency) >> 16) > ovf;
    uint32_t ticks = of_ticks_extend(ovf, value, pending);
    if (pending) {
        fake.pending_captures++;
    }
    if (fake.echo_state == 1 && high) {
        fake.cap_rise = ticks;
        fake.echo_state = 2;
    } else if (fake.echo_state == 2 && !high) {
        fake.cap_fall = ticks;
        fake.echo_state = 3;
    }
}

static void drain_tx(uint64_t t)
{
    while (tx_level > 0 && tx_next_done <= t) {
        tx_level--;
        tx_next_done += TX_BYTE_TICKS;
    }
}

void fake_advance_to(uint64_t t)
{
    for (;;) {
        uint64_t next = fake.rise_at < fake.fall_at ? fake.rise_at : fake.fall_at;
        if (next == FAKE_NEVER || next > t) {
            break;
        }
        fake.now = next;
        drain_tx(next);
        if (next == fake.rise_at) {
            fake.rise_at = FAKE_NEVER;
            fake.echo_high = true;
            capture(next, true);
        } else {
            fake.fall_at = FAKE_NEVER;
            fake.echo_high = false;
            fake.busy_sensor = 0xFF;
            fake.last_fall_at = next;
            capture(next, false);
        }
    }
    if (t > fake.now) {
        fake.now = t;
    }
    drain_tx(fake.now);
}

void fake_rx_bytes(const uint8_t *data, uint16_t n)
{
    for (uint16_t i = 0; i < n; i++) {
        uint16_t h = fake.rx_head % sizeof fake.rx;
        fake.rx[h] = data[i];
        fake.rx_stamp[h] = hal_micros();
        fake.rx_head++;
    }
}

void fake_rx_frame(uint8_t msg_id, uint8_t seq, const uint8_t *payload, uint8_t len)
{
    uint8_t buf[OF_MAX_FRAME + 8];
    size_t n = of_frame_encode(buf, sizeof buf, msg_id, seq, payload, len);
    fake_rx_bytes(buf, (uint16_t)n);
}

int fake_tx_take(of_frame_t *out, int cap, int *errors)
{
    of_frame_decoder_t d;
    of_frame_decoder_init(&d);
    int n = 0;
    int bad = 0;
    of_frame_t f;
    for (uint16_t i = 0; i < fake.tx_len; i++) {
        of_feed_result_t r = of_frame_decoder_feed(&d, fake.tx[i], &f);
        if (r == OF_FEED_FRAME && n < cap) {
            out[n++] = f;
        } else if (r == OF_FEED_ERROR) {
            bad++;
        }
    }
    if (d.len != 0) {
        bad++; /* a partial frame left at the end */
    }
    fake.tx_len = 0;
    if (errors) {
        *errors = bad;
    }
    return n;
}

/* ---- hal.h ---- */

void hal_init(void)
{
}

uint32_t hal_cpu_hz(void)
{
    return 16000000UL;
}

uint32_t hal_micros(void)
{
    uint16_t c;
    uint32_t o;
    bool p;
    timer_at(raw(fake.now), &c, &o, &p);
    return of_ticks_micros(o, c, p, 1);
}

uint32_t hal_ticks(void)
{
    uint16_t c;
    uint32_t o;
    bool p;
    timer_at(raw(fake.now), &c, &o, &p);
    return of_ticks_extend(o, c, p);
}

uint32_t hal_trigger(uint8_t sensor)
{
    uint32_t us = hal_micros();
    uint32_t i = fake.triggers++;
    if (i < 64) {
        fake.trigger_at[i] = fake.now;
        fake.trigger_sensor[i] = sensor;
    }
    fake.echo_state = 1;
    if (fake.busy_sensor != 0xFF || fake.echo_high) {
        fake.ignored_triggers++; /* the sensor is still measuring: it ignores TRIG */
    } else {
        uint64_t width = fake.sensor[sensor & 3].width_ticks;
        if (fake.queue_len) {
            uint32_t w = fake.width_queue[fake.queue_pos++ % fake.queue_len];
            width = w == UINT32_MAX ? FAKE_NEVER : w;
        }
        if (width != FAKE_NEVER) {
            fake.busy_sensor = sensor;
            fake.rise_at = fake.now + TRIG_TICKS + fake.sensor[sensor & 3].burst_ticks;
            fake.fall_at = fake.rise_at + width;
        }
    }
    fake_advance_to(fake.now + TRIG_TICKS); /* the busy-wait pulse takes its time */
    return us;
}

uint8_t hal_echo_edges(uint32_t *rise_ticks, uint32_t *fall_ticks)
{
    if (fake.rise_in_edges_call != 0 && --fake.rise_in_edges_call == 0) {
        fake.echo_high = true;
        capture(fake.now, true);
    }
    *rise_ticks = fake.cap_rise;
    *fall_ticks = fake.cap_fall;
    return fake.echo_state == 3 ? 2u : (fake.echo_state == 2 ? 1u : 0u);
}

void hal_echo_disarm(void)
{
    fake.echo_state = 0;
}

bool hal_echo_is_high(void)
{
    return fake.echo_high;
}

bool hal_uart_read(uint8_t *byte, uint32_t *stamp_us)
{
    if (fake.rx_tail == fake.rx_head) {
        return false;
    }
    uint16_t t = fake.rx_tail % sizeof fake.rx;
    *byte = fake.rx[t];
    if (*byte == 0) {
        *stamp_us = fake.rx_stamp[t];
    }
    fake.rx_tail++;
    return true;
}

bool hal_uart_write(const uint8_t *data, uint8_t n)
{
    drain_tx(fake.now);
    if ((uint32_t)tx_level + n > fake.tx_capacity) {
        return false;
    }
    if (tx_level == 0) {
        tx_next_done = fake.now + TX_BYTE_TICKS;
    }
    tx_level = (uint16_t)(tx_level + n);
    for (uint8_t i = 0; i < n && fake.tx_len < sizeof fake.tx; i++) {
        fake.tx[fake.tx_len++] = data[i];
    }
    return true;
}

void hal_idle_until(uint32_t wake_us)
{
    (void)wake_us;
    fake.idle_calls++;
}

bool hal_reset_by_watchdog(void)
{
    return fake.watchdog_reset;
}

void hal_watchdog_kick(void)
{
}
