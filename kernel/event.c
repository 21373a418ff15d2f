/* event.c — event notification and triggering (contract in event.h). */
#include <stdlib.h>
#include <string.h>

#include "kernel/sim_internal.h"

void ks_event_init(ks_event *ev, ks_sim *sim, const char *name)
{
    memset(ev, 0, sizeof *ev);
    ev->sim = sim;
    ev->name = ks__xstrdup(name ? name : "event");
}

void ks_event_destroy(ks_event *ev)
{
    if (!ev || !ev->sim)
        return;
    ks_sim *sim = ev->sim;
    /* Drop queued entries that point at this event (rare: only when it is
     * destroyed with a notification pending). */
    if (ev->pending == KS_PEND_TIMED) {
        for (size_t i = 0; i < sim->n_heap; i++)
            if (sim->heap[i].obj == ev)
                sim->heap[i].obj = NULL, sim->heap[i].key = (sim->heap[i].key & ~(uint64_t)3) | KS_K_EVENT;
    }
    if (ev->pending == KS_PEND_DELTA) {
        for (size_t i = 0; i < sim->n_delta; i++)
            if (sim->delta[i].obj == ev)
                sim->delta[i].obj = NULL;
    }
    for (ks_method *m = ev->dyn_head; m;) {
        ks_method *n = m->dyn_next;
        m->dyn_event = NULL;
        m->dyn_prev = m->dyn_next = NULL;
        m = n;
    }
    free((char *)ev->name);
    free(ev->statics);
    free(ev->clocked);
    memset(ev, 0, sizeof *ev);
}

const char *ks_event_name(const ks_event *ev) { return ev->name; }
uint64_t ks_event_trigger_count(const ks_event *ev) { return ev->notify_count; }

/* Fires the event: wakes its method waiters (clocked waiters were woken when
 * the notification was made). */
void ks__event_trigger(ks_event *ev)
{
    if (!ev)
        return; /* entry of a destroyed event */
    ks_sim *sim = ev->sim;
    ev->notify_count++;
    for (uint32_t i = 0; i < ev->n_statics; i++) {
        ks_method *m = ev->statics[i];
        if (m->dyn_mode == KS_DYN_STATIC)
            ks__make_runnable(sim, m);
    }
    ks_method *m = ev->dyn_head;
    ev->dyn_head = NULL;
    while (m) {
        ks_method *n = m->dyn_next;
        m->dyn_prev = m->dyn_next = NULL;
        m->dyn_event = NULL;
        m->dyn_mode = KS_DYN_STATIC;
        m->timeout_key = 0;
        ks__make_runnable(sim, m);
        m = n;
    }
}

static inline int has_method_waiters(const ks_event *ev) { return ev->n_statics || ev->dyn_head; }

void ks_event_notify(ks_event *ev)
{
    for (uint32_t i = 0; i < ev->n_clocked; i++)
        ks__clocked_wake_after_now(ev->clocked[i]);
    ev->pending = KS_PEND_NONE;
    ks__event_trigger(ev);
}

void ks_event_notify_delta(ks_event *ev)
{
    for (uint32_t i = 0; i < ev->n_clocked; i++)
        ks__clocked_wake_after_now(ev->clocked[i]);
    if (!has_method_waiters(ev) || ev->pending == KS_PEND_DELTA)
        return;
    ev->pending = KS_PEND_DELTA;
    ev->pending_key = ks__next_key(ev->sim, KS_K_EVENT);
    ks__delta_push(ev->sim, ev, ev->pending_key);
}

void ks_event_notify_at(ks_event *ev, ks_time when)
{
    ks_sim *sim = ev->sim;
    if (when <= sim->now) {
        ks_event_notify_delta(ev);
        return;
    }
    for (uint32_t i = 0; i < ev->n_clocked; i++)
        ks__clocked_wake_at_time(ev->clocked[i], when);
    if (!has_method_waiters(ev) || ev->pending == KS_PEND_DELTA ||
        (ev->pending == KS_PEND_TIMED && ev->pending_time <= when))
        return;
    ev->pending = KS_PEND_TIMED;
    ev->pending_time = when;
    ev->pending_key = ks__next_key(sim, KS_K_EVENT);
    ks__heap_push(sim, when, ev->pending_key, ev);
}

void ks_event_notify_after(ks_event *ev, ks_time delay)
{
    if (delay <= 0)
        ks_event_notify_delta(ev);
    else
        ks_event_notify_at(ev, ev->sim->now + delay);
}

void ks_event_cancel(ks_event *ev) { ev->pending = KS_PEND_NONE; }
