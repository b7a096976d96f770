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
    uint64_t tifr_restored;
    uint64_t flags_cleared;
    uint64_t level_polls_cancelled;
} quirks_t;

/* The run callback we install instead of avr_callback_run_raw: the same steps, with the
 * SEI latency corrected and no usleep() while the CPU sleeps (pacing is ours). */
void quirks_run(avr_t *avr);
/* Install the TIFR write wrapper for every timer; returns how many were wrapped. */
int quirks_install(avr_t *avr, quirks_t *q);
/* The state quirks_run() uses. */
extern quirks_t *quirks_active;

#endif
