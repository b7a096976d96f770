/* simavr 1.6 quirks we can correct from outside the library.
 *
 * SEI latency: avr_sreg_set() arms interrupt_state = -2 when I goes 0 -> 1, and
 * avr_service_interrupts() counts it up once per instruction, so two instructions run
 * before a pending interrupt. The chip runs exactly one. Setting -1 right after the
 * instruction that armed it restores the chip's behaviour.
 *
 * TIFR: the timer's flag-register write handler loses flags that were pending and not
 * written as one. We remember the flags before the write and raise again any that the
 * write should not have cleared.
 *
 * EIFR/PCIFR: writing one to a flag does not cancel the pending interrupt. We take over
 * those registers' writes: a one clears the flag and its pending interrupt, as on the
 * chip.
 *
 * INT0/INT1 low level: when the pin goes low in low-level mode (the reset default),
 * simavr 1.6 starts a poll that raises the interrupt every cycle while the pin stays low,
 * and never checks the mode again, so it goes on after EICRA selects an edge. On each
 * EICRA write we cancel the polls of interrupts that are no longer level-triggered.
 *
 * Watchdog in interrupt-and-reset mode (WDE and WDIE): the datasheet (WDTCSR, WDIE) says
 * that if the interrupt is not executed before the next time-out, a system reset is
 * applied. simavr 1.6 (and its later releases) raises the interrupt again at every
 * time-out while WDIE is set, so a program hung with interrupts off never resets. We
 * watch the watchdog interrupt: from its first raise in that mode we time one more
 * time-out (restarted by WDR, as the chip's counter is) and, if the interrupt is still
 * pending then, reset the MCU the way simavr's own watchdog reset does (WDRF, WDE,
 * 16 ms). */
#include "quirks.h"

#include <string.h>

#include "avr_extint.h"
#include "avr_ioport.h"
#include "avr_timer.h"
#include "avr_watchdog.h"
#include "sim_core.h"
#include "sim_cycle_timers.h"
#include "sim_regbit.h"
#include "sim_interrupts.h"
#include "sim_io.h"

quirks_t *quirks_active;

