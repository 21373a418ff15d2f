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
    if (ev->pending == KS_PEND_TIMED)
        ks__queue_forget(sim, ev);
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

void ks_event_notify(ks_event *ev)
{
    if (ev->n_clocked)
        ks__wake_clocked_next(ev);
    ev->pending = KS_PEND_NONE;
    ks__event_trigger(ev);
}

void ks_event_notify_delta(ks_event *ev) { ks__event_notify_delta(ev); }

/* A delta notification overriding a pending timed one. */
void ks__event_notify_delta_slow(ks_event *ev)
{
    ev->pending = KS_PEND_NONE;
    ks__event_notify_delta(ev);
}

void ks__event_notify_at_methods(ks_event *ev, ks_time when)
{
    if (ev->pending == KS_PEND_DELTA || (ev->pending == KS_PEND_TIMED && ev->pending_time <= when))
        return;
    ks_sim *sim = ev->sim;
    ev->pending = KS_PEND_TIMED;
    ev->pending_time = when;
    ev->pending_key = ks__next_key(sim, KS_K_EVENT);
    ev->queued = 1;
    ks__heap_push(sim, when, ev->pending_key, ev);
}

void ks__event_queue_pending(ks_event *ev)
{
    if (ev->on_wait) {
        ev->on_wait(ev, ev->on_wait_ctx);
        return;
    }
    if (ev->queued || ev->pending == KS_PEND_NONE)
        return;
    if (!ks__pending_live(ev)) {
        ev->pending = KS_PEND_NONE;
        return;
    }
    ev->queued = 1;
    if (ev->pending == KS_PEND_DELTA) {
        ks__delta_push(ev->sim, ev, 0);
    } else {
        ev->pending_key = ks__next_key(ev->sim, KS_K_EVENT);
        ks__heap_push(ev->sim, ev->pending_time, ev->pending_key, ev);
    }
}

void ks_event_notify_at(ks_event *ev, ks_time when)
{
    if (when <= ev->sim->now)
        ks__event_notify_delta(ev);
    else
        ks__event_notify_at(ev, when);
}

void ks_event_notify_after(ks_event *ev, ks_time delay)
{
    if (delay <= 0)
        ks__event_notify_delta(ev);
    else
        ks__event_notify_at(ev, ev->sim->now + delay);
}

void ks_event_cancel(ks_event *ev) { ev->pending = KS_PEND_NONE; }
