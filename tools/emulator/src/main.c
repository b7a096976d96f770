/* of-emulator: run the unmodified firmware ELF under simavr, with a virtual HC-SR04 on
 * its TRIG/ECHO pins and USART0 on a pseudo-terminal, paced to wall-clock time or as fast
 * as possible. Usage and the control commands: tools/emulator/README.md. */
#define _GNU_SOURCE
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>
#include <unistd.h>

#include "sim_avr.h"
#include "sim_elf.h"
#include "sim_cycle_timers.h"

#include "bootloader.h"
#include "control.h"
#include "quirks.h"
#include "rng.h"
#include "scene.h"
#include "sonar.h"
#include "uart_bridge.h"

typedef struct {
    /* options */
    const char *elf;
    bootloader_t boot;              /* --bootloader: Optiboot at the reset vector */
    const char *mcu;
    unsigned long freq;
    int fast;
    double clock_ppm;
    double duration_s;
    double service_us;
    int wait_client;
    double client_grace_ms;
    int reset_on_open;
    int optiboot;           /* hand the reset cause over in r2 with MCUSR cleared */
    int exit_with_parent;
    pid_t parent;
    const char *truth_path;
    const char *pty_file;
    const char *control_path;
    const char *scene_path;
    const char *sensor_scene[SONAR_MAX]; /* --sensor-scene K:FILE, after --scene */
    uint64_t seed;
    int verbose;
    /* state */
    avr_t *avr;
    int nsensors;
    int ntrig;                      /* --trig options given */
    char trig_port[SONAR_MAX];
    int trig_pin[SONAR_MAX];
    scene_t scene[SONAR_MAX];       /* what each sensor faces */
    rng_t rng_sonar;
    rng_t rng_uart;
    echo_line_t echo_line;
    sonar_t sonar[SONAR_MAX];
    sonar_params_t sp;
    uart_bridge_t bridge;
    uart_faults_t faults;
    quirks_t quirks;
    int model_rx_overrun;
    int uart_rate_fix;
    int tx_timer_armed;
    control_t control;
    int have_control;
    FILE *truth;
    avr_cycle_count_t service_cycles;
    /* pacing */
    struct timespec wall0;
    avr_cycle_count_t cycle0;
    double max_lag_s;
    /* requests from the control channel or signals, handled between instructions */
    int reset_requested;    /* 1: reset button (EXTRF), 2: as if the watchdog fired (WDRF) */
    uint8_t reset_cause;    /* MCUSR bits of the reset being handled */
    int quit_requested;
    uint64_t resets;
    uint64_t ticks;
} emu_t;

static emu_t g_emu;
static volatile sig_atomic_t g_signal;
static void (*g_core_reset)(avr_t *avr);
static int g_core_was_reset;

static void on_signal(int sig)
{
    g_signal = sig;
}

/* The reset cause register of the ATmega48/88/168/328 (MCUSR, I/O 0x34 = data 0x54). */
#define MCUSR_ADDR 0x54
enum { MCUSR_PORF = 0x01, MCUSR_EXTRF = 0x02, MCUSR_WDRF = 0x08 };

static int has_mcusr(const avr_t *avr)
{
    static const char *const parts[] = {"atmega48", "atmega88", "atmega168", "atmega328"};
    for (size_t i = 0; i < sizeof parts / sizeof parts[0]; i++) {
        if (!strncmp(avr->mmcu, parts[i], strlen(parts[i])))
            return 1;
    }
    return 0;
}

/* Adds `cause` to MCUSR as the chip would (simavr 1.6 sets only WDRF, and only for its own
 * watchdog), then, with --optiboot, does what Optiboot does before it jumps to the
 * application: MCUSR into r2, MCUSR cleared (so the application reads its reset cause
 * from r2, the convention of Optiboot >= 4.6). Runs before the first instruction. */
static void hand_over(emu_t *e, uint8_t cause)
{
    if (!has_mcusr(e->avr))
        return;
    uint8_t mcusr = (uint8_t)(e->avr->data[MCUSR_ADDR] | cause);
    if (e->optiboot) {
        e->avr->data[2] = mcusr;
        mcusr = 0;
    }
    e->avr->data[MCUSR_ADDR] = mcusr;
}

