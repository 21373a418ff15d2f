/* sched_types.h — the kernel's private scheduling structures.
 *
 * Not an API: model code must not touch these fields. They are visible only
 * so that the hot paths (FIFO read/write and the wake-ups they cause) can be
 * inlined into the caller, which is what makes an activation cost a few
 * nanoseconds (docs/validation/kernel-speed.md). */
#ifndef KS_SCHED_TYPES_H
#define KS_SCHED_TYPES_H

#include <stddef.h>
#include <stdint.h>

#include "kernel/clock.h"
#include "kernel/event.h"
#include "kernel/process.h"
#include "kernel/signal.h"
#include "kernel/sim.h"
#include "kernel/vcd.h"

enum { KS_K_EVENT = 0, KS_K_TIMEOUT = 1, KS_K_CLOCK = 2 };
enum { KS_PEND_NONE = 0, KS_PEND_DELTA = 1, KS_PEND_TIMED = 2 };
enum { KS_DYN_STATIC = 0, KS_DYN_EVENT = 1, KS_DYN_TIME = 2, KS_DYN_EVENT_TIMEOUT = 3 };

typedef struct ks_qentry {
    ks_time t;
    uint64_t key;
    void *obj;
} ks_qentry;

typedef struct ks_dentry {
    void *obj;
    uint64_t key;
} ks_dentry;

struct ks_method {
    ks_sim *sim;
    char *name;
    ks_method_fn fn;
    void *user;
    uint8_t runnable;
    uint8_t dont_init;
    uint8_t inited;
    uint8_t dyn_mode;          /* KS_DYN_*: what the next activation waits on */
    ks_event *dyn_event;       /* when waiting dynamically on an event */
    struct ks_method *dyn_prev, *dyn_next;
    uint64_t timeout_key;      /* key of the valid timeout entry, 0 none */
    uint64_t runs;
    ks_event **sens;           /* static sensitivity (for reports) */
    uint32_t n_sens, cap_sens;
    ks_busy_fn busy;
    ks_describe_fn describe;
    void *clock;               /* non-NULL: the stepper of this clock */
};

struct ks_clocked {
    ks_clock *clk;
    char *name;
    ks_step_fn step;
    void *user;
    uint32_t idx;
    uint64_t bit;              /* 1 << (idx & 63) */
    uint64_t *awake_word;      /* &clk->awake[idx >> 6] */
    uint64_t *woken_word;      /* &clk->woken[idx >> 6] */
    uint8_t slept;             /* sleep_until_cycle called in this step */
    uint64_t sleep_until;
    uint64_t last_timer;       /* cycle of the last timer pushed (dedupe) */
    uint64_t steps, progress;
    ks_event **wake_events;
    uint32_t n_wake, cap_wake;
    ks_busy_fn busy;
    ks_describe_fn describe;
};

typedef struct ks_timer {
    uint64_t cycle;
    uint32_t idx;
    uint32_t pad;
} ks_timer;

struct ks_clock {
    ks_sim *sim;
    char *name;
    ks_time period;
    ks_method *stepper;
    ks_clocked **procs;
    uint32_t n_procs, cap_procs;
    /* Bit per process: awake = step at the tick being run (when later in
     * the order than the process stepping) or the next one; woken = woken
     * during a tick for the next cycle, merged after it. */
    uint64_t *awake, *woken;
    uint32_t stepping;         /* index of the process being stepped */
    uint8_t woke_later;        /* it woke a process later in the order */
    uint32_t n_words;
    ks_timer *timers;          /* min-heap on (cycle, idx) */
    uint32_t n_timers, cap_timers;
    uint64_t cur_cycle;        /* last ticked cycle */
    ks_time cur_time;          /* its edge time */
    ks_time next_time;         /* edge time of cur_cycle + 1 */
    uint64_t next_min;         /* first cycle that may still tick */
    uint64_t sched_cycle;      /* next tick, valid when scheduled */
    ks_time tick_t;            /* time of its entry in the sim's clock queue */
    uint32_t idx;              /* creation order: coincident edges tick in it */
    uint8_t scheduled, in_tick, exhaustive, started;
    uint8_t in_cq;             /* has an entry in the clock queue (at tick_t) */
    uint64_t ticks;
    ks_event posedge;
};