void quirks_run(avr_t *avr)
{
    avr_flashaddr_t new_pc = avr->pc;
    quirks_t *q = quirks_active;
    if (q && q->hang_until && avr->cycle >= q->hang_until)
        quirks_hang_end(avr, 0);
    /* The hang begins in the main program with interrupts on, so a `hang cli` that ends
     * can give them back. */
    int spin = q && q->hang && avr->state == cpu_Running && avr->interrupts.running_ptr == 0 &&
               (q->frozen || avr->sreg[S_I]);
    if (spin) {
        /* The main program is stuck: `rjmp .` (2 cycles), after a `cli` with hang 2. */
        if (!q->frozen && q->hang == 2)
            avr_sreg_set(avr, S_I, 0);
        q->frozen = 1;
        avr->cycle += 2;
    } else if (avr->state == cpu_Running) {
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

void quirks_hang_end(avr_t *avr, int reset)
{
    quirks_t *q = quirks_active;
    if (!q)
        return;
    if (!reset && q->frozen && q->hang == 2)
        avr_sreg_set(avr, S_I, 1);
    q->hang = 0;
    q->hang_until = 0;
    q->frozen = 0;
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

#define MAX_FLAGREGS 4

typedef struct {
    avr_io_addr_t addr;
    avr_io_write_t orig;
    void *orig_param;
    avr_int_vector_t *vec[8];
    int nvec;
} flagreg_wrap_t;

static flagreg_wrap_t g_flagregs[MAX_FLAGREGS];
static int g_nflagregs;

static void flagreg_write(avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param)
{
    flagreg_wrap_t *w = param;
    if (w->orig)
        w->orig(avr, addr, v, w->orig_param);
    /* Flags are cleared by writing one; a zero leaves them. */
    avr->data[addr] = (uint8_t)(avr->data[addr] & ~v);
    for (int i = 0; i < w->nvec; i++) {
        avr_int_vector_t *vec = w->vec[i];
        if (!(v & (vec->raised.mask << vec->raised.bit)))
            continue;
        if (vec->pending || avr_regbit_get(avr, vec->raised)) {
            avr_clear_interrupt(avr, vec);
            if (quirks_active)
                quirks_active->flags_cleared++;
        }
    }
}

static void add_flag_vector(avr_t *avr, avr_int_vector_t *vec)
{
    avr_io_addr_t addr = vec->raised.reg;
    if (!vec->vector || !addr || AVR_DATA_TO_IO(addr) >= MAX_IOs)
        return;
    flagreg_wrap_t *w = NULL;
    for (int i = 0; i < g_nflagregs; i++)
        if (g_flagregs[i].addr == addr)
            w = &g_flagregs[i];
    if (!w) {
        if (g_nflagregs == MAX_FLAGREGS)
            return;
        int slot = AVR_DATA_TO_IO(addr);
        w = &g_flagregs[g_nflagregs++];
        w->addr = addr;
        w->orig = avr->io[slot].w.c;
        w->orig_param = avr->io[slot].w.param;
        w->nvec = 0;
        avr->io[slot].w.c = flagreg_write;
        avr->io[slot].w.param = w;
    }
    if (w->nvec < 8)
        w->vec[w->nvec++] = vec;
}

static void install_flagregs(avr_t *avr)
{
    for (avr_io_t *io = avr->io_port; io; io = io->next) {
        if (!io->kind)
            continue;
        if (!strcmp(io->kind, "extint")) {
            avr_extint_t *x = (avr_extint_t *)io;
            for (int i = 0; i < EXTINT_COUNT; i++)
                add_flag_vector(avr, &x->eint[i].vector);
        } else if (!strcmp(io->kind, "port")) {
            add_flag_vector(avr, &((avr_ioport_t *)io)->pcint);
        }
    }
}

/* Layout of simavr 1.6's private poll context (avr_extint.c), to recognise its timers. */
typedef struct {
    uint32_t eint_no;
    avr_extint_t *extint;
} extint_poll_t;

typedef struct {
    avr_extint_t *extint;
    avr_io_addr_t addr;
    avr_io_write_t orig;
    void *orig_param;
} eicra_wrap_t;

static eicra_wrap_t g_eicra;

static void eicra_write(avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param)
{
    eicra_wrap_t *w = param;
    if (w->orig)
        w->orig(avr, addr, v, w->orig_param);
    else
        avr->data[addr] = v;
    avr_extint_t *x = w->extint;
    avr_cycle_timer_slot_p stale[16];
    int n = 0;
    for (avr_cycle_timer_slot_p t = avr->cycle_timers.timer; t && n < 16; t = t->next) {
        extint_poll_t *poll = t->param;
        if (!poll || poll->extint != x || poll->eint_no >= EXTINT_COUNT)
            continue;
        if (avr_regbit_get_array(avr, x->eint[poll->eint_no].isc, 2) != 0)
            stale[n++] = t;
    }
    for (int i = 0; i < n; i++) {
        avr_cycle_timer_cancel(avr, stale[i]->timer, stale[i]->param);
        if (quirks_active)
            quirks_active->level_polls_cancelled++;
    }
}

static void install_eicra(avr_t *avr)
{
    for (avr_io_t *io = avr->io_port; io; io = io->next) {
        if (!io->kind || strcmp(io->kind, "extint") != 0)
            continue;
        avr_extint_t *x = (avr_extint_t *)io;
        avr_io_addr_t addr = x->eint[0].isc[0].reg;
        if (!addr || !x->eint[0].isc[1].reg || AVR_DATA_TO_IO(addr) >= MAX_IOs)
            return;
        int slot = AVR_DATA_TO_IO(addr);
        g_eicra.extint = x;
        g_eicra.addr = addr;
        g_eicra.orig = avr->io[slot].w.c;
        g_eicra.orig_param = avr->io[slot].w.param;
        avr->io[slot].w.c = eicra_write;
        avr->io[slot].w.param = &g_eicra;
        return;
    }
}

static avr_watchdog_t *g_wdt;
static int (*g_wdt_ioctl)(struct avr_io_t *io, uint32_t ctl, void *param);

static void wdt_reset_now(avr_t *avr)
{
    avr_reset(avr); /* the watchdog's reset handler puts the run callback back */
}

static avr_cycle_count_t wdt_next_timeout(avr_t *avr, avr_cycle_count_t when, void *param)
{
    avr_watchdog_t *p = param;
    (void)when;
    if (p->watchdog.pending && avr_regbit_get(avr, p->watchdog.enable) &&
        avr_regbit_get(avr, p->wde)) {
        p->reset_context.avr_run = avr->run;
        p->reset_context.wdrf = 1;
        avr->run = wdt_reset_now;
        if (quirks_active)
            quirks_active->wdt_escalations++;
    }
    return 0;
}

/* The watchdog interrupt's pending line: 1 when raised, 0 when executed or cleared. */
static void wdt_pending(struct avr_irq_t *irq, uint32_t value, void *param)
{
    avr_watchdog_t *p = param;
    avr_t *avr = p->io.avr;
    (void)irq;
    if (!value)
        avr_cycle_timer_cancel(avr, wdt_next_timeout, p);
    else if (avr_regbit_get(avr, p->watchdog.enable) && avr_regbit_get(avr, p->wde) &&
             !avr_cycle_timer_status(avr, wdt_next_timeout, p))
        avr_cycle_timer_register(avr, p->cycle_count, wdt_next_timeout, p);
}

/* WDR restarts the chip's counter, so it moves the next time-out too. */
static int wdt_ioctl(struct avr_io_t *io, uint32_t ctl, void *param)
{
    int res = g_wdt_ioctl(io, ctl, param);
    if (ctl == AVR_IOCTL_WATCHDOG_RESET && avr_cycle_timer_status(io->avr, wdt_next_timeout, g_wdt))
        avr_cycle_timer_register(io->avr, g_wdt->cycle_count, wdt_next_timeout, g_wdt);
    return res;
}

static void install_wdt(avr_t *avr)
{
    for (avr_io_t *io = avr->io_port; io; io = io->next) {
        if (!io->kind || strcmp(io->kind, "watchdog") != 0 || !io->ioctl)
            continue;
        g_wdt = (avr_watchdog_t *)io;
        if (!g_wdt->watchdog.vector || !g_wdt->watchdog.enable.reg)
            return;
        g_wdt_ioctl = io->ioctl;
        io->ioctl = wdt_ioctl;
        avr_irq_register_notify(g_wdt->watchdog.irq + AVR_INT_IRQ_PENDING, wdt_pending, g_wdt);
        return;
    }
}

int quirks_install(avr_t *avr, quirks_t *q)
{
    quirks_active = q;
    if (q->wdt_fix)
        install_wdt(avr);
    if (q->flag_fix) {
        install_flagregs(avr);
        install_eicra(avr);
    }
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
