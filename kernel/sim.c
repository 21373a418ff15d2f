/* sim.c — the scheduler: timed queue, delta cycles, run loop, deadlock
 * detection (contract in sim.h). */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "kernel/sim_internal.h"

void *ks__xmalloc(size_t n)
{
    void *p = malloc(n ? n : 1);
    if (!p) {
        fprintf(stderr, "rtsim kernel: out of memory (%zu bytes)\n", n);
        abort();
    }
    return p;
}

void *ks__xcalloc(size_t n, size_t size)
{
    void *p = calloc(n ? n : 1, size ? size : 1);
    if (!p) {
        fprintf(stderr, "rtsim kernel: out of memory (%zu x %zu bytes)\n", n, size);
        abort();
    }
    return p;
}

void *ks__xrealloc(void *p, size_t n)
{
    void *q = realloc(p, n ? n : 1);
    if (!q) {
        fprintf(stderr, "rtsim kernel: out of memory (%zu bytes)\n", n);
        abort();
    }
    return q;
}

char *ks__xstrdup(const char *s)
{
    if (!s)
        s = "";
    size_t n = strlen(s) + 1;
    char *d = ks__xmalloc(n);
    memcpy(d, s, n);
    return d;
}

void ks__set_error(ks_sim *sim, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(sim->error, sizeof sim->error, fmt, ap);
    va_end(ap);
}

const char *ks_sim_error(const ks_sim *sim) { return sim->error; }

enum { KS_Q_BUCKETS = 8 * 256 }; /* timed-queue buckets: 8 byte digits */

ks_sim *ks_sim_create(void)
{
    ks_sim *sim = ks__xcalloc(1, sizeof *sim);
    sim->dl_cycles = 100000;
    sim->seq = KS_CLOCK_KEY_RANGE;
    sim->q = ks__xcalloc(KS_Q_BUCKETS, sizeof *sim->q);
    sim->report = ks__xstrdup("");
    return sim;
}

void ks_sim_destroy(ks_sim *sim)
{
    if (!sim)
        return;
    if (sim->vcd)
        ks_vcd_close(sim->vcd);
    for (size_t i = 0; i < sim->n_fifos; i++)
        ks__fifo_free(sim->fifos[i]);
    for (size_t i = 0; i < sim->n_signals; i++)
        ks__signal_free(sim->signals[i]);
    for (size_t i = 0; i < sim->n_clocks; i++)
        ks__clock_free(sim->clocks[i]);
    for (size_t i = 0; i < sim->n_methods; i++)
        ks__method_free(sim->methods[i]);
    free(sim->fifos);
    free(sim->signals);
    free(sim->clocks);
    free(sim->methods);
    for (unsigned b = 0; b < KS_Q_BUCKETS; b++)
        free(sim->q[b].e);
    free(sim->q);
    free(sim->q_now.e);
    free(sim->cq);
    free(sim->run);
    free(sim->delta);
    free(sim->delta2);
    free(sim->upd);
    free(sim->report);
    free(sim);
}

ks_time ks_sim_now(const ks_sim *sim) { return sim->now; }
uint64_t ks_sim_delta_count(const ks_sim *sim) { return sim->deltas; }
uint64_t ks_sim_activations(const ks_sim *sim) { return sim->activations; }
void ks_sim_stop(ks_sim *sim) { sim->stop = 1; }
void ks_sim_set_deadlock_cycles(ks_sim *sim, uint64_t cycles) { sim->dl_cycles = cycles; }
uint64_t ks_sim_total_progress(const ks_sim *sim) { return sim->progress; }
const char *ks_sim_deadlock_report(const ks_sim *sim) { return sim->report; }

void ks_sim_progress(ks_sim *sim, uint64_t n)
{
    if (n) {
        sim->progress += n;
        sim->last_progress = sim->now;
    }
}

const char *ks_run_status_name(ks_run_status st)
{
    switch (st) {
    case KS_RUN_FINISHED: return "finished";
    case KS_RUN_TIME_LIMIT: return "time limit";
    case KS_RUN_DEADLOCK: return "deadlock";
    case KS_RUN_STOPPED: return "stopped";
    }
    return "?";
}


