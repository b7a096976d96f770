/* Ranging state machine and scheduler; see of_ranger.h. */
#include "of_ranger.h"

#include "hal.h"
#include "of_ticks.h"

/* While waiting on the ECHO line (guard, stuck line) look again this often. */
#define OF_RANGER_RECHECK_US 1000UL

void of_ranger_init(of_ranger_t *r)
{
    r->state = OF_RANGER_IDLE;
    r->running = 0;
    r->sensor = 0;
    r->last_sensor = (uint8_t)(OF_MAX_SENSORS - 1u);
    r->measurement = 0;
    r->triggers = 0;
    r->trigger_us = 0;
    r->rise_ticks = 0;
    r->next_due_us = 0;
    r->low_since_us = 0;
    r->low_seen = 0;
}

void of_ranger_start(of_ranger_t *r, uint32_t now_us)
{
    if (!r->running) {
        r->running = 1;
        r->next_due_us = now_us;
    }
}

void of_ranger_stop(of_ranger_t *r)
{
    if (r->state != OF_RANGER_IDLE) {
        hal_echo_disarm();
        r->state = OF_RANGER_IDLE;
    }
    r->running = 0;
    r->low_seen = 0;
}

uint8_t of_ranger_next_sensor(uint8_t mask, uint8_t last)
{
    for (uint8_t i = 1; i <= OF_MAX_SENSORS; i++) {
        uint8_t s = (uint8_t)((last + i) % OF_MAX_SENSORS);
        if (mask & (1u << s)) {
            return s;
        }
    }
    return 0;
}

uint8_t of_ranger_classify(uint32_t ticks, uint32_t max_echo_us, uint32_t ticks_per_us)
{
    if (ticks >= OF_NO_ECHO_MIN_US * ticks_per_us) {
        return OF_RANGE_STATUS_NO_ECHO;
    }
    if (ticks > max_echo_us * ticks_per_us) {
        return OF_RANGE_STATUS_OUT_OF_RANGE;
    }
    return OF_RANGE_STATUS_OK;
}

static bool finish(of_ranger_t *r, of_range_t *out, uint32_t ticks, uint8_t status,
                   uint32_t now_us)
{
    hal_echo_disarm();
    r->state = OF_RANGER_IDLE;
    out->measurement = r->measurement;
    out->sensor_id = r->sensor;
    out->trigger_us = r->trigger_us;
    out->echo_ticks = ticks;
    out->status = status;
    r->low_seen = !hal_echo_is_high();
    r->low_since_us = now_us;
    return true;
}

/* IDLE: trigger when due, ECHO has been low for the guard time, or ECHO looks stuck. */
static void poll_idle(of_ranger_t *r, const of_ranger_config_t *cfg, uint32_t now,
                      uint32_t *wake_us)
{
    if (hal_echo_is_high()) {
        r->low_seen = 0;
    } else if (!r->low_seen) {
        r->low_seen = 1;
        r->low_since_us = now;
    }
    if (!of_time_reached(now, r->next_due_us)) {
        *wake_us = r->next_due_us;
        return;
    }
    bool guard_ok = r->low_seen && (now - r->low_since_us) >= OF_GUARD_US;
    bool stuck = (now - r->next_due_us) >= OF_STUCK_ECHO_US;
    if (!guard_ok && !stuck) {
        *wake_us = r->low_seen ? r->low_since_us + OF_GUARD_US : now + OF_RANGER_RECHECK_US;
        return;
    }
    r->sensor = of_ranger_next_sensor(cfg->sensor_mask, r->last_sensor);
    r->last_sensor = r->sensor;
    r->measurement = r->triggers++;
    r->trigger_us = hal_trigger(r->sensor);
    r->state = OF_RANGER_WAIT_RISE;
    r->low_seen = 0;
    /* The period counts from this trigger's own stamp: the next one is never closer than
     * the cycle (the spec's min_cycle_ms is a physical floor), however little this one
     * was held back (guard, stuck line, start, the poll's own latency). Keeping the phase
     * instead would pay a late trigger back with a short gap. */
    r->next_due_us = r->trigger_us + cfg->cycle_us;
    *wake_us = r->trigger_us + cfg->echo_timeout_us + 1u;
}

bool of_ranger_poll(of_ranger_t *r, const of_ranger_config_t *cfg, of_range_t *out,
                    uint32_t *wake_us)
{
    uint32_t now = hal_micros();
    *wake_us = now + 1000000UL;
    if (r->state == OF_RANGER_IDLE) {
        if (r->running) {
            poll_idle(r, cfg, now, wake_us);
        }
        return false;
    }
    uint32_t rise = 0;
    uint32_t fall = 0;
    uint32_t ticks = 0;
    uint8_t edges = hal_echo_edges(&rise, &fall);
    if (edges == 1u) {
        r->state = OF_RANGER_WAIT_FALL;
        r->rise_ticks = rise;
        uint32_t limit = cfg->echo_timeout_us * HAL_TICKS_PER_US;
        ticks = hal_ticks() - rise;
        if (ticks <= limit) {
            *wake_us = now + (limit - ticks) / HAL_TICKS_PER_US + 1u;
            return false;
        }
        /* Timed out, unless the fall slipped in after the first look. */
        edges = hal_echo_edges(&rise, &fall);
    } else if (edges == 0u) {
        if (now - r->trigger_us <= cfg->echo_timeout_us) {
            *wake_us = r->trigger_us + cfg->echo_timeout_us + 1u;
            return false;
        }
        if (hal_echo_edges(&rise, &fall) > 0u) {
            *wake_us = now; /* an edge arrived just now: judge it on the next poll */
            return false;
        }
    }
    uint8_t status = OF_RANGE_STATUS_TIMEOUT; /* no rise: 0 ticks; no fall: ticks so far */
    if (edges >= 2u) {
        ticks = fall - rise;
        status = of_ranger_classify(ticks, cfg->max_echo_us, HAL_TICKS_PER_US);
    }
    return finish(r, out, ticks, status, now);
}
