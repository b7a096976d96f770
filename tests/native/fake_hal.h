/* A simulated board behind hal.h: a 16-bit timer with an overflow interrupt whose
 * service can be delayed, an HC-SR04 per sensor, and UART rings. Time only moves when a
 * test says so, so every edge lands on a chosen tick. */
#ifndef FAKE_HAL_H
#define FAKE_HAL_H

#include <stdbool.h>
#include <stdint.h>

#include "of_frame.h"

#define FAKE_NEVER UINT64_MAX

typedef struct {
    uint64_t burst_ticks;  /* TRIG fall to ECHO rise */
    uint64_t width_ticks;  /* ECHO high time; FAKE_NEVER: ECHO never rises */
} fake_sensor_t;

typedef struct {
    /* timing model */
    uint64_t now;               /* true time in ticks since the simulated power-up */
    uint64_t start_offset;      /* ticks already elapsed on the timer at power-up */
    uint32_t capture_latency;   /* ticks from an edge to its capture interrupt */
    uint32_t ovf_isr_delay;     /* ticks from a wrap to its overflow interrupt */
    /* sensors */
    fake_sensor_t sensor[4];
    uint8_t busy_sensor;        /* 0xFF none */
    uint64_t rise_at, fall_at;  /* pending ECHO edges (true ticks), FAKE_NEVER if none */
    bool echo_high;
    uint32_t triggers;          /* TRIG pulses sent */
    uint32_t ignored_triggers;  /* TRIG pulses while a measurement was still running */
    uint64_t trigger_at[64];    /* true tick of each TRIG rise (first 64) */
    uint8_t trigger_sensor[64];
    uint32_t width_queue[16];   /* if queue_len: widths for successive triggers */
    uint8_t queue_len, queue_pos;
    /* capture unit as the Uno ISR keeps it */
    uint8_t echo_state;         /* 0 off, 1 wait rise, 2 wait fall, 3 done */
    uint32_t cap_rise, cap_fall;
    uint32_t pending_captures;  /* captures taken while an overflow was still pending */
    uint64_t last_fall_at;      /* true tick of the latest ECHO fall */
    uint32_t rise_in_edges_call; /* hook: ECHO rises (and is captured) just before the Nth
                                    hal_echo_edges() call from now, as an interrupt between
                                    two looks would have it (0: off) */
    /* UART */
    uint8_t rx[1024];
    uint32_t rx_stamp[1024];
    uint16_t rx_head, rx_tail;
    uint16_t tx_capacity;       /* bytes the TX ring holds (the Uno has 128) */
    uint8_t tx[4096];
    uint16_t tx_len;
    uint32_t idle_calls;
    bool watchdog_reset;        /* what hal_reset_by_watchdog() reports */
} fake_board_t;

extern fake_board_t fake;

void fake_reset(uint64_t start_offset_ticks);

/* Ticks -> true microseconds since power-up on the fake clock. */
uint64_t fake_us(uint64_t ticks);

/* Advances true time to `t`, firing ECHO edges (capture interrupts) on the way. */
void fake_advance_to(uint64_t t);

/* Queues a frame from the host; its delimiter is stamped when read by the core. */
void fake_rx_frame(uint8_t msg_id, uint8_t seq, const uint8_t *payload, uint8_t len);
void fake_rx_bytes(const uint8_t *data, uint16_t n);

/* Decodes and removes everything the firmware transmitted so far. Returns how many
 * frames went into out (at most cap); *errors (if given) counts bad frames. */
int fake_tx_take(of_frame_t *out, int cap, int *errors);

#endif /* FAKE_HAL_H */