struct ks_signal {
    ks_sim *sim;
    char *name;
    unsigned width;
    uint64_t mask, cur, next;
    uint8_t upd_pending;
    ks_event changed;
    ks_vcd_var *vcd_var;
};

struct ks_sim {
    ks_time now;
    uint64_t seq;
    /* Timed queue: a byte-digit radix heap (see sim.c). q_now holds the
     * entries at time q_last sorted by key, popped from q_head0; bucket
     * 256 * L + d holds entries whose time differs from q_last first in
     * byte L and has digit d there. */
    struct ks_qbucket {
        ks_qentry *e;
        uint32_t n, cap;
    } *q, q_now;
    uint32_t q_head0;
    uint64_t q_nonempty[32];   /* bit per bucket */
    uint32_t q_words;          /* bit w: q_nonempty[w] != 0 */
    ks_time q_last;
    size_t n_heap;             /* entries in all buckets */
    /* Clock queue: the clocks with a scheduled tick, sorted by (tick_t,
     * idx) descending, so cq[n_cq - 1] ticks next. A clock has at most one
     * entry; one superseded by an earlier tick leaves a void entry in the
     * timed queue (clock.c). */
    ks_clock **cq;
    uint32_t n_cq, cap_cq;
    ks_method **run;
    size_t n_run, cap_run;
    size_t run_i;              /* index in run of the method being evaluated */
    ks_dentry *delta, *delta2;
    size_t n_delta, cap_delta, cap_delta2;
    ks_signal **upd;
    size_t n_upd, cap_upd;
    ks_method **methods;
    size_t n_methods, cap_methods;
    size_t n_uninit_from;      /* methods[n_uninit_from..] not initialised yet */
    ks_clock **clocks;
    size_t n_clocks, cap_clocks;
    ks_fifo **fifos;
    size_t n_fifos, cap_fifos;
    ks_signal **signals;
    size_t n_signals, cap_signals;
    size_t n_clocked;
    ks_clock *ticking;         /* the clock whose processes are stepping */
    uint64_t deltas, activations, progress;
    ks_time last_progress;
    uint64_t dl_cycles;
    char *report;
    uint8_t stop, running;
    ks_time until;             /* time limit of the current run */
    ks_vcd *vcd;
    char error[512];
};


/* Out-of-line parts of the wake-up and notification paths. */
void ks__clocked_wake_after_now(ks_clocked *p);     /* immediate/delta */
void ks__clocked_wake_at_time(ks_clocked *p, ks_time t);
void ks__grow_run(ks_sim *sim);
void ks__grow_delta(ks_sim *sim);

/* A delta/immediate wake-up made during a tick of p's clock: p steps in
 * this tick when it comes later in the order than the process stepping
 * (stepping every process every cycle, it would see the change now), else
 * at the next edge. */
static inline void ks__clocked_wake_in_tick(ks_clocked *p)
{
    ks_clock *c = p->clk;
    if (p->idx > c->stepping) {
        *p->awake_word |= p->bit;
        c->woke_later = 1;
    } else
        *p->woken_word |= p->bit;
}

static inline void ks__make_runnable(ks_sim *sim, ks_method *m)
{
    if (m->runnable)
        return;
    m->runnable = 1;
    if (sim->n_run == sim->cap_run)
        ks__grow_run(sim);
    sim->run[sim->n_run++] = m;
}

/* Wakes the clocked waiters of an event at the next edge after now. */
static inline void ks__wake_clocked_next(const ks_event *ev)
{
    if (ev->n_clocked == 1) { /* the usual case: one consumer or producer */
        ks_clocked *p = ev->clocked[0];
        if (p->clk->in_tick)
            ks__clocked_wake_in_tick(p);
        else
            ks__clocked_wake_after_now(p);
        return;
    }
    for (uint32_t i = 0; i < ev->n_clocked; i++) {
        ks_clocked *p = ev->clocked[i];
        ks_clock *c = p->clk;
        if (c->in_tick)
            ks__clocked_wake_in_tick(p);
        else
            ks__clocked_wake_after_now(p);
    }
}

