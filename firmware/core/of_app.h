/* The firmware application: protocol in and out, command handling, heartbeat, and the
 * ranger. Portable; boards call of_app_init() once and of_app_poll() from their loop. */
#ifndef OF_APP_H
#define OF_APP_H

#include <stdbool.h>
#include <stdint.h>

#include "of_frame.h"
#include "of_protocol.h"
#include "of_ranger.h"

#define OF_FW_MAJOR 1u
#define OF_FW_MINOR 0u
#define OF_FW_PATCH 0u

/* At most this many received bytes are decoded per poll, so a flood of input cannot
 * hold off the ranger for long. */
#define OF_RX_BYTES_PER_POLL 32u

typedef struct {
    of_set_config_t cfg;     /* configuration in force, always valid */
    of_ranger_t ranger;
    of_frame_decoder_t decoder;
    uint8_t tx_seq;          /* seq of the next frame; advances even when one is dropped */
    uint32_t frames_sent;
    uint32_t rx_errors;
    uint32_t tx_overruns;
    uint32_t uptime_ms;
    uint32_t uptime_mark_us; /* hal_micros() up to which uptime_ms is counted */
    uint32_t next_heartbeat_us;
} of_app_t;

/* Sends HELLO then CONFIG (then a LOG warning after a watchdog reset) and starts ranging
 * with the default configuration. */
void of_app_init(of_app_t *app);

/* Does all pending work; returns the time by which it wants to be called again. */
uint32_t of_app_poll(of_app_t *app);

/* Validates a whole SET_CONFIG in the documented order; OF_ERROR_NONE if acceptable. */
uint8_t of_app_validate(const of_set_config_t *c, uint8_t sensor_count);

/* Handles one received frame; rx_us is when its last byte arrived. */
void of_app_handle_frame(of_app_t *app, const of_frame_t *f, uint32_t rx_us);

#endif /* OF_APP_H */
