/* sim_internal.h — private structures shared by the kernel's .c files.
 *
 * Not part of the API: model code must include only the public headers.
 * Scheduling data: a binary min-heap of timed entries ordered by (time, key)
 * where key = sequence number << 2 | kind, so equal times fire in notification
 * order; entries are invalidated lazily (the owner stores the key of its one
 * valid entry). Delta notifications go to a list of (object, key) entries
 * with the same validation. */
#ifndef KS_SIM_INTERNAL_H
#define KS_SIM_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "kernel/clock.h"
#include "kernel/event.h"
#include "kernel/fifo.h"
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
    uint64_t *awake, *woken;   /* bit per process */
    uint32_t n_words;
    ks_timer *timers;          /* min-heap on (cycle, idx) */
    uint32_t n_timers, cap_timers;
    uint64_t cur_cycle;        /* last ticked cycle */
    ks_time cur_time;          /* its edge time */
    uint64_t next_min;         /* first cycle that may still tick */
    uint64_t sched_cycle;      /* next tick, valid when scheduled */
    uint64_t tick_key;
    uint8_t scheduled, in_tick, exhaustive, started;
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
    ks_qentry *heap;
    size_t n_heap, cap_heap;
    ks_method **run;
    size_t n_run, cap_run;
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
    uint64_t deltas, activations, progress;
    ks_time last_progress;
    uint64_t dl_cycles;
    char *report;
    uint8_t stop, running;
    ks_vcd *vcd;
    char error[512];
};

/* Allocation that aborts with a message on exhaustion (the kernel cannot
 * continue meaningfully without memory). */
void *ks__xmalloc(size_t n);
void *ks__xcalloc(size_t n, size_t size);
void *ks__xrealloc(void *p, size_t n);
char *ks__xstrdup(const char *s);
#define KS_GROW(arr, n, cap)                                                          \
    do {                                                                              \
        if ((n) >= (cap)) {                                                           \
            (cap) = (cap) ? (cap) * 2 : 8;                                            \
            (arr) = ks__xrealloc((arr), (size_t)(cap) * sizeof *(arr));               \
        }                                                                             \
    } while (0)

void ks__set_error(ks_sim *sim, const char *fmt, ...);
uint64_t ks__next_key(ks_sim *sim, unsigned kind);
void ks__heap_push(ks_sim *sim, ks_time t, uint64_t key, void *obj);
void ks__delta_push(ks_sim *sim, void *obj, uint64_t key);
void ks__make_runnable(ks_sim *sim, ks_method *m);
void ks__event_trigger(ks_event *ev);
void ks__method_timeout(ks_method *m, uint64_t key);
void ks__method_init(ks_sim *sim, ks_method *m);
ks_method *ks__method_new(ks_sim *sim, const char *name, ks_method_fn fn, void *user);
void ks__method_free(ks_method *m);
/* Clock side. */
void ks__clock_tick_entry(ks_clock *clk, uint64_t key);
void ks__clocked_wake_after_now(ks_clocked *p);     /* immediate/delta */
void ks__clocked_wake_at_time(ks_clocked *p, ks_time t);
void ks__clock_free(ks_clock *clk);
void ks__clock_start(ks_clock *clk);
int ks__clock_any_awake(const ks_clock *clk);
/* Signals and FIFOs. */
void ks__signal_update(ks_signal *s);
void ks__signal_free(ks_signal *s);
void ks__fifo_free(ks_fifo *f);
/* VCD hooks. */
void ks__vcd_trace_fifo(ks_vcd *vcd, ks_fifo *f);
void ks__vcd_trace_signal(ks_vcd *vcd, ks_signal *s);
void ks__vcd_finish(ks_vcd *vcd);

#endif
