/* simavr 1.6 quirks we can correct from outside the library.
 *
 * SEI latency: avr_sreg_set() arms interrupt_state = -2 when I goes 0 -> 1, and
 * avr_service_interrupts() counts it up once per instruction, so two instructions run
 * before a pending interrupt. The chip runs exactly one. Setting -1 right after the
 * instruction that armed it restores the chip's behaviour.
 *
 * TIFR: the timer's flag-register write handler loses flags that were pending and not
 * written as one. We remember the flags before the write and raise again any that the
 * write should not have cleared. */
#include "quirks.h"

#include <string.h>

#include "avr_timer.h"
#include "sim_core.h"
#include "sim_interrupts.h"
#include "sim_io.h"

quirks_t *quirks_active;

void quirks_run(avr_t *avr)
{
    avr_flashaddr_t new_pc = avr->pc;
    if (avr->state == cpu_Running) {
        new_pc = avr_run_one(avr);
        if (quirks_active && quirks_active->sei_fix && avr->interrupt_state == -2)
            avr->interrupt_state = -1;
    }
    avr_cycle_count_t sleep = avr_cycle_timer_process(avr);
    avr->pc = new_pc;
    if (avr->state == cpu_Sleeping) {
        if (!avr->sreg[S_I]) {
            avr->state = cpu_Done;
            return;
        }
        avr->cycle += 1 + sleep;
    }
    if ((avr->state == cpu_Running || avr->state == cpu_Sleeping) && avr->interrupt_state)
        avr_service_interrupts(avr);
}

#define MAX_WRAPPED 8

typedef struct {
    avr_timer_t *timer;
    avr_io_addr_t addr;
    avr_io_write_t orig;
    void *orig_param;
} tifr_wrap_t;

static tifr_wrap_t g_wraps[MAX_WRAPPED];
static int g_nwraps;

static void restore_if_lost(avr_t *avr, avr_int_vector_t *v, avr_io_addr_t addr, uint8_t lost)
{
    if (v->raised.reg == addr && (lost & (v->raised.mask << v->raised.bit))) {
        avr_raise_interrupt(avr, v);
        if (quirks_active)
            quirks_active->tifr_restored++;
    }
}

static void tifr_write(avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param)
{
    tifr_wrap_t *w = param;
    uint8_t before = avr->data[addr];
    w->orig(avr, addr, v, w->orig_param);
    uint8_t lost = (uint8_t)(before & ~v & ~avr->data[addr]);
    if (!lost)
        return;
    avr_timer_t *t = w->timer;
    restore_if_lost(avr, &t->overflow, addr, lost);
    restore_if_lost(avr, &t->icr, addr, lost);
    for (int i = 0; i < AVR_TIMER_COMP_COUNT; i++)
        restore_if_lost(avr, &t->comp[i].interrupt, addr, lost);
}

int quirks_install(avr_t *avr, quirks_t *q)
{
    quirks_active = q;
    if (!q->tifr_fix)
        return 0;
    int n = 0;
    for (avr_io_t *io = avr->io_port; io && g_nwraps < MAX_WRAPPED; io = io->next) {
        if (!io->kind || strcmp(io->kind, "timer") != 0)
            continue;
        avr_timer_t *t = (avr_timer_t *)io;
        avr_io_addr_t addr = t->overflow.raised.reg;
        if (!addr || AVR_DATA_TO_IO(addr) >= MAX_IOs)
            continue;
        int slot = AVR_DATA_TO_IO(addr);
        if (!avr->io[slot].w.c || avr->io[slot].w.c == tifr_write)
            continue;
        tifr_wrap_t *w = &g_wraps[g_nwraps++];
        w->timer = t;
        w->addr = addr;
        w->orig = avr->io[slot].w.c;
        w->orig_param = avr->io[slot].w.param;
        avr->io[slot].w.c = tifr_write;
        avr->io[slot].w.param = w;
        n++;
    }
    return n;
}
