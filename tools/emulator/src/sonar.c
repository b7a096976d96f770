/* HC-SR04 behaviour: a trigger of >= 10 us starts a measurement; after the burst delay
 * ECHO is high for exactly 2 d / v (or the ~38 ms no-echo pulse), d being the distance
 * when the burst meets the face. Both edges are cycle
 * timers at their exact cycle, and a truth-log line records what was sent. */
#include "sonar.h"

#include <math.h>

#include "avr_ioport.h"
#include "sim_cycle_timers.h"

/* Fixed-point passes for the distance at the reflection instant (start_measurement). */
#define REFLECTION_PASSES 3

void sonar_default_params(sonar_params_t *p)
{
    p->trig_port = 'B';
    p->trig_pin = 1;
    p->echo_port = 'B';
    p->echo_pin = 0;
    p->burst_us = 450.0;
    p->min_trig_us = 10.0;
    p->no_echo_us = 38000.0;
    p->max_range_m = 4.0;
    p->noise_mm = 0.0;
    p->dropout_p = 0.0;
    p->spike_p = 0.0;
    p->clock_ppm = 0.0;
    p->exact_edges = 1;
}

static double mcu_rate(const sonar_t *s)
{
    return (double)s->avr->frequency * (1.0 + s->p.clock_ppm * 1e-6);
}

double sonar_true_time(const sonar_t *s, avr_cycle_count_t cycle)
{
    return (double)cycle / mcu_rate(s);
}

/* Drive ECHO as if the edge happened at cycle `when`. simavr runs timers after the
 * instruction that crosses `when`, a few cycles late; the input-capture unit reads the
 * cycle counter, so we present the scheduled cycle for the duration of the edge. */
static void drive_echo(sonar_t *s, avr_cycle_count_t when, int level)
{
    echo_line_t *line = s->line;
    if (level) {
        if (line->high++ > 0)
            return;   /* another sensor already holds the line high */
    } else {
        if (line->high == 0 || --line->high > 0)
            return;
    }
    avr_t *avr = s->avr;
    avr_cycle_count_t now = avr->cycle;
    if (s->p.exact_edges && when <= now)
        avr->cycle = when;
    avr_raise_irq(line->irq, (uint32_t)level);
    avr->cycle = now;
}

static void write_truth(sonar_t *s)
{
    if (!s->truth)
        return;
    double f = (double)s->avr->frequency;
    double echo_true_s = (double)s->m_echo_cycles / mcu_rate(s);
    fprintf(s->truth, "%llu %.9f %.9f %.3f %.6f %.6f %.2f %s %llu %llu %llu %d\n",
            (unsigned long long)s->m_index,
            (double)s->m_trig_cycle / f,
            echo_true_s,
            (double)s->m_echo_cycles * 2e6 / f,
            s->m_distance,
            s->m_echo_distance,
            s->m_temperature,
            s->m_kind,
            (unsigned long long)s->m_trig_cycle,
            (unsigned long long)s->m_rise_cycle,
            (unsigned long long)s->m_echo_cycles,
            s->id);
    fflush(s->truth);
}

static avr_cycle_count_t echo_fall(avr_t *avr, avr_cycle_count_t when, void *param)
{
    sonar_t *s = param;
    (void)avr;
    drive_echo(s, when, 0);
    s->busy = 0;
    write_truth(s);
    s->measurements++;
    return 0;
}

static avr_cycle_count_t echo_rise(avr_t *avr, avr_cycle_count_t when, void *param)
{
    sonar_t *s = param;
    (void)avr;
    drive_echo(s, when, 1);
    return 0;
}