/* ---- timed queue: radix heap on time, FIFO by key within a time ----
 * Times popped never decrease, so a radix heap applies (Ahuja, Mehlhorn,
 * Orlin and Tarjan 1990), here with byte digits: an entry lives in q_now
 * when its time equals q_last (the last minimum), otherwise in bucket
 * (L, d) where byte L is the highest byte in which its time differs from
 * q_last and d is its byte there; buckets in (L, d) order are in time
 * order. A push is an append; when q_now runs empty, the lowest non-empty
 * bucket (a bitmap scan) is searched for its minimum time, which becomes
 * q_last, and its entries are redistributed to lower buckets (each entry
 * moves at most 8 times; for delays below 2^24 ps, two or three). Keys are
 * drawn from a counter at push time, so entries pushed at time q_last
 * arrive in key order, except clock ticks, whose fixed keys sort below all
 * others (sched_types.h) and are moved to their place; entries
 * redistributed into q_now are sorted by key first. The result is the
 * exact (time, key) order of a heap at a fraction of its cost. A push before q_last (possible after a run stopped at its
 * time limit looked beyond it, or on an empty queue) re-buckets everything
 * around the new minimum. */


static inline void q_append_to(struct ks_qbucket *q, ks_qentry e)
{
    if (q->n == q->cap) {
        q->cap = q->cap ? q->cap * 2 : 16;
        q->e = ks__xrealloc(q->e, (size_t)q->cap * sizeof *q->e);
    }
    q->e[q->n++] = e;
}

/* Appends e (e.t > q_last) to its bucket. */
static inline void q_append_far(ks_sim *sim, ks_qentry e)
{
    uint64_t x = (uint64_t)e.t ^ (uint64_t)sim->q_last;
    unsigned level = (63u - (unsigned)__builtin_clzll(x)) >> 3;
    unsigned b = (level << 8) | (unsigned)(((uint64_t)e.t >> (level * 8)) & 255);
    q_append_to(&sim->q[b], e);
    sim->q_nonempty[b >> 6] |= (uint64_t)1 << (b & 63);
    sim->q_words |= (uint32_t)1 << (b >> 6);
}

static void q_rebucket(ks_sim *sim, ks_time new_last)
{
    /* Rare: move every entry, q_now's first (they keep their key order:
     * their time, the old q_last, is above new_last) */
    ks_qentry *all = ks__xmalloc((sim->n_heap ? sim->n_heap : 1) * sizeof *all);
    size_t n = 0;
    for (uint32_t i = sim->q_head0; i < sim->q_now.n; i++)
        all[n++] = sim->q_now.e[i];
    sim->q_now.n = sim->q_head0 = 0;
    sim->q_words = 0;
    for (unsigned w = 0; w < 32; w++) {
        while (sim->q_nonempty[w]) {
            unsigned b = (w << 6) | (unsigned)__builtin_ctzll(sim->q_nonempty[w]);
            sim->q_nonempty[w] &= sim->q_nonempty[w] - 1;
            struct ks_qbucket *q = &sim->q[b];
            for (uint32_t i = 0; i < q->n; i++)
                all[n++] = q->e[i];
            q->n = 0;
        }
    }
    sim->q_last = new_last;
    for (size_t i = 0; i < n; i++)
        q_append_far(sim, all[i]);
    free(all);
}

void ks__heap_push(ks_sim *sim, ks_time t, uint64_t key, void *obj)
{
    ks_qentry e = {t, key, obj};
    sim->n_heap++;
    if (t == sim->q_last) {
        q_append_to(&sim->q_now, e);
        /* keys arrive in increasing order except a clock tick's (small,
         * fixed) key: move it down to its place among the pending ones */
        ks_qentry *q = sim->q_now.e;
        uint32_t j = sim->q_now.n - 1;
        while (j > sim->q_head0 && q[j - 1].key > key) {
            q[j] = q[j - 1];
            j--;
        }
        q[j] = e;
        return;
    }
    if (sim->n_heap == 1) { /* empty: e is the minimum */
        sim->q_now.n = sim->q_head0 = 0;
        sim->q_last = t;
        q_append_to(&sim->q_now, e);
        return;
    }
    if (t < sim->q_last) {
        q_rebucket(sim, t);
        q_append_to(&sim->q_now, e);
        return;
    }
    q_append_far(sim, e);
}