static void die(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("of-emulator: error: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    exit(2);
}

static void note(const emu_t *e, const char *fmt, ...)
{
    if (!e->verbose)
        return;
    va_list ap;
    va_start(ap, fmt);
    fputs("of-emulator: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

static void simavr_logger(avr_t *avr, const int level, const char *fmt, va_list ap)
{
    (void)avr;
    if (level > (g_emu.verbose >= 2 ? LOG_TRACE : LOG_ERROR))
        return;
    fputs("simavr: ", stderr);
    vfprintf(stderr, fmt, ap);
}

static double now_s(const struct timespec *t)
{
    return (double)t->tv_sec + (double)t->tv_nsec * 1e-9;
}

static double sim_seconds(const emu_t *e)
{
    return (double)e->avr->cycle / (double)e->avr->frequency;
}

/* ------------------------------------------------------------------ option parsing */

static double parse_num(const char *opt, const char *s, double lo, double hi)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || end == s || *end || !isfinite(v) || v < lo || v > hi)
        die("%s: '%s' is not a number in [%g, %g]", opt, s, lo, hi);
    return v;
}

/* "D9", "PB1" or "B1" -> port letter and bit (Arduino Uno numbering for D/A). */
static void parse_pin(const char *opt, const char *s, char *port, int *pin)
{
    char *end;
    if ((s[0] == 'D' || s[0] == 'd') && s[1]) {
        long n = strtol(s + 1, &end, 10);
        if (*end == '\0' && n >= 0 && n <= 13) {
            *port = n < 8 ? 'D' : 'B';
            *pin = (int)(n < 8 ? n : n - 8);
            return;
        }
    }
    if ((s[0] == 'A' || s[0] == 'a') && s[1] >= '0' && s[1] <= '5' && !s[2]) {
        *port = 'C';
        *pin = s[1] - '0';
        return;
    }
    const char *p = s;
    if ((p[0] == 'P' || p[0] == 'p') && p[1] && p[2])
        p++;
    char letter = (char)(p[0] & ~0x20);
    if (letter >= 'A' && letter <= 'L' && p[1] >= '0' && p[1] <= '7' && !p[2]) {
        *port = letter;
        *pin = p[1] - '0';
        return;
    }
    die("%s: '%s' is not a pin (use D0..D13, A0..A5, or PB1 style)", opt, s);
}

static void usage(FILE *f)
{
    fputs(
        "usage: of-emulator [options] FIRMWARE.elf\n"
        "       of-emulator --bootloader BOOT.hex [options] [FIRMWARE.elf]\n"
        "Runs the firmware under simavr with a virtual HC-SR04 and USART0 on a pty.\n"
        "Prints the pty path on stdout.\n\n"
        "world:\n"
        "  --distance M|none     constant obstacle distance (default 1.0)\n"
        "  --scene FILE          keyframe file: `<time_s> <distance_m|none>` lines\n"
        "  --sensor-scene K:FILE sensor K's own keyframe file (after --scene)\n"
        "  --temperature C       air temperature (default 20)\n"
        "  --noise-mm MM         Gaussian distance noise, sigma (default 0)\n"
        "  --dropout P           probability of a no-echo pulse (default 0)\n"
        "  --spike P             probability of an echo from a random distance (default 0)\n"
        "sensor:\n"
        "  --sensors N           sensors 1..4 sharing ECHO through an OR gate (default 1)\n"
        "  --trig PIN            TRIG of the next sensor (default D9, D10, D11, D12)\n"
        "  --echo PIN            the shared ECHO pin (default D8 = PB0, ICP1)\n"
        "  --burst-us US         trigger fall to ECHO rise (default 450)\n"
        "  --no-echo-us US       ECHO pulse when nothing answers (default 38000)\n"
        "  --max-range M         farther obstacles give no echo (default 4.0)\n"
        "  --min-trigger-us US   shortest trigger accepted (default 10)\n"
        "time:\n"
        "  --fast                run as fast as possible instead of real time\n"
        "  --clock-ppm N         the MCU crystal runs N ppm fast (negative: slow)\n"
        "  --duration S          stop after S simulated seconds\n"
        "  --service-us US       I/O and pacing interval (default 200, fast mode 1000)\n"
        "uart:\n"
        "  --uart-drop P --uart-corrupt P --uart-insert P   fault rates per byte\n"
        "  --fault-dir tx|rx|both  direction of faults (default tx = MCU to host)\n"
        "  --wait-client         hold the MCU in reset until a client opens the pty\n"
        "  --client-grace-ms MS  then wait this long before starting (default 100)\n"
        "  --reset-on-open       reset the MCU whenever a client opens the pty (like DTR)\n"
        "  --optiboot            start the firmware as Optiboot does: MCUSR cleared, the\n"
        "                        reset cause in r2 (ATmega48/88/168/328)\n"
        "  --exit-with-parent    stop when the process that started us goes away\n"
        "files:\n"
        "  --truth FILE          truth log, one line per measurement\n"
        "  --pty-file FILE       also write the pty path here\n"
        "  --control PATH        UNIX socket for live commands (see README)\n"
        "other:\n"
        "  --bootloader HEX      start every reset in this bootloader (BOOTRST), e.g. the\n"
        "                        Uno's Optiboot; the ELF (the application) is optional\n"
        "  --mcu NAME --freq HZ  when the ELF does not say (default atmega328p, 16000000)\n"
        "  --seed N              random seed for noise and faults (default 1)\n"
        "  --no-quirk-fixes      run simavr 1.6 as it is (see README)\n"
        "  -v, --verbose         diagnostics on stderr (-vv: simavr trace)\n",
        f);
}

static void parse_args(emu_t *e, int argc, char **argv)
{
    enum {
        O_DIST = 256, O_SCENE, O_TEMP, O_NOISE, O_DROPOUT, O_SPIKE, O_TRIG, O_ECHO, O_BURST,
        O_NOECHO, O_MAXR, O_MINTRIG, O_FAST, O_PPM, O_DUR, O_SERVICE, O_UDROP, O_UCORR,
        O_UINS, O_FDIR, O_WAIT, O_GRACE, O_RESETOPEN, O_TRUTH, O_PTYFILE, O_CONTROL, O_MCU,
        O_FREQ, O_SEED, O_NOQUIRK, O_ELF, O_SENSORS, O_PARENT, O_OPTIBOOT, O_BOOT, O_SENSCENE
    };
    static const struct option opts[] = {
        {"distance", required_argument, 0, O_DIST},
        {"scene", required_argument, 0, O_SCENE},
        {"sensor-scene", required_argument, 0, O_SENSCENE},
        {"temperature", required_argument, 0, O_TEMP},
        {"noise-mm", required_argument, 0, O_NOISE},
        {"dropout", required_argument, 0, O_DROPOUT},
        {"spike", required_argument, 0, O_SPIKE},
        {"trig", required_argument, 0, O_TRIG},
        {"sensors", required_argument, 0, O_SENSORS},
        {"exit-with-parent", no_argument, 0, O_PARENT},
        {"echo", required_argument, 0, O_ECHO},
        {"burst-us", required_argument, 0, O_BURST},
        {"no-echo-us", required_argument, 0, O_NOECHO},
        {"max-range", required_argument, 0, O_MAXR},
        {"min-trigger-us", required_argument, 0, O_MINTRIG},
        {"fast", no_argument, 0, O_FAST},
        {"clock-ppm", required_argument, 0, O_PPM},
        {"duration", required_argument, 0, O_DUR},
        {"service-us", required_argument, 0, O_SERVICE},
        {"uart-drop", required_argument, 0, O_UDROP},
        {"uart-corrupt", required_argument, 0, O_UCORR},
        {"uart-insert", required_argument, 0, O_UINS},
        {"fault-dir", required_argument, 0, O_FDIR},
        {"wait-client", no_argument, 0, O_WAIT},
        {"client-grace-ms", required_argument, 0, O_GRACE},
        {"reset-on-open", no_argument, 0, O_RESETOPEN},
        {"optiboot", no_argument, 0, O_OPTIBOOT},
        {"truth", required_argument, 0, O_TRUTH},
        {"pty-file", required_argument, 0, O_PTYFILE},
        {"control", required_argument, 0, O_CONTROL},
        {"mcu", required_argument, 0, O_MCU},
        {"freq", required_argument, 0, O_FREQ},
        {"seed", required_argument, 0, O_SEED},
        {"no-quirk-fixes", no_argument, 0, O_NOQUIRK},
        {"elf", required_argument, 0, O_ELF},
        {"bootloader", required_argument, 0, O_BOOT},
        {"verbose", no_argument, 0, 'v'},
        {"help", no_argument, 0, 'h'},
        {0, 0, 0, 0},
    };
    double distance = 1.0;
    int none = 0;
    double temperature = 20.0;
    int c;
    while ((c = getopt_long(argc, argv, "vh", opts, NULL)) != -1) {
        switch (c) {
        case O_DIST:
            if (strcasecmp(optarg, "none") == 0)
                none = 1;
            else
                distance = parse_num("--distance", optarg, 0.0, 1000.0);
            break;
        case O_SCENE: e->scene_path = optarg; break;
        case O_SENSCENE: {
            char *colon = strchr(optarg, ':');
            char *end;
            long k = colon ? strtol(optarg, &end, 10) : -1;
            if (!colon || end != colon || k < 0 || k >= SONAR_MAX || !colon[1])
                die("--sensor-scene: '%s' is not K:FILE with K in 0..%d", optarg, SONAR_MAX - 1);
            e->sensor_scene[k] = colon + 1;
            break;
        }
        case O_TEMP: temperature = parse_num("--temperature", optarg, -100, 100); break;
        case O_NOISE: e->sp.noise_mm = parse_num("--noise-mm", optarg, 0, 10000); break;
        case O_DROPOUT: e->sp.dropout_p = parse_num("--dropout", optarg, 0, 1); break;
        case O_SPIKE: e->sp.spike_p = parse_num("--spike", optarg, 0, 1); break;
        case O_TRIG:
            if (e->ntrig == SONAR_MAX)
                die("--trig: at most %d sensors", SONAR_MAX);
            parse_pin("--trig", optarg, &e->trig_port[e->ntrig], &e->trig_pin[e->ntrig]);
            e->ntrig++;
            break;
        case O_SENSORS:
            e->nsensors = (int)parse_num("--sensors", optarg, 1, SONAR_MAX);
            break;
        case O_ECHO: parse_pin("--echo", optarg, &e->sp.echo_port, &e->sp.echo_pin); break;
        case O_BURST: e->sp.burst_us = parse_num("--burst-us", optarg, 0, 100000); break;
        case O_NOECHO: e->sp.no_echo_us = parse_num("--no-echo-us", optarg, 1, 1e6); break;
        case O_MAXR: e->sp.max_range_m = parse_num("--max-range", optarg, 0, 1000); break;
        case O_MINTRIG:
            e->sp.min_trig_us = parse_num("--min-trigger-us", optarg, 0, 1e6);
            break;
        case O_FAST: e->fast = 1; break;
        case O_PPM: e->clock_ppm = parse_num("--clock-ppm", optarg, -100000, 100000); break;
        case O_DUR: e->duration_s = parse_num("--duration", optarg, 0, 1e9); break;
        case O_SERVICE: e->service_us = parse_num("--service-us", optarg, 10, 1e6); break;
        case O_UDROP: e->faults.drop_p = parse_num("--uart-drop", optarg, 0, 1); break;
        case O_UCORR: e->faults.corrupt_p = parse_num("--uart-corrupt", optarg, 0, 1); break;
        case O_UINS: e->faults.insert_p = parse_num("--uart-insert", optarg, 0, 1); break;
        case O_FDIR:
            if (!strcmp(optarg, "tx"))
                e->faults.dirs = FAULT_TX;
            else if (!strcmp(optarg, "rx"))
                e->faults.dirs = FAULT_RX;
            else if (!strcmp(optarg, "both"))
                e->faults.dirs = FAULT_TX | FAULT_RX;
            else
                die("--fault-dir: '%s' is not tx, rx or both", optarg);
            break;
        case O_WAIT: e->wait_client = 1; break;
        case O_GRACE:
            e->client_grace_ms = parse_num("--client-grace-ms", optarg, 0, 60000);
            break;
        case O_RESETOPEN: e->reset_on_open = 1; break;
        case O_OPTIBOOT: e->optiboot = 1; break;
        case O_PARENT: e->exit_with_parent = 1; break;
        case O_TRUTH: e->truth_path = optarg; break;
        case O_PTYFILE: e->pty_file = optarg; break;
        case O_CONTROL: e->control_path = optarg; break;
        case O_MCU: e->mcu = optarg; break;
        case O_FREQ: e->freq = (unsigned long)parse_num("--freq", optarg, 1000, 1e9); break;
        case O_SEED: e->seed = (uint64_t)parse_num("--seed", optarg, 0, 9e15); break;
        case O_NOQUIRK:
            e->quirks.sei_fix = 0;
            e->quirks.tifr_fix = 0;
            e->quirks.flag_fix = 0;
            e->quirks.wdt_fix = 0;
            e->sp.exact_edges = 0;
            e->model_rx_overrun = 0;
            e->uart_rate_fix = 0;
            break;
        case O_ELF: e->elf = optarg; break;
        case O_BOOT: e->boot.path = optarg; break;
        case 'v': e->verbose++; break;
        case 'h': usage(stdout); exit(0);
        default: usage(stderr); exit(2);
        }
    }
    if (optind < argc)
        e->elf = argv[optind++];
    if (optind < argc)
        die("unexpected argument '%s'", argv[optind]);
    if (!e->elf && !e->boot.path)
        die("no firmware ELF given (usage: of-emulator [options] FIRMWARE.elf)");
    e->sp.clock_ppm = e->clock_ppm;
    if (e->nsensors == 0)
        e->nsensors = e->ntrig > 0 ? e->ntrig : 1;
    if (e->ntrig > e->nsensors)
        die("%d --trig pins given for --sensors %d", e->ntrig, e->nsensors);
    for (int k = e->ntrig; k < e->nsensors; k++) {
        /* Uno wiring (firmware/README.md): sensor k's TRIG on D9 + k. */
        e->trig_port[k] = 'B';
        e->trig_pin[k] = 1 + k;
    }
    for (int k = 0; k < SONAR_MAX; k++)
        scene_init(&e->scene[k], distance, none, temperature);
}

/* ------------------------------------------------------------------ control commands */

static int parse_prob(const char *s, double *out)
{
    char *end;
    double v = strtod(s, &end);
    if (end == s || *end || !(v >= 0.0 && v <= 1.0))
        return -1;
    *out = v;
    return 0;
}

static void cmd_stats(emu_t *e, char *reply, size_t n)
{
    const bridge_stats_t *b = &e->bridge.st;
    unsigned long long meas = 0, ignored = 0, shorts = 0;
    for (int k = 0; k < e->nsensors; k++) {
        meas += e->sonar[k].measurements;
        ignored += e->sonar[k].ignored_triggers;
        shorts += e->sonar[k].short_triggers;
    }
    snprintf(reply, n,
             "ok sim_s=%.6f cycle=%llu measurements=%llu ignored_triggers=%llu "
             "short_triggers=%llu tx_bytes=%llu tx_written=%llu tx_no_client=%llu "
             "tx_overflow=%llu rx_bytes=%llu rx_fed=%llu rx_overruns=%llu dropped=%llu "
             "corrupted=%llu inserted=%llu resets=%llu tifr_restored=%llu flags_cleared=%llu "
             "level_polls_cancelled=%llu wdt_escalations=%llu hang=%d client=%d "
             "max_lag_s=%.6f wall0_s=%.9f cycle0=%llu freq_hz=%lu uart_cycles_per_byte=%llu",
             sim_seconds(e), (unsigned long long)e->avr->cycle,
             meas, ignored, shorts, (unsigned long long)b->tx_bytes,
             (unsigned long long)b->tx_written, (unsigned long long)b->tx_no_client,
             (unsigned long long)b->tx_overflow, (unsigned long long)b->rx_bytes,
             (unsigned long long)b->rx_fed, (unsigned long long)b->rx_overruns,
             (unsigned long long)b->dropped, (unsigned long long)b->corrupted,
             (unsigned long long)b->inserted, (unsigned long long)e->resets,
             (unsigned long long)e->quirks.tifr_restored,
             (unsigned long long)e->quirks.flags_cleared,
             (unsigned long long)e->quirks.level_polls_cancelled,
             (unsigned long long)e->quirks.wdt_escalations, e->quirks.hang, e->bridge.client,
             e->max_lag_s,
             /* The pacing anchor: cycle c runs at CLOCK_MONOTONIC wall0_s + (c - cycle0) /
              * (freq_hz * (1 + ppm/1e6)), the exact host time of any MCU event. */
             now_s(&e->wall0), (unsigned long long)e->cycle0, (unsigned long)e->avr->frequency,
             (unsigned long long)bridge_cycles_per_byte(&e->bridge));
}

static void handle_command(void *ctx, char *line, char *reply, size_t n)
{
    emu_t *e = ctx;
    char *argv[20]; /* poke: address and 16 bytes */
    int argc = 0;
    char *p = strtok(line, " \t");
    for (; p && argc < 20; p = strtok(NULL, " \t"))
        argv[argc++] = p;
    if (argc == 0) {
        snprintf(reply, n, "error empty command");
        return;
    }
    if (p) {
        snprintf(reply, n, "error %s: too many arguments", argv[0]);
        return;
    }
    const char *cmd = argv[0];
    double v;
    char *end;
    /* An optional last argument picks one sensor; without it, all of them. */
    int first = 0, last = e->nsensors - 1;
    if ((!strcmp(cmd, "distance") || !strcmp(cmd, "scene")) && argc == 3) {
        long k = strtol(argv[2], &end, 10);
        if (end == argv[2] || *end || k < 0 || k >= e->nsensors) {
            snprintf(reply, n, "error %s: no sensor '%s' (0..%d)", cmd, argv[2], e->nsensors - 1);
            return;
        }
        first = last = (int)k;
        argc = 2;
    }
    if (!strcmp(cmd, "distance") && argc == 2) {
        int none = !strcasecmp(argv[1], "none");
        v = 0.0;
        if (!none) {
            v = strtod(argv[1], &end);
            if (end == argv[1] || *end || !(v >= 0.0 && v < 1000.0)) {
                snprintf(reply, n, "error distance: '%s' is not metres >= 0 or none", argv[1]);
                return;
            }
        }
        for (int k = first; k <= last; k++) {
            e->scene[k].n = 0;
            e->scene[k].constant_none = none;
            e->scene[k].constant = v;
        }
    } else if (!strcmp(cmd, "temperature") && argc == 2) {
        v = strtod(argv[1], &end);
        if (end == argv[1] || *end || !(v >= -100.0 && v <= 100.0)) {
            snprintf(reply, n, "error temperature: '%s' is not celsius in -100..100", argv[1]);
            return;
        }
        for (int k = 0; k < SONAR_MAX; k++)
            e->scene[k].temperature_c = v;
    } else if (!strcmp(cmd, "noise") && argc == 2) {
        v = strtod(argv[1], &end);
        if (end == argv[1] || *end || !(v >= 0.0 && v <= 10000.0)) {
            snprintf(reply, n, "error noise: '%s' is not millimetres >= 0", argv[1]);
            return;
        }
        for (int k = 0; k < SONAR_MAX; k++)
            e->sonar[k].p.noise_mm = v;
    } else if ((!strcmp(cmd, "dropout") || !strcmp(cmd, "spike")) && argc == 2) {
        if (parse_prob(argv[1], &v)) {
            snprintf(reply, n, "error %s: '%s' is not a probability 0..1", cmd, argv[1]);
            return;
        }
        for (int k = 0; k < SONAR_MAX; k++) {
            if (cmd[0] == 'd')
                e->sonar[k].p.dropout_p = v;
            else
                e->sonar[k].p.spike_p = v;
        }
    } else if (!strcmp(cmd, "uart") && argc == 3) {
        if (parse_prob(argv[2], &v)) {
            snprintf(reply, n, "error uart: '%s' is not a probability 0..1", argv[2]);
            return;
        }
        if (!strcmp(argv[1], "drop"))
            e->bridge.faults.drop_p = v;
        else if (!strcmp(argv[1], "corrupt"))
            e->bridge.faults.corrupt_p = v;
        else if (!strcmp(argv[1], "insert"))
            e->bridge.faults.insert_p = v;
        else {
            snprintf(reply, n, "error uart: '%s' is not drop, corrupt or insert", argv[1]);
            return;
        }
    } else if (!strcmp(cmd, "scene") && argc == 2) {
        char err[512];
        double t0 = sonar_true_time(&e->sonar[0], e->avr->cycle);
        for (int k = first; k <= last; k++) {
            if (scene_load(&e->scene[k], argv[1], t0, err, sizeof err)) {
                snprintf(reply, n, "error %s", err);
                return;
            }
        }
    } else if (!strcmp(cmd, "reset") && argc == 1) {
        e->reset_requested = 1;
    } else if (!strcmp(cmd, "reset") && argc == 2 && !strcmp(argv[1], "watchdog")) {
        if (!has_mcusr(e->avr)) {
            snprintf(reply, n, "error reset watchdog: no MCUSR model for %s", e->avr->mmcu);
            return;
        }
        e->reset_requested = 2;
    } else if (!strcmp(cmd, "hang") && argc == 2 && !strcmp(argv[1], "off")) {
        quirks_hang_end(e->avr, 0);
    } else if (!strcmp(cmd, "hang") && argc <= 3) {
        /* hang [cli] [SECONDS]: the main program stops (as `rjmp .`; after `cli` too) until
         * a reset, or for SECONDS of simulated time. */
        int k = 1, cli = argc > 1 && !strcmp(argv[1], "cli");
        k += cli;
        v = 0.0;
        if (argc > k) {
            v = strtod(argv[k], &end);
            if (end == argv[k] || *end || !(v > 0.0 && v <= 3600.0)) {
                snprintf(reply, n, "error hang: '%s' is not seconds in (0, 3600]", argv[k]);
                return;
            }
            if (argc > k + 1) {
                snprintf(reply, n, "error hang: use hang [cli] [SECONDS] or hang off");
                return;
            }
        }
        quirks_hang_end(e->avr, 0);
        e->quirks.hang = cli ? 2 : 1;
        e->quirks.hang_until =
            v > 0.0 ? e->avr->cycle + (uint64_t)llround(v * e->avr->frequency) : 0;
    } else if (!strcmp(cmd, "poke") && argc >= 3) {
        /* poke ADDR BYTE...: write the MCU's SRAM (data addresses, e.g. 0x269), as RAM
         * left by an earlier run or random at power-on would hold. */
        unsigned long addr = strtoul(argv[1], &end, 0);
        if (end == argv[1] || *end || addr <= e->avr->ioend ||
            addr + (unsigned long)(argc - 2) > (unsigned long)e->avr->ramend + 1) {
            snprintf(reply, n, "error poke: '%s' is not an SRAM address (0x%x..0x%x)", argv[1],
                     (unsigned)e->avr->ioend + 1, (unsigned)e->avr->ramend);
            return;
        }
        uint8_t bytes[16];
        if (argc - 2 > (int)sizeof bytes) {
            snprintf(reply, n, "error poke: at most %d bytes", (int)sizeof bytes);
            return;
        }
        for (int k = 2; k < argc; k++) {
            unsigned long b = strtoul(argv[k], &end, 0);
            if (end == argv[k] || *end || b > 0xFF) {
                snprintf(reply, n, "error poke: '%s' is not a byte", argv[k]);
                return;
            }
            bytes[k - 2] = (uint8_t)b;
        }
        memcpy(e->avr->data + addr, bytes, (size_t)(argc - 2));
    } else if (!strcmp(cmd, "time") && argc == 1) {
        snprintf(reply, n, "ok %.9f %llu", sim_seconds(e), (unsigned long long)e->avr->cycle);
        return;
    } else if (!strcmp(cmd, "stats") && argc == 1) {
        cmd_stats(e, reply, n);
        return;
    } else if (!strcmp(cmd, "quit") && argc == 1) {
        e->quit_requested = 1;
    } else if (!strcmp(cmd, "help")) {
        snprintf(reply, n, "ok commands: distance M|none [SENSOR], temperature C, noise MM, "
                           "dropout P, spike P, uart drop|corrupt|insert P, scene FILE [SENSOR], "
                           "reset [watchdog], hang [cli] [S] | off, poke ADDR BYTE..., time, "
                           "stats, quit");
        return;
    } else {
        snprintf(reply, n, "error unknown command or wrong arguments: '%s' (try help)", cmd);
        return;
    }
    snprintf(reply, n, "ok");
}

/* ------------------------------------------------------------------ service and pacing */

static int collect_fds(emu_t *e, struct pollfd *pfd, int max)
{
    int fds[CONTROL_MAX_CLIENTS + 1];
    int n = 0;
    pfd[n].fd = e->bridge.master;
    pfd[n].events = POLLIN;
    pfd[n].revents = 0;
    n++;
    if (e->have_control) {
        int k = control_fds(&e->control, fds, CONTROL_MAX_CLIENTS + 1);
        for (int i = 0; i < k && n < max; i++) {
            pfd[n].fd = fds[i];
            pfd[n].events = POLLIN;
            pfd[n].revents = 0;
            n++;
        }
    }
    return n;
}

/* A test runner killed mid-test must not leave emulators behind. */
static void check_parent(emu_t *e)
{
    if (e->exit_with_parent && getppid() != e->parent)
        e->quit_requested = 1;
}

static void service_io(emu_t *e, int deliver_tx)
{
    int opened = bridge_service_ex(&e->bridge, deliver_tx);
    if (opened && e->reset_on_open)
        e->reset_requested = 1;
    if (e->have_control)
        control_service(&e->control);
}

/* Wait until wall time catches up with `cycle`, answering the pty and the control socket
 * as they become ready. A pty with a client and no data keeps the master readable only
 * when the host writes, so the wait really sleeps. */
static void pace_to(emu_t *e, avr_cycle_count_t cycle)
{
    double rate = (double)e->avr->frequency * (1.0 + e->clock_ppm * 1e-6);
    double target = now_s(&e->wall0) + (double)(cycle - e->cycle0) / rate;
    for (;;) {
        struct timespec now;
        clock_gettime(CLOCK_MONOTONIC, &now);
        double left = target - now_s(&now);
        if (left <= 0.0) {
            if (-left > e->max_lag_s)
                e->max_lag_s = -left;
            return;
        }
        struct pollfd pfd[CONTROL_MAX_CLIENTS + 2];
        int n = collect_fds(e, pfd, CONTROL_MAX_CLIENTS + 2);
        /* Without a client the master reports POLLHUP at once: do not poll it then. */
        if (!e->bridge.client)
            pfd[0].fd = -1;
        struct timespec ts = {(time_t)left, (long)((left - floor(left)) * 1e9)};
        int r = ppoll(pfd, (nfds_t)n, &ts, NULL);
        if (r > 0)
            service_io(e, 0);   /* simulated time is ahead: no TX bytes yet */
        if (g_signal || e->quit_requested || e->reset_requested)
            return;
    }
}

/* simavr 1.6 times every byte as 11 bits at UBRR, ignoring U2X0: with U2X0 set (how
 * Arduino runs 115200 at 16 MHz) the emulated line ran at half speed, twice as long one
 * way as the other for unequal frames, which skews a host's round-trip clock estimate.
 * Keep the USART's byte time at the chip's: (UBRR + 1) * (U2X ? 8 : 16) cycles per bit,
 * times start + data + parity + stop bits. simavr reads this field for UDRE, TXC and RXC. */
static void uart_rate_fix(emu_t *e)
{
    avr_uart_t *u = e->bridge.uart;
    if (!e->uart_rate_fix || !u)
        return;
    avr_t *avr = e->avr;
    uint32_t ubrr = avr_regbit_get(avr, u->ubrrl) | ((uint32_t)avr_regbit_get(avr, u->ubrrh) << 8);
    uint32_t per_bit = (ubrr + 1u) * (avr_regbit_get(avr, u->u2x) ? 8u : 16u);
    uint32_t ucsz = avr_regbit_get(avr, u->ucsz);
    uint32_t data = (ucsz == 3u && avr_regbit_get(avr, u->ucsz2)) ? 9u : 5u + ucsz;
    uint32_t parity = ((avr->data[u->r_ucsrc] >> 4) & 3u) ? 1u : 0u;
    uint32_t bits = 1u + data + parity + 1u + (avr_regbit_get(avr, u->usbs) ? 1u : 0u);
    u->cycles_per_byte = (avr_cycle_count_t)per_bit * bits;
}

static avr_cycle_count_t service_tick(avr_t *avr, avr_cycle_count_t when, void *param)
{
    emu_t *e = param;
    (void)avr;
    /* Real time: first wait for the wall clock, then hand over the bytes due by now, so
     * a byte reaches the host at most one service interval late and never early. */
    uart_rate_fix(e);
    if (!e->fast)
        pace_to(e, when);
    service_io(e, 1);
    if (e->duration_s > 0.0 && sim_seconds(e) >= e->duration_s)
        e->quit_requested = 1;
    /* About every 50 ms of simulated time. */
    if (++e->ticks % (1 + (uint64_t)(0.05 / (e->service_us * 1e-6))) == 0)
        check_parent(e);
    return when + e->service_cycles;
}

/* Real time: a byte goes to the host at its own due cycle, not at the next service tick,
 * so MCU-to-host latency is the line's alone (host-to-MCU bytes already enter as they
 * come); a round-trip clock estimate then sees both directions alike. */
static avr_cycle_count_t tx_due_tick(avr_t *avr, avr_cycle_count_t when, void *param)
{
    emu_t *e = param;
    (void)avr;
    pace_to(e, when);
    service_io(e, 1);
    uart_bridge_t *b = &e->bridge;
    if (b->tx_tail == b->tx_head) {
        e->tx_timer_armed = 0;
        return 0;
    }
    avr_cycle_count_t due = b->tx_due[b->tx_tail & (BRIDGE_TX_SIZE - 1)];
    /* Still due but not written (the host is not reading): look again a byte later. */
    return due > when ? due : when + bridge_cycles_per_byte(b);
}

static void on_tx_byte(avr_irq_t *irq, uint32_t value, void *param)
{
    emu_t *e = param;
    (void)irq;
    (void)value;
    if (e->fast || e->tx_timer_armed)
        return;
    e->tx_timer_armed = 1;
    avr_cycle_timer_register(e->avr, bridge_cycles_per_byte(&e->bridge), tx_due_tick, e);
}

static void core_reset_hook(avr_t *avr)
{
    if (g_core_reset)
        g_core_reset(avr);
    g_core_was_reset = 1;
}

/* After any MCU reset (watchdog, control command): simavr dropped every cycle timer, so
 * start our service tick again; the sensor is outside the MCU and finishes its pulse. */
static void after_reset(emu_t *e)
{
    g_core_was_reset = 0;
    quirks_hang_end(e->avr, 1); /* a reset ends the hang: the firmware starts over */
    hand_over(e, e->reset_cause);
    e->reset_cause = 0;
    e->resets++;
    e->bridge.rx_scheduled = 0;
    e->tx_timer_armed = 0;
    avr_cycle_timer_register(e->avr, e->service_cycles, service_tick, e);
    for (int k = 0; k < e->nsensors; k++)
        sonar_rearm(&e->sonar[k]);
    note(e, "MCU reset at %.6f s", sim_seconds(e));
}

static void wait_for_client(emu_t *e)
{
    note(e, "waiting for a client to open %s", e->bridge.path);
    while (!bridge_client_present(&e->bridge)) {
        check_parent(e);
        if (g_signal || e->quit_requested)
            return;
        struct pollfd pfd[CONTROL_MAX_CLIENTS + 2];
        int n = collect_fds(e, pfd, CONTROL_MAX_CLIENTS + 2);
        pfd[0].fd = -1;
        struct timespec ts = {0, 5 * 1000 * 1000};
        if (ppoll(pfd, (nfds_t)n, &ts, NULL) > 0 && e->have_control)
            control_service(&e->control);
    }
    /* pyserial flushes its input right after open(): let it finish first. */
    struct timespec end, now;
    clock_gettime(CLOCK_MONOTONIC, &end);
    double until = now_s(&end) + e->client_grace_ms * 1e-3;
    do {
        struct pollfd pfd[CONTROL_MAX_CLIENTS + 2];
        int n = collect_fds(e, pfd, CONTROL_MAX_CLIENTS + 2);
        pfd[0].fd = -1;
        struct timespec ts = {0, 2 * 1000 * 1000};
        if (ppoll(pfd, (nfds_t)n, &ts, NULL) > 0 && e->have_control)
            control_service(&e->control);
        clock_gettime(CLOCK_MONOTONIC, &now);
    } while (now_s(&now) < until && !g_signal);
    e->bridge.client = 1;
    e->bridge.st.client_opens++;
    note(e, "client connected, starting");
}

/* ------------------------------------------------------------------ setup */

static void write_pty_file(const char *path, const char *pty)
{
    char tmp[4096];
    snprintf(tmp, sizeof tmp, "%s.tmp%ld", path, (long)getpid());
    FILE *f = fopen(tmp, "w");
    if (!f || fprintf(f, "%s\n", pty) < 0 || fclose(f) != 0 || rename(tmp, path) != 0)
        die("cannot write the pty path to %s: %s", path, strerror(errno));
}

static avr_t *load_mcu_elf(emu_t *e);

/* The MCU with the bootloader, and the application when an ELF is given too (a board that
 * was flashed before); without one the application flash is erased (0xFF). */
static avr_t *load_mcu(emu_t *e)
{
    if (!e->boot.path)
        return load_mcu_elf(e);
    avr_t *avr;
    if (e->elf) {
        avr = load_mcu_elf(e);
    } else {
        const char *mcu = e->mcu ? e->mcu : "atmega328p";
        fflush(stdout);
        int saved = dup(1);
        dup2(2, 1);
        avr = avr_make_mcu_by_name(mcu);
        if (!avr)
            die("simavr does not know the MCU '%s'", mcu);
        avr_init(avr);
        avr->frequency = (uint32_t)(e->freq ? e->freq : 16000000UL);
        avr->log = e->verbose >= 2 ? LOG_TRACE : LOG_ERROR;
        fflush(stdout);
        dup2(saved, 1);
        close(saved);
    }
    char err[512];
    if (bootloader_load(&e->boot, avr, err, sizeof err))
        die("%s", err);
    note(e, "bootloader %s: %u bytes at 0x%04x", e->boot.path, (unsigned)e->boot.size,
         (unsigned)e->boot.start);
    return avr;
}

static avr_t *load_mcu_elf(emu_t *e)
{
    if (access(e->elf, R_OK) != 0)
        die("firmware ELF %s: %s (build it with `make -C firmware BOARD=uno`, or run "
            "`make setup`)", e->elf, strerror(errno));
    elf_firmware_t fw;
    memset(&fw, 0, sizeof fw);
    /* simavr prints progress on stdout; stdout is ours (the pty path), so send it to
     * stderr while the library sets up. */
    fflush(stdout);
    int saved = dup(1);
    dup2(2, 1);
    if (elf_read_firmware(e->elf, &fw) != 0)
        die("cannot read firmware ELF %s (is it an AVR ELF?)", e->elf);
    const char *mcu = fw.mmcu[0] ? fw.mmcu : e->mcu;
    if (e->mcu && fw.mmcu[0] && strcmp(e->mcu, fw.mmcu) != 0)
        note(e, "the ELF says %s; using it instead of --mcu %s", fw.mmcu, e->mcu);
    avr_t *avr = avr_make_mcu_by_name(mcu ? mcu : "atmega328p");
    if (!avr)
        die("simavr does not know the MCU '%s'", mcu ? mcu : "atmega328p");
    avr_init(avr);
    unsigned long freq = e->freq ? e->freq : (fw.frequency ? fw.frequency : 16000000UL);
    fw.frequency = (uint32_t)freq;
    avr_load_firmware(avr, &fw);
    avr->frequency = (uint32_t)freq;
    avr->log = e->verbose >= 2 ? LOG_TRACE : LOG_ERROR;
    fflush(stdout);
    dup2(saved, 1);
    close(saved);
    return avr;
}

static void print_summary(emu_t *e, const char *why)
{
    char line[1024];
    cmd_stats(e, line, sizeof line);
    fprintf(stderr, "of-emulator: %s; %s\n", why, line + 3);
}

int main(int argc, char **argv)
{
    emu_t *e = &g_emu;
    memset(e, 0, sizeof *e);
    sonar_default_params(&e->sp);
    e->client_grace_ms = 100.0;
    e->seed = 1;
    e->faults.dirs = FAULT_TX;
    e->quirks.sei_fix = 1;
    e->quirks.tifr_fix = 1;
    e->quirks.flag_fix = 1;
    e->quirks.wdt_fix = 1;
    e->model_rx_overrun = 1;
    e->uart_rate_fix = 1;
    e->parent = getppid();
    parse_args(e, argc, argv);
    if (e->service_us <= 0.0)
        e->service_us = e->fast ? 1000.0 : 200.0;

    avr_global_logger_set(simavr_logger);
    if (e->scene_path) {
        char err[512];
        for (int k = 0; k < SONAR_MAX; k++)
            if (scene_load(&e->scene[k], e->scene_path, 0.0, err, sizeof err))
                die("%s", err);
    }
    for (int k = 0; k < SONAR_MAX; k++) {
        char err[512];
        if (e->sensor_scene[k] && k >= e->nsensors)
            die("--sensor-scene %d: there are only %d sensors (--sensors)", k, e->nsensors);
        if (e->sensor_scene[k] && scene_load(&e->scene[k], e->sensor_scene[k], 0.0, err, sizeof err))
            die("%s", err);
    }
    if (e->truth_path) {
        e->truth = fopen(e->truth_path, "w");
        if (!e->truth)
            die("cannot write truth log %s: %s", e->truth_path, strerror(errno));
    }
    rng_seed(&e->rng_sonar, e->seed * 2 + 1);
    rng_seed(&e->rng_uart, e->seed * 2 + 2);

    avr_t *avr = load_mcu(e);
    e->avr = avr;
    e->service_cycles = (avr_cycle_count_t)llround(e->service_us * 1e-6 * avr->frequency);
    if (e->service_cycles < 1)
        e->service_cycles = 1;
    avr->run = quirks_run;
    g_core_reset = avr->reset;
    avr->reset = core_reset_hook;
    int wrapped = quirks_install(avr, &e->quirks);
    note(e, "%s at %u Hz; %d timer flag registers wrapped", avr->mmcu, avr->frequency, wrapped);

    if (e->truth)
        sonar_truth_header(e->truth);
    for (int k = 0; k < e->nsensors; k++) {
        sonar_params_t sp = e->sp;
        sp.trig_port = e->trig_port[k];
        sp.trig_pin = e->trig_pin[k];
        if (sonar_attach(&e->sonar[k], k, &e->echo_line, avr, &sp, &e->scene[k], &e->rng_sonar,
                         e->truth))
            die("the MCU has no pin P%c%d or P%c%d for sensor %d", sp.trig_port, sp.trig_pin,
                sp.echo_port, sp.echo_pin, k);
    }
    if (bridge_open_pty(&e->bridge))
        die("cannot create a pseudo-terminal: %s", strerror(errno));
    if (bridge_attach(&e->bridge, avr, &e->rng_uart, &e->faults, e->model_rx_overrun))
        die("the MCU %s has no USART0", avr->mmcu);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT),
                            on_tx_byte, e);
    if (e->control_path) {
        char err[512];
        if (control_open(&e->control, e->control_path, handle_command, e, err, sizeof err))
            die("%s", err);
        e->have_control = 1;
    }

    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGHUP, &sa, NULL);
    signal(SIGPIPE, SIG_IGN);

    if (e->pty_file)
        write_pty_file(e->pty_file, e->bridge.path);
    printf("%s\n", e->bridge.path);
    fflush(stdout);

    if (e->wait_client)
        wait_for_client(e);
    else
        e->bridge.client = bridge_client_present(&e->bridge);
    if (e->boot.active)
        bootloader_mark_reset(avr, e->wait_client);

    clock_gettime(CLOCK_MONOTONIC, &e->wall0);
    e->cycle0 = avr->cycle;
    g_core_was_reset = 0;
    if (e->optiboot && e->boot.active)
        die("--optiboot stands in for a bootloader; with --bootloader the real one runs");
    if (e->optiboot && !has_mcusr(avr))
        die("--optiboot: no MCUSR model for %s (ATmega48/88/168/328 only)", avr->mmcu);
    hand_over(e, MCUSR_PORF); /* power-on */
    avr_cycle_timer_register(avr, e->service_cycles, service_tick, e);

    const char *why = "stopped";
    int rc = 0;
    while (!g_signal && !e->quit_requested) {
        int state = avr_run(avr);
        if (g_core_was_reset)
            after_reset(e);
        if (e->reset_requested) {
            e->reset_cause = e->reset_requested == 2 ? MCUSR_WDRF : MCUSR_EXTRF;
            e->reset_requested = 0;
            avr_reset(avr);
            if (e->boot.active) {
                avr->pc = e->boot.start;
                if (e->reset_cause == MCUSR_EXTRF) /* `reset watchdog`: WDRF alone */
                    bootloader_mark_reset(avr, 1);
            }
            bridge_flush(&e->bridge);
            if (g_core_was_reset)
                after_reset(e);
        }
        if (state == cpu_Done || state == cpu_Crashed) {
            why = state == cpu_Done ? "firmware stopped (SLEEP with interrupts disabled)"
                                    : "firmware crashed";
            rc = 3;
            break;
        }
    }
    if (g_signal)
        why = "interrupted";
    else if (e->quit_requested && e->duration_s > 0.0 && sim_seconds(e) >= e->duration_s)
        why = "duration reached";
    else if (e->quit_requested)
        why = "quit";
    /* Deliver the bytes still on the wire before the port goes away; after a signal,
     * only briefly. */
    bridge_drain(&e->bridge, g_signal ? 0.2 : 2.0);
    print_summary(e, why);
    if (e->have_control)
        control_close(&e->control);
    if (e->truth)
        fclose(e->truth);
    return rc;
}
