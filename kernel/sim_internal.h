/* sim_internal.h — private structures shared by the kernel's .c files.
 *
 * Not part of the API: model code must include only the public headers.
 * Scheduling data: a radix heap of timed entries popped in (time, key) order
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
#include "kernel/sched_types.h"

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
void ks__heap_push(ks_sim *sim, ks_time t, uint64_t key, void *obj);
/* 1 when no timed entry is due at or before t. */
int ks__queue_clear_until(ks_sim *sim, ks_time t);
/* 1 when a timed entry other than a clock tick is queued (a method
 * timeout or a timed notification, possibly stale). */
int ks__queue_has_non_clock(ks_sim *sim);
/* Voids the queued entries pointing at obj (it is being destroyed). */
void ks__queue_forget(ks_sim *sim, const void *obj);
void ks__delta_push(ks_sim *sim, void *obj, uint64_t key);
void ks__event_trigger(ks_event *ev);
/* Queues a pending notification recorded while the event had no method
 * waiters (called when a method starts waiting on it). */
void ks__event_queue_pending(ks_event *ev);
void ks__method_timeout(ks_method *m, uint64_t key);
void ks__method_init(ks_sim *sim, ks_method *m);
ks_method *ks__method_new(ks_sim *sim, const char *name, ks_method_fn fn, void *user);
void ks__method_free(ks_method *m);
/* Clock side. */
void ks__clock_tick_entry(ks_clock *clk, uint64_t key);
/* Fires the clock-queue entries at time t (now), in clock creation order. */
void ks__clock_fire_due(ks_sim *sim, ks_time t);
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