/* Refills the empty q_now from the lowest non-empty bucket. */
static __attribute__((noinline)) ks_qentry *q_refill(ks_sim *sim)
{
    struct ks_qbucket *q0 = &sim->q_now;
    q0->n = 0;
    sim->q_head0 = 0;
    unsigned w = (unsigned)__builtin_ctz(sim->q_words);
    unsigned b = (w << 6) | (unsigned)__builtin_ctzll(sim->q_nonempty[w]);
    sim->q_nonempty[w] &= sim->q_nonempty[w] - 1;
    if (!sim->q_nonempty[w])
        sim->q_words &= ~((uint32_t)1 << w);
    struct ks_qbucket *q = &sim->q[b];
    ks_time m = q->e[0].t, mx = m;
    for (uint32_t i = 1; i < q->n; i++) {
        ks_time t = q->e[i].t;
        m = t < m ? t : m;
        mx = t > mx ? t : mx;
    }
    sim->q_last = m;
    uint32_t n = q->n;
    q->n = 0;
    if (m == mx) { /* one time (always so at level 0): the bucket becomes q_now */
        ks_qentry *e = q0->e;
        uint32_t cap = q0->cap;
        q0->e = q->e;
        q0->cap = q->cap;
        q0->n = n;
        q->e = e;
        q->cap = cap;
    } else {
        for (uint32_t i = 0; i < n; i++) {
            if (q->e[i].t == m)
                q_append_to(q0, q->e[i]);
            else
                q_append_far(sim, q->e[i]);
        }
    }
    /* entries redistributed into q_now in key order */
    ks_qentry *e = q0->e;
    for (uint32_t i = 1; i < q0->n; i++) {
        ks_qentry x = e[i];
        uint32_t j = i;
        while (j > 0 && e[j - 1].key > x.key) {
            e[j] = e[j - 1];
            j--;
        }
        e[j] = x;
    }
    return &q0->e[0];
}

/* The minimum entry (the queue must not be empty). */
static inline ks_qentry *q_min(ks_sim *sim)
{
    if (sim->q_head0 < sim->q_now.n)
        return &sim->q_now.e[sim->q_head0];
    return q_refill(sim);
}

int ks__queue_clear_until(ks_sim *sim, ks_time t)
{
    return sim->n_heap == 0 || q_min(sim)->t > t;
}

int ks__queue_has_non_clock(ks_sim *sim)
{
    for (uint32_t i = sim->q_head0; i < sim->q_now.n; i++)
        if (sim->q_now.e[i].obj && (sim->q_now.e[i].key & 3) != KS_K_CLOCK)
            return 1;
    for (unsigned b = 0; b < KS_Q_BUCKETS; b++)
        if (sim->q_nonempty[b >> 6] >> (b & 63) & 1)
            for (uint32_t i = 0; i < sim->q[b].n; i++)
                if (sim->q[b].e[i].obj && (sim->q[b].e[i].key & 3) != KS_K_CLOCK)
                    return 1;
    return 0;
}

static inline void q_pop(ks_sim *sim)
{
    sim->n_heap--;
    sim->q_head0++;
}

static void q_forget_in(struct ks_qbucket *q, uint32_t from, const void *obj)
{
    for (uint32_t i = from; i < q->n; i++)
        if (q->e[i].obj == obj)
            q->e[i].obj = NULL, q->e[i].key = (q->e[i].key & ~(uint64_t)3) | KS_K_EVENT;
}

void ks__queue_forget(ks_sim *sim, const void *obj)
{
    q_forget_in(&sim->q_now, sim->q_head0, obj);
    for (unsigned b = 0; b < KS_Q_BUCKETS; b++)
        if (sim->q_nonempty[b >> 6] >> (b & 63) & 1)
            q_forget_in(&sim->q[b], 0, obj);
}