/* Wakes the clocked waiters of an event at the first edge at or after t > now. */
static inline void ks__wake_clocked_at(const ks_event *ev, ks_time t)
{
    if (ev->n_clocked == 1) {
        ks_clocked *p = ev->clocked[0];
        ks_clock *c = p->clk;
        if (c->in_tick && t == c->next_time)
            *p->woken_word |= p->bit;
        else
            ks__clocked_wake_at_time(p, t);
        return;
    }
    for (uint32_t i = 0; i < ev->n_clocked; i++) {
        ks_clocked *p = ev->clocked[i];
        ks_clock *c = p->clk;
        if (c->in_tick && t == c->next_time)
            *p->woken_word |= p->bit;
        else
            ks__clocked_wake_at_time(p, t);
    }
}

/* Recomputes ev->only_clocked after its waiters or flags changed. */
static inline void ks__event_refresh(ks_event *ev)
{
    ev->only_clocked =
        ev->n_clocked == 1 && !ev->has_methods && ev->no_record ? ev->clocked[0] : NULL;
}

/* Keys of clock-tick entries are (clock index << 2) | KS_K_CLOCK, below
 * every other key, so the edges due at one time tick in clock creation
 * order before any other entry of that time; sequence numbers of the other
 * entries start above that range. */
enum { KS_CLOCK_KEY_RANGE = 1 << 24 };
static inline uint64_t ks__next_key(ks_sim *sim, unsigned kind) { return (++sim->seq << 2) | kind; }

/* Is the event's pending notification still ahead? (An unqueued one,
 * recorded while nobody waited, expires when its time or delta passes.) */
static inline int ks__pending_live(const ks_event *ev)
{
    if (ev->pending == KS_PEND_NONE)
        return 0;
    if (ev->queued)
        return 1;
    if (ev->pending == KS_PEND_TIMED)
        return ev->pending_time > ev->sim->now;
    return ev->pending_delta == ev->sim->deltas;
}

/* Delta notification. With method waiters it gets a delta-list entry
 * (an event is in the list at most once while pending; a cancelled entry is
 * skipped when its pending flag is gone); without, it is only recorded. */
void ks__event_notify_delta_slow(ks_event *ev);
static inline __attribute__((always_inline)) void ks__event_notify_delta(ks_event *ev)
{
    ks_clocked *only = ev->only_clocked;
    if (only) {
        if (only->clk->in_tick)
            ks__clocked_wake_in_tick(only);
        else
            ks__clocked_wake_after_now(only);
        return;
    }
    if (ev->n_clocked)
        ks__wake_clocked_next(ev);
    if (!ev->has_methods) { /* record only; pending_key 0 voids a queued entry */
        if (ev->no_record)
            return;
        ev->pending = KS_PEND_DELTA;
        ev->pending_delta = ev->sim->deltas;
        ev->pending_key = 0;
        ev->queued = 0;
        return;
    }
    if (ev->pending != KS_PEND_NONE) {
        if (ev->pending == KS_PEND_TIMED)
            ks__event_notify_delta_slow(ev);
        return;
    }
    ks_sim *sim = ev->sim;
    ev->pending = KS_PEND_DELTA;
    ev->queued = 1;
    if (sim->n_delta == sim->cap_delta)
        ks__grow_delta(sim);
    sim->delta[sim->n_delta].obj = ev;
    sim->delta[sim->n_delta].key = 0;
    sim->n_delta++;
}

void ks__event_notify_at_methods(ks_event *ev, ks_time when);
/* Timed notification at when > now. */
static inline __attribute__((always_inline)) void ks__event_notify_at(ks_event *ev, ks_time when)
{
    ks_clocked *only = ev->only_clocked;
    if (only) {
        ks_clock *c = only->clk;
        if (c->in_tick && when == c->next_time)
            *only->woken_word |= only->bit;
        else
            ks__clocked_wake_at_time(only, when);
        return;
    }
    if (ev->n_clocked)
        ks__wake_clocked_at(ev, when);
    if (ev->has_methods) {
        ks__event_notify_at_methods(ev, when);
        return;
    }
    /* record only (the queue key is drawn when a method starts waiting) */
    if (ev->no_record)
        return;
    if (ev->pending == KS_PEND_TIMED ? ev->pending_time > ev->sim->now && ev->pending_time <= when
                                     : ks__pending_live(ev))
        return;
    ev->pending = KS_PEND_TIMED;
    ev->pending_time = when;
    ev->pending_key = 0;
    ev->queued = 0;
}

#endif
