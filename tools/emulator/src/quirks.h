/* Compensation for simavr 1.6 behaviour that differs from the ATmega328P (README). */
#ifndef OF_EMU_QUIRKS_H
#define OF_EMU_QUIRKS_H

#include <stdint.h>

#include "sim_avr.h"

typedef struct {
    int sei_fix;          /* one instruction after SEI/RETI before an interrupt, not two */
    int tifr_fix;         /* writing TIFRn clears only the flags written as one */
    int flag_fix;         /* EIFR/PCIFR writes cancel interrupts; INTn level polls end with
                           * level mode */
    int wdt_fix;          /* interrupt-and-reset watchdog: a timeout while its interrupt is
                           * still pending resets the MCU */
    int hang;             /* control `hang`: 1 the main program stops (interrupts still
                           * served), 2 it stops with interrupts off; cleared by a reset */
    uint64_t hang_until;  /* cycle at which the hang ends by itself; 0: only a reset ends it */
    int frozen;           /* the hang has begun (it waits for the main program, I set) */
    uint64_t tifr_restored;
    uint64_t flags_cleared;
    uint64_t level_polls_cancelled;
    uint64_t wdt_escalations;  /* watchdog resets only the wdt_fix made */
} quirks_t;

/* The run callback we install instead of avr_callback_run_raw: the same steps, with the
 * SEI latency corrected and no usleep() while the CPU sleeps (pacing is ours); with
 * `hang` set, the main program spins in place as `rjmp .` would (interrupt handlers
 * still run, unless hang is 2). */
void quirks_run(avr_t *avr);
/* Ends a hang (`hang off`, or its time is up): the main program goes on, with interrupts
 * on again after a `hang cli`. reset != 0: the MCU is being reset, nothing to restore. */
void quirks_hang_end(avr_t *avr, int reset);
/* Install the TIFR write wrapper for every timer (and the other fixes switched on);
 * returns how many timers were wrapped. */
int quirks_install(avr_t *avr, quirks_t *q);
/* The state quirks_run() uses. */
extern quirks_t *quirks_active;

#endif