/* ---- delta notifications and runnable queue ---- */

void ks__grow_run(ks_sim *sim)
{
    sim->cap_run = sim->cap_run ? sim->cap_run * 2 : 64;
    sim->run = ks__xrealloc(sim->run, sim->cap_run * sizeof *sim->run);
}

void ks__grow_delta(ks_sim *sim)
{
    sim->cap_delta = sim->cap_delta ? sim->cap_delta * 2 : 64;
    sim->delta = ks__xrealloc(sim->delta, sim->cap_delta * sizeof *sim->delta);
}

void ks__delta_push(ks_sim *sim, void *obj, uint64_t key)
{
    if (sim->n_delta == sim->cap_delta)
        ks__grow_delta(sim);
    sim->delta[sim->n_delta].obj = obj;
    sim->delta[sim->n_delta].key = key;
    sim->n_delta++;
}

/* Fires an event: wakes its method waiters (clocked waiters were woken when
 * the notification was made). */
static __attribute__((noinline)) void trigger_dynamic(ks_sim *sim, ks_event *ev);

static inline void event_trigger(ks_sim *sim, ks_event *ev)
{
    ev->notify_count++;
    ks_method **st = ev->statics;
    uint32_t n = ev->n_statics;
    ks_method **run = sim->run; /* capacity >= number of methods */
    size_t nr = sim->n_run;
    for (uint32_t i = 0; i < n; i++) {
        ks_method *m = st[i];
        if (!m->runnable && m->dyn_mode == KS_DYN_STATIC) {
            m->runnable = 1;
            run[nr++] = m;
        }
    }
    sim->n_run = nr;
    if (ev->dyn_head)
        trigger_dynamic(sim, ev);
}

static void trigger_dynamic(ks_sim *sim, ks_event *ev)
{
    ks_method *m = ev->dyn_head;
    ev->dyn_head = NULL;
    ev->has_methods = ev->n_statics != 0;
    ev->any_waiters = ev->has_methods || ev->n_clocked;
    ks__event_refresh(ev);
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

void ks__event_trigger(ks_event *ev)
{
    if (ev)
        event_trigger(ev->sim, ev);
}

static void fire_entry(void *obj, uint64_t key)
{
    switch (key & 3) {
    case KS_K_EVENT: {
        ks_event *ev = obj;
        if (ev && ev->pending != KS_PEND_NONE && ev->pending_key == key) {
            ev->pending = KS_PEND_NONE;
            ks__event_trigger(ev);
        }
        break;
    }
    case KS_K_TIMEOUT: ks__method_timeout(obj, key); break;
    case KS_K_CLOCK: ks__clock_tick_entry(obj, key); break;
    }
}

/* ---- deadlock detection ---- */

static int fifo_event_owner(const ks_sim *sim, const ks_event *ev, const ks_fifo **out)
{
    for (size_t i = 0; i < sim->n_fifos; i++) {
        const ks_fifo *f = sim->fifos[i];
        if (ev == &f->ev_written || ev == &f->ev_freed) {
            *out = f;
            return 1;
        }
    }
    return 0;
}

typedef struct sbuf {
    char *s;
    size_t n, cap;
} sbuf;

static void sb_printf(sbuf *b, const char *fmt, ...)
{
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int k = vsnprintf(b->s ? b->s + b->n : NULL, b->s ? b->cap - b->n : 0, fmt, ap);
        va_end(ap);
        if (k < 0)
            return;
        if (b->s && b->n + (size_t)k < b->cap) {
            b->n += (size_t)k;
            return;
        }
        b->cap = (b->cap + (size_t)k + 1) * 2;
        b->s = ks__xrealloc(b->s, b->cap);
    }
}

