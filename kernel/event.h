/* event.h — events: the synchronisation primitive of the kernel.
 *
 * Contract (SystemC sc_event semantics):
 *  - A ks_event is embedded in a user struct and set up with ks_event_init;
 *    it must outlive its use and be released with ks_event_destroy.
 *  - ks_event_notify: immediate; processes waiting on it become runnable in
 *    the current evaluation phase. ks_event_notify_delta: they run in the next
 *    delta cycle. ks_event_notify_after(ev, d): at now + d (d = 0 behaves as
 *    a delta notification).
 *  - An event holds at most one pending notification; an earlier one wins
 *    (delta beats timed, an earlier time beats a later one); an immediate
 *    notification cancels a pending one. ks_event_cancel drops it.
 *  - Waiters: method processes (static sensitivity or next-trigger, see
 *    process.h) and clocked processes (ks_clocked_wake_on, clock.h), which are
 *    woken at the first clock edge at or after the notification time (strictly
 *    after `now` for immediate/delta notifications), without any per-cycle
 *    cost. Notifying an event with no method waiters is cheap: the pending
 *    notification is only recorded, and queued when a method starts waiting
 *    on the event before it is due (so SystemC semantics hold).
 * The fields are private to the kernel. */
#ifndef KS_EVENT_H
#define KS_EVENT_H

#include <stdint.h>

#include "kernel/sim.h"
#include "kernel/time.h"

struct ks_method;
struct ks_clocked;

typedef struct ks_event {
    ks_sim *sim;
    const char *name;               /* copied by ks_event_init */
    struct ks_method **statics;     /* methods statically sensitive */
    struct ks_clocked **clocked;    /* clocked processes woken by it */
    struct ks_method *dyn_head;     /* next-trigger waiters (intrusive list) */
    uint32_t n_statics, cap_statics;
    uint32_t n_clocked, cap_clocked;
    uint64_t pending_key;           /* queue key of the pending notification */
    ks_time pending_time;
    uint8_t pending;                /* 0 none, 1 delta, 2 timed */
    uint8_t has_methods;            /* n_statics || dyn_head */
    uint8_t any_waiters;            /* has_methods || n_clocked */
    uint8_t queued;                 /* the pending notification has a queue entry */
    uint64_t pending_delta;         /* delta count when delta-notified */
    /* Channel events (FIFOs) do not record notifications nobody waits for;
     * instead on_wait re-derives them from the channel's state when a
     * method starts waiting on the event. */
    uint8_t no_record;
    void (*on_wait)(struct ks_event *ev, void *ctx);
    void *on_wait_ctx;
    uint64_t notify_count;          /* times it triggered (statistics, tests) */
    /* The one clocked waiter when that is all a notification has to do
     * (one clocked waiter, no method waiters, nothing to record). */
    struct ks_clocked *only_clocked;
} ks_event;

void ks_event_init(ks_event *ev, ks_sim *sim, const char *name);
void ks_event_destroy(ks_event *ev);
const char *ks_event_name(const ks_event *ev);

void ks_event_notify(ks_event *ev);
void ks_event_notify_delta(ks_event *ev);
void ks_event_notify_after(ks_event *ev, ks_time delay);
void ks_event_notify_at(ks_event *ev, ks_time when); /* absolute, >= now */
void ks_event_cancel(ks_event *ev);
/* Number of times the event triggered (immediate or pending notification
 * reaching its time). */
uint64_t ks_event_trigger_count(const ks_event *ev);

#endif
