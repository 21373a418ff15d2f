/* process.h — method processes (SystemC SC_METHOD).
 *
 * Contract:
 *  - A method runs to completion each time it is triggered; it never blocks.
 *  - Static sensitivity: ks_method_sensitive(m, ev) (before or during the run).
 *  - Dynamic sensitivity: inside its function, a method may call
 *    ks_next_trigger_event / _time / _event_timeout; that replaces the static
 *    sensitivity for the next activation only (SystemC next_trigger).
 *  - Every method runs once at the start (first delta of time 0, or of its
 *    creation time if created later) unless ks_method_dont_initialize().
 *  - A method triggered several times in one delta runs once. Runnable
 *    methods run in the order they became runnable (deterministic).
 * Methods are owned by the sim (no destroy). */
#ifndef KS_PROCESS_H
#define KS_PROCESS_H

#include "kernel/event.h"
#include "kernel/sim.h"

typedef struct ks_method ks_method;
typedef void (*ks_method_fn)(void *user);

ks_method *ks_method_create(ks_sim *sim, const char *name, ks_method_fn fn, void *user);
void ks_method_sensitive(ks_method *m, ks_event *ev);
void ks_method_dont_initialize(ks_method *m);
const char *ks_method_name(const ks_method *m);
/* Number of times the method has run. */
uint64_t ks_method_runs(const ks_method *m);

/* Dynamic sensitivity for the next activation (call from the method). */
void ks_next_trigger_event(ks_method *m, ks_event *ev);
void ks_next_trigger_time(ks_method *m, ks_time delay);
void ks_next_trigger_event_timeout(ks_method *m, ks_event *ev, ks_time timeout);

/* Describes the method for the deadlock report: `busy` returns non-zero when
 * the unit holds work it could not finish; `describe` writes a one-line state
 * (either may be NULL). */
typedef int (*ks_busy_fn)(void *user);
typedef void (*ks_describe_fn)(void *user, char *buf, unsigned cap);
void ks_method_set_describe(ks_method *m, ks_busy_fn busy, ks_describe_fn describe);

#endif