static void sb_waits(sbuf *b, const ks_sim *sim, ks_event *const *evs, uint32_t n)
{
    if (n == 0) {
        sb_printf(b, " (no wake-up events)");
        return;
    }
    sb_printf(b, " waits on:");
    for (uint32_t i = 0; i < n; i++) {
        const ks_fifo *f;
        sb_printf(b, "%s %s", i ? "," : "", evs[i]->name);
        if (fifo_event_owner(sim, evs[i], &f))
            sb_printf(b, " [fifo %u/%u%s]", f->count, f->capacity,
                      f->count == f->capacity ? " full" : f->count == 0 ? " empty" : "");
    }
}

/* Work is pending when a FIFO holds items, a unit says it is busy, or a
 * clocked process asked to be stepped again. */
static int work_pending(const ks_sim *sim)
{
    for (size_t i = 0; i < sim->n_fifos; i++)
        if (sim->fifos[i]->count)
            return 1;
    for (size_t i = 0; i < sim->n_clocks; i++) {
        const ks_clock *c = sim->clocks[i];
        if (ks__clock_any_awake(c))
            return 1;
        for (uint32_t j = 0; j < c->n_procs; j++)
            if (c->procs[j]->busy && c->procs[j]->busy(c->procs[j]->user))
                return 1;
    }
    for (size_t i = 0; i < sim->n_methods; i++)
        if (sim->methods[i]->busy && sim->methods[i]->busy(sim->methods[i]->user))
            return 1;
    return 0;
}

static ks_time ref_period(const ks_sim *sim)
{
    return sim->n_clocks ? sim->clocks[0]->period : KS_DEFAULT_PERIOD_PS;
}

static void build_report(ks_sim *sim, const char *why)
{
    sbuf b = {0};
    char line[512];
    sb_printf(&b, "deadlock at t=%lld ps: %s\n", (long long)sim->now, why);
    sb_printf(&b, "last progress at t=%lld ps (total progress %llu)\n",
              (long long)sim->last_progress, (unsigned long long)sim->progress);
    sb_printf(&b, "processes:\n");
    for (size_t i = 0; i < sim->n_clocks; i++) {
        const ks_clock *c = sim->clocks[i];
        for (uint32_t j = 0; j < c->n_procs; j++) {
            const ks_clocked *p = c->procs[j];
            int awake = (c->awake[j >> 6] >> (j & 63)) & 1;
            int busy = p->busy ? p->busy(p->user) : -1;
            sb_printf(&b, "  %s (clocked on %s, %s%s)", p->name, c->name, awake ? "awake" : "asleep",
                      busy < 0 ? "" : busy ? ", busy" : ", idle");
            sb_waits(&b, sim, p->wake_events, p->n_wake);
            if (p->describe) {
                line[0] = 0;
                p->describe(p->user, line, sizeof line);
                sb_printf(&b, "; state: %s", line);
            }
            sb_printf(&b, "\n");
        }
    }
    for (size_t i = 0; i < sim->n_methods; i++) {
        const ks_method *m = sim->methods[i];
        if (m->clock)
            continue;
        int busy = m->busy ? m->busy(m->user) : -1;
        sb_printf(&b, "  %s (method%s)", m->name, busy < 0 ? "" : busy ? ", busy" : ", idle");
        if (m->dyn_mode == KS_DYN_EVENT || m->dyn_mode == KS_DYN_EVENT_TIMEOUT)
            sb_waits(&b, sim, &m->dyn_event, 1);
        else
            sb_waits(&b, sim, m->sens, m->n_sens);
        if (m->describe) {
            line[0] = 0;
            m->describe(m->user, line, sizeof line);
            sb_printf(&b, "; state: %s", line);
        }
        sb_printf(&b, "\n");
    }
    sb_printf(&b, "channels holding items or full:\n");
    int any = 0;
    for (size_t i = 0; i < sim->n_fifos; i++) {
        const ks_fifo *f = sim->fifos[i];
        if (!f->count && f->capacity)
            continue;
        any = 1;
        sb_printf(&b, "  %s: %u/%u entries%s, oldest ready at t=%lld ps\n", f->name, f->count,
                  f->capacity, f->count == f->capacity ? " (full)" : "",
                  (long long)f->ready[f->head]);
    }
    if (!any)
        sb_printf(&b, "  (none)\n");
    free(sim->report);
    sim->report = b.s ? b.s : ks__xstrdup("");
}

