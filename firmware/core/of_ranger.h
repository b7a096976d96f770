/* The ranging state machine and its scheduler: one measurement at a time, sensors taken
 * in round robin, a fixed trigger period with a cross-talk guard. Times come from the
 * HAL; the decisions here are portable and tested on the host with a fake HAL. */
#ifndef OF_RANGER_H
#define OF_RANGER_H

#include <stdbool.h>
#include <stdint.h>

#include "of_protocol.h"

/* ECHO must have been low this long after a measurement before any sensor is
 * triggered again: the previous ping's sound and the sensor's own pulse are over. */
#define OF_GUARD_US 2000UL
/* If ECHO stays high this long past the due time (a stuck line or a missing sensor),
 * trigger anyway so the host sees timeouts instead of silence. */
#define OF_STUCK_ECHO_US 100000UL

typedef enum {
    OF_RANGER_IDLE = 0,  /* waiting for the next due time and the guard */
    OF_RANGER_WAIT_RISE, /* triggered, ECHO not yet risen */
    OF_RANGER_WAIT_FALL  /* ECHO high, waiting for it to fall */
} of_ranger_state_t;

/* The timing part of the configuration the ranger obeys. */
typedef struct {
    uint32_t cycle_us;        /* trigger period (any sensor) */
    uint32_t max_echo_us;     /* longer echoes are out_of_range */
    uint32_t echo_timeout_us; /* no rise, or no fall, within this is a timeout */
    uint8_t sensor_mask;      /* sensors taken in turn */
} of_ranger_config_t;

typedef struct {
    uint8_t state;       /* of_ranger_state_t */
    uint8_t running;     /* 0 after stop */
    uint8_t sensor;      /* sensor of the measurement in progress */
    uint8_t last_sensor; /* round robin position */
    uint32_t measurement; /* number of the measurement in progress (or last) */
    uint32_t triggers;    /* triggers so far: the next measurement's number */
    uint32_t trigger_us;
    uint32_t rise_ticks;
    uint32_t next_due_us; /* next trigger time */
    uint32_t low_since_us; /* ECHO seen low (and no measurement running) since then */
    uint8_t low_seen;      /* low_since_us is valid */
} of_ranger_t;

void of_ranger_init(of_ranger_t *r);

/* Starts ranging: the first trigger is due at now_us (guard permitting). */
void of_ranger_start(of_ranger_t *r, uint32_t now_us);

/* Stops ranging; a measurement in progress is abandoned without a report. */
void of_ranger_stop(of_ranger_t *r);

/* Runs the state machine. Returns true when a measurement finished and *out holds it.
 * *wake_us gets the latest time the next call is needed (an echo edge wakes earlier). */
bool of_ranger_poll(of_ranger_t *r, const of_ranger_config_t *cfg, of_range_t *out,
                    uint32_t *wake_us);

/* Classifies a finished pulse of `ticks` (ticks_per_us per microsecond). */
uint8_t of_ranger_classify(uint32_t ticks, uint32_t max_echo_us, uint32_t ticks_per_us);

/* The next sensor after `last` in mask (round robin); mask must be nonzero. */
uint8_t of_ranger_next_sensor(uint8_t mask, uint8_t last);

#endif /* OF_RANGER_H */
