/* A virtual HC-SR04 wired to two MCU pins: TRIG in, ECHO out. */
#ifndef OF_EMU_SONAR_H
#define OF_EMU_SONAR_H

#include <stdint.h>
#include <stdio.h>

#include "sim_avr.h"
#include "sim_irq.h"

#include "rng.h"
#include "scene.h"

typedef struct {
    char trig_port;       /* 'B' */
    int trig_pin;         /* 1 */
    char echo_port;       /* 'B' */
    int echo_pin;         /* 0 */
    double burst_us;      /* trigger fall to ECHO rise */
    double min_trig_us;   /* shortest accepted trigger pulse */
    double no_echo_us;    /* ECHO pulse when nothing answers */
    double max_range_m;   /* farther obstacles give the no-echo pulse */
    double noise_mm;      /* Gaussian sigma on the distance */
    double dropout_p;     /* probability of a no-echo pulse */
    double spike_p;       /* probability of an echo from a random distance */
    double clock_ppm;     /* MCU crystal error: MCU time = true time * (1 + ppm) */
    int exact_edges;      /* present edges to the timers at their scheduled cycle */
} sonar_params_t;

#define SONAR_MAX 4

/* Several sensors share one ECHO pin through an OR gate (firmware/README.md): the line is
 * high while any sensor drives it high. */
typedef struct {
    avr_irq_t *irq;
    int high;           /* sensors driving it high */
    uint64_t started;   /* measurements started by all sensors: the truth log's index */
} echo_line_t;

typedef struct {
    avr_t *avr;
    int id;             /* sensor number, 0..SONAR_MAX-1 */
    echo_line_t *line;
    sonar_params_t p;
    scene_t *scene;
    rng_t *rng;
    FILE *truth;
    /* trigger */
    int trig_high;
    avr_cycle_count_t trig_rise;
    /* measurement in flight */
    int busy;
    uint64_t m_index;
    avr_cycle_count_t m_trig_cycle;
    avr_cycle_count_t m_rise_cycle;
    avr_cycle_count_t m_echo_cycles;
    double m_distance;        /* scene distance, NAN when none */
    double m_echo_distance;   /* distance that produced the echo, NAN for no-echo */
    double m_temperature;
    const char *m_kind;
    /* counters */
    uint64_t measurements;
    uint64_t ignored_triggers;   /* during a measurement */
    uint64_t short_triggers;     /* shorter than min_trig_us */
} sonar_t;

void sonar_default_params(sonar_params_t *p);
/* Attach sensor `id` to the MCU's pins (its TRIG from p, ECHO onto the shared line, set up
 * on first use); truth may be NULL. Returns -1 if a pin does not exist. */
int sonar_attach(sonar_t *s, int id, echo_line_t *line, avr_t *avr, const sonar_params_t *p,
                 scene_t *scene, rng_t *rng, FILE *truth);
/* The truth log's header lines. */
void sonar_truth_header(FILE *truth);
/* After an MCU reset (simavr drops all cycle timers): the sensor is outside the MCU, so
 * a pulse in flight goes on; schedule its remaining edges again. */
void sonar_rearm(sonar_t *s);
/* Cycles to seconds of true time, taking the crystal error into account. */
double sonar_true_time(const sonar_t *s, avr_cycle_count_t cycle);

#endif