/* ---- the run loop ---- */

static void init_new_methods(ks_sim *sim)
{
    while (sim->n_uninit_from < sim->n_methods)
        ks__method_init(sim, sim->methods[sim->n_uninit_from++]);
}

ks_run_status ks_sim_run(ks_sim *sim, ks_time until)
{
    sim->stop = 0;
    sim->running = 1;
    sim->until = until;
    ks_run_status st;
    for (size_t i = 0; i < sim->n_clocks; i++)
        ks__clock_start(sim->clocks[i]);
    for (;;) {
        /* evaluate */
        if (sim->n_uninit_from < sim->n_methods)
            init_new_methods(sim);
        /* the index lives in the sim: a clock's stepper may go on ticking
         * in place (clock.c), replacing its own entry */
        for (sim->run_i = 0; sim->run_i < sim->n_run; sim->run_i++) {
            ks_method *m = sim->run[sim->run_i];
            m->runnable = 0;
            m->runs++;
            sim->activations++;
            m->fn(m->user);
        }
        sim->n_run = 0;
        /* update */
        if (sim->n_upd) {
            for (size_t i = 0; i < sim->n_upd; i++)
                ks__signal_update(sim->upd[i]);
            sim->n_upd = 0;
        }
        if (sim->stop) {
            st = KS_RUN_STOPPED;
            break;
        }
        /* delta notification (entries pushed while firing go to the next
         * round: swap the lists first) */
        if (sim->n_delta) {
            /* Firing only makes methods runnable; it never adds delta
             * entries, so the list is walked in place. */
            ks_dentry *d = sim->delta;
            size_t nd = sim->n_delta;
            for (size_t i = 0; i < nd; i++) {
                if (d[i].key == 0) { /* event: valid while still delta-pending */
                    ks_event *ev = d[i].obj;
                    if (ev && ev->pending == KS_PEND_DELTA) {
                        ev->pending = KS_PEND_NONE;
                        event_trigger(sim, ev);
                    }
                } else {
                    fire_entry(d[i].obj, d[i].key);
                }
            }
            sim->n_delta = 0;
        }
        if (sim->n_run || sim->n_delta || sim->n_uninit_from < sim->n_methods) {
            sim->deltas++;
            continue;
        }
        /* advance time */
        if (sim->n_heap == 0 && sim->n_cq == 0) {
            if (sim->dl_cycles && sim->n_clocked && work_pending(sim)) {
                build_report(sim, "nothing is left to run but work is pending");
                st = KS_RUN_DEADLOCK;
            } else {
                st = KS_RUN_FINISHED;
            }
            break;
        }
        /* the earliest of the timed queue and the clock queue; clock ticks
         * fire first at equal times (their keys sort below all others) */
        ks_time t = sim->n_heap ? q_min(sim)->t : KS_TIME_MAX;
        int clocks_due = 0;
        if (sim->n_cq && sim->cq[sim->n_cq - 1]->tick_t <= t) {
            t = sim->cq[sim->n_cq - 1]->tick_t;
            clocks_due = 1;
        }
        if (t > until) {
            sim->now = until;
            st = KS_RUN_TIME_LIMIT;
            break;
        }
        if (sim->dl_cycles && sim->n_clocked &&
            t - sim->last_progress > (ks_time)sim->dl_cycles * ref_period(sim)) {
            if (work_pending(sim)) {
                char why[160];
                snprintf(why, sizeof why, "no progress for %llu cycles while work is pending",
                         (unsigned long long)sim->dl_cycles);
                build_report(sim, why);
                st = KS_RUN_DEADLOCK;
                break;
            }
            sim->last_progress = t;
        }
        sim->now = t;
        if (clocks_due)
            ks__clock_fire_due(sim, t);
        while (sim->n_heap && q_min(sim)->t == t) {
            ks_qentry e = *q_min(sim);
            q_pop(sim);
            fire_entry(e.obj, e.key);
        }
        sim->deltas++;
    }
    sim->running = 0;
    return st;
}
