/* signal.c — signals with request-update semantics (contract in signal.h). */
#include <stdlib.h>

#include "kernel/sim_internal.h"

ks_signal *ks_signal_create(ks_sim *sim, const char *name, unsigned width, uint64_t init)
{
    if (!name)
        name = "signal";
    if (width < 1 || width > 64) {
        ks__set_error(sim, "signal '%s': width %u out of range 1..64", name, width);
        return NULL;
    }
    ks_signal *s = ks__xcalloc(1, sizeof *s);
    s->sim = sim;
    s->name = ks__xstrdup(name);
    s->width = width;
    s->mask = width == 64 ? UINT64_MAX : (((uint64_t)1 << width) - 1);
    s->cur = s->next = init & s->mask;
    char ev[512];
    snprintf(ev, sizeof ev, "%s.changed", name);
    ks_event_init(&s->changed, sim, ev);
    KS_GROW(sim->signals, sim->n_signals, sim->cap_signals);
    sim->signals[sim->n_signals++] = s;
    if (sim->vcd)
        ks__vcd_trace_signal(sim->vcd, s);
    return s;
}

void ks__signal_free(ks_signal *s)
{
    ks_event_destroy(&s->changed);
    free(s->name);
    free(s);
}

uint64_t ks_signal_read(const ks_signal *s) { return s->cur; }
ks_event *ks_signal_ev_changed(ks_signal *s) { return &s->changed; }
const char *ks_signal_name(const ks_signal *s) { return s->name; }
unsigned ks_signal_width(const ks_signal *s) { return s->width; }

void ks_signal_write(ks_signal *s, uint64_t value)
{
    s->next = value & s->mask;
    if (!s->upd_pending) {
        s->upd_pending = 1;
        ks_sim *sim = s->sim;
        KS_GROW(sim->upd, sim->n_upd, sim->cap_upd);
        sim->upd[sim->n_upd++] = s;
    }
}

void ks__signal_update(ks_signal *s)
{
    s->upd_pending = 0;
    if (s->next == s->cur)
        return;
    s->cur = s->next;
    if (s->vcd_var)
        ks_vcd_set(s->vcd_var, s->cur);
    ks_event_notify_delta(&s->changed);
}