static void start_measurement(sonar_t *s, avr_cycle_count_t trig_cycle)
{
    const sonar_params_t *p = &s->p;
    double rate = mcu_rate(s);
    avr_cycle_count_t burst = (avr_cycle_count_t)llround(p->burst_us * 1e-6 * rate);
    s->m_temperature = s->scene->temperature_c;
    double v = sound_speed(s->m_temperature);
    /* The burst leaves as ECHO rises and meets the face d / v later: a moving face is
     * measured where it stands at that instant (1.5 m away, 4.4 ms after the burst), not
     * at the trigger. d depends on the instant, so settle it in a few passes; at robot
     * speeds the second already moves it by well under a micrometre. */
    double t_leave = sonar_true_time(s, s->avr->cycle + burst);
    double d = NAN;
    int have = scene_distance(s->scene, t_leave, &d) == 0;
    for (int pass = 0; have && pass < REFLECTION_PASSES; pass++)
        have = scene_distance(s->scene, t_leave + d / v, &d) == 0;
    s->m_distance = have ? d : NAN;
    double echo_s;
    const char *kind = "echo";
    double ed = have ? d : NAN;
    if (rng_chance(s->rng, p->dropout_p)) {
        kind = "dropout";
        ed = NAN;
    } else if (rng_chance(s->rng, p->spike_p)) {
        kind = "spike";
        ed = 0.02 + rng_uniform(s->rng) * (p->max_range_m - 0.02);
    } else if (have && p->noise_mm > 0.0) {
        ed = d + rng_gauss(s->rng) * p->noise_mm * 1e-3;
        if (ed < 0.005)
            ed = 0.005;
    }
    if (isnan(ed) || ed > p->max_range_m) {
        if (ed > p->max_range_m)
            kind = "beyond";
        else if (!have && kind[0] == 'e')
            kind = "none";
        ed = NAN;
        echo_s = p->no_echo_us * 1e-6;
    } else {
        echo_s = 2.0 * ed / v;
    }
    s->m_echo_distance = ed;
    s->m_kind = kind;
    avr_cycle_count_t width = (avr_cycle_count_t)llround(echo_s * rate);
    if (width < 1)
        width = 1;
    s->m_index = s->line->started++;
    s->m_trig_cycle = trig_cycle;
    s->m_rise_cycle = s->avr->cycle + burst;
    s->m_echo_cycles = width;
    s->busy = 1;
    avr_cycle_timer_register(s->avr, burst, echo_rise, s);
    avr_cycle_timer_register(s->avr, burst + width, echo_fall, s);
}

static void trig_changed(avr_irq_t *irq, uint32_t value, void *param)
{
    sonar_t *s = param;
    (void)irq;
    avr_cycle_count_t now = s->avr->cycle;
    if (value && !s->trig_high) {
        s->trig_high = 1;
        s->trig_rise = now;
        return;
    }
    if (!value && s->trig_high) {
        s->trig_high = 0;
        double width_us = (double)(now - s->trig_rise) * 1e6 / (double)s->avr->frequency;
        if (s->busy) {
            s->ignored_triggers++;
        } else if (width_us + 1e-9 < s->p.min_trig_us) {
            s->short_triggers++;
        } else {
            start_measurement(s, s->trig_rise);
        }
    }
}

void sonar_truth_header(FILE *truth)
{
    fprintf(truth, "# of-emulator truth log v1: one line per measurement, at ECHO fall\n"
                   "# index trigger_s echo_s echo_ticks distance_m echo_distance_m "
                   "temperature_c kind trigger_cycle rise_cycle echo_cycles sensor\n");
    fflush(truth);
}

int sonar_attach(sonar_t *s, int id, echo_line_t *line, avr_t *avr, const sonar_params_t *p,
                 scene_t *scene, rng_t *rng, FILE *truth)
{
    s->avr = avr;
    s->id = id;
    s->line = line;
    s->p = *p;
    s->scene = scene;
    s->rng = rng;
    s->truth = truth;
    s->trig_high = 0;
    s->busy = 0;
    s->measurements = 0;
    s->ignored_triggers = 0;
    s->short_triggers = 0;
    avr_irq_t *trig = avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(p->trig_port), p->trig_pin);
    if (!line->irq) {
        line->irq = avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(p->echo_port), p->echo_pin);
        line->high = 0;
        line->started = 0;
    }
    if (!trig || !line->irq)
        return -1;
    avr_irq_register_notify(trig, trig_changed, s);
    return 0;
}

void sonar_rearm(sonar_t *s)
{
    if (!s->busy)
        return;
    avr_t *avr = s->avr;
    avr_cycle_count_t now = avr->cycle;
    avr_cycle_count_t rise = s->m_rise_cycle;
    avr_cycle_count_t fall = rise + s->m_echo_cycles;
    if (now < rise) {
        avr_cycle_timer_register(avr, rise - now, echo_rise, s);
        avr_cycle_timer_register(avr, fall - now, echo_fall, s);
    } else if (now < fall) {
        avr_raise_irq(s->line->irq, s->line->high > 0);
        avr_cycle_timer_register(avr, fall - now, echo_fall, s);
    } else {
        echo_fall(avr, now, s);
    }
}
