/* process.c — method processes and their static/dynamic sensitivity
 * (contract in process.h). */
#include <stdlib.h>

#include "kernel/sim_internal.h"

ks_method *ks__method_new(ks_sim *sim, const char *name, ks_method_fn fn, void *user)
{
    ks_method *m = ks__xcalloc(1, sizeof *m);
    m->sim = sim;
    m->name = ks__xstrdup(name ? name : "method");
    m->fn = fn;
    m->user = user;
    KS_GROW(sim->methods, sim->n_methods, sim->cap_methods);
    sim->methods[sim->n_methods++] = m;
    /* the runnable list never needs more room than one slot per method */
    while (sim->cap_run < sim->n_methods)
        ks__grow_run(sim);
    return m;
}

ks_method *ks_method_create(ks_sim *sim, const char *name, ks_method_fn fn, void *user)
{
    if (!fn) {
        ks__set_error(sim, "method '%s': no function given", name ? name : "?");
        return NULL;
    }
    return ks__method_new(sim, name, fn, user);
}

void ks__method_free(ks_method *m)
{
    free(m->name);
    free(m->sens);
    free(m);
}

void ks__method_init(ks_sim *sim, ks_method *m)
{
    if (m->inited)
        return;
    m->inited = 1;
    if (!m->dont_init)
        ks__make_runnable(sim, m);
}

void ks_method_sensitive(ks_method *m, ks_event *ev)
{
    KS_GROW(ev->statics, ev->n_statics, ev->cap_statics);
    ev->statics[ev->n_statics++] = m;
    ev->has_methods = ev->any_waiters = 1;
    ks__event_refresh(ev);
    ks__event_queue_pending(ev);
    KS_GROW(m->sens, m->n_sens, m->cap_sens);
    m->sens[m->n_sens++] = ev;
}

void ks_method_dont_initialize(ks_method *m) { m->dont_init = 1; }
const char *ks_method_name(const ks_method *m) { return m->name; }
uint64_t ks_method_runs(const ks_method *m) { return m->runs; }

void ks_method_set_describe(ks_method *m, ks_busy_fn busy, ks_describe_fn describe)
{
    m->busy = busy;
    m->describe = describe;
}

static void dyn_unlink(ks_method *m)
{
    ks_event *ev = m->dyn_event;
    if (!ev)
        return;
    if (m->dyn_prev)
        m->dyn_prev->dyn_next = m->dyn_next;
    else
        ev->dyn_head = m->dyn_next;
    if (m->dyn_next)
        m->dyn_next->dyn_prev = m->dyn_prev;
    ev->has_methods = ev->n_statics || ev->dyn_head;
    ev->any_waiters = ev->has_methods || ev->n_clocked;
    ks__event_refresh(ev);
    m->dyn_prev = m->dyn_next = NULL;
    m->dyn_event = NULL;
}

/* A later next_trigger call in the same activation replaces an earlier one. */
static void dyn_clear(ks_method *m)
{
    dyn_unlink(m);
    m->timeout_key = 0;
    m->dyn_mode = KS_DYN_STATIC;
}

static void dyn_link(ks_method *m, ks_event *ev)
{
    m->dyn_event = ev;
    m->dyn_prev = NULL;
    m->dyn_next = ev->dyn_head;
    if (ev->dyn_head)
        ev->dyn_head->dyn_prev = m;
    ev->dyn_head = m;
    ev->has_methods = ev->any_waiters = 1;
    ks__event_refresh(ev);
    ks__event_queue_pending(ev);
}

static void set_timeout(ks_method *m, ks_time delay)
{
    ks_sim *sim = m->sim;
    if (delay <= 0) {
        m->timeout_key = ks__next_key(sim, KS_K_TIMEOUT);
        ks__delta_push(sim, m, m->timeout_key);
    } else {
        m->timeout_key = ks__next_key(sim, KS_K_TIMEOUT);
        ks__heap_push(sim, sim->now + delay, m->timeout_key, m);
    }
}

void ks_next_trigger_event(ks_method *m, ks_event *ev)
{
    dyn_clear(m);
    m->dyn_mode = KS_DYN_EVENT;
    dyn_link(m, ev);
}

void ks_next_trigger_time(ks_method *m, ks_time delay)
{
    dyn_clear(m);
    m->dyn_mode = KS_DYN_TIME;
    set_timeout(m, delay);
}

void ks_next_trigger_event_timeout(ks_method *m, ks_event *ev, ks_time timeout)
{
    dyn_clear(m);
    m->dyn_mode = KS_DYN_EVENT_TIMEOUT;
    dyn_link(m, ev);
    set_timeout(m, timeout);
}

void ks__method_timeout(ks_method *m, uint64_t key)
{
    if (m->timeout_key != key)
        return; /* stale: the method was triggered otherwise or re-armed */
    dyn_unlink(m);
    m->timeout_key = 0;
    m->dyn_mode = KS_DYN_STATIC;
    ks__make_runnable(m->sim, m);
}
