/* clock.c — clocks and clocked processes with idle skipping (contract in
 * clock.h).
 *
 * Each clock keeps bits per process: `awake` (step at the next tick; a
 * delta/immediate wake-up during a tick sets it for a process later in the
 * order than the one stepping, which the tick's scan then reaches) and
 * `woken` (woken for the next tick while a tick is running, merged after
 * it), plus a min-heap of timers (cycle, process) for wake-ups further
 * ahead.
 * The clock itself is one entry in the sim's timed queue, at the next cycle
 * where any process is due; when none is, the clock is not scheduled at all,
 * so idle cycles cost nothing. When its next edge is also the next thing to
 * happen in the whole sim (nothing else runnable, pending or due before it),
 * the clock advances time and ticks again in place, doing what the
 * scheduler's round trip would (time, delta count, activation counters). */
#include <stdlib.h>
#include <string.h>

#include "kernel/sim_internal.h"

static void clock_step(void *user);

ks_clock *ks_clock_create(ks_sim *sim, const char *name, ks_time period)
{
    if (period < 0) {
        ks__set_error(sim, "clock '%s': period %lld ps must be > 0", name ? name : "?",
                      (long long)period);
        return NULL;
    }
    if (sim->n_clocks >= KS_CLOCK_KEY_RANGE) {
        ks__set_error(sim, "clock '%s': more than %d clocks", name ? name : "?", KS_CLOCK_KEY_RANGE);
        return NULL;
    }
    ks_clock *c = ks__xcalloc(1, sizeof *c);
    c->sim = sim;
    c->idx = (uint32_t)sim->n_clocks;
    c->name = ks__xstrdup(name ? name : "clk");
    c->period = period ? period : KS_DEFAULT_PERIOD_PS;
    c->stepper = ks__method_new(sim, c->name, clock_step, c);
    c->stepper->clock = c;
    c->stepper->dont_init = 1;
    char evname[256];
    snprintf(evname, sizeof evname, "%s.posedge", c->name);
    ks_event_init(&c->posedge, sim, evname);
    KS_GROW(sim->clocks, sim->n_clocks, sim->cap_clocks);
    sim->clocks[sim->n_clocks++] = c;
    KS_GROW(sim->cq, sim->n_clocks - 1, sim->cap_cq); /* one clock-queue entry each */
    return c;
}

void ks__clock_free(ks_clock *c)
{
    for (uint32_t i = 0; i < c->n_procs; i++) {
        free(c->procs[i]->name);
        free(c->procs[i]->wake_events);
        free(c->procs[i]);
    }
    ks_event_destroy(&c->posedge);
    free(c->procs);
    free(c->awake);
    free(c->woken);
    free(c->timers);
    free(c->name);
    free(c);
}

const char *ks_clock_name(const ks_clock *c) { return c->name; }
ks_time ks_clock_period(const ks_clock *c) { return c->period; }
uint64_t ks_clock_cycle(const ks_clock *c) { return c->cur_cycle; }
uint64_t ks_clock_ticks(const ks_clock *c) { return c->ticks; }
ks_time ks_clock_time_of(const ks_clock *c, uint64_t cycle) { return (ks_time)cycle * c->period; }
ks_event *ks_clock_posedge(ks_clock *c) { return &c->posedge; }

uint64_t ks_clock_cycle_at_or_after(const ks_clock *c, ks_time t)
{
    if (t <= 0)
        return 0;
    return (uint64_t)((t + c->period - 1) / c->period);
}

int ks__clock_any_awake(const ks_clock *c)
{
    for (uint32_t w = 0; w < c->n_words; w++)
        if (c->awake[w] | c->woken[w])
            return 1;
    return 0;
}

/* ---- scheduling of the clock's own tick ----
 * A scheduled tick is an entry in the sim's clock queue (sched_types.h), not
 * in the general timed queue: with a few clocks, comparing their next edges
 * is cheaper than a queue round trip. The order is the same as a timed-queue
 * entry with key (idx << 2) | KS_K_CLOCK would have (below every other key):
 * ticks due at one time fire in creation order, before other entries of that
 * time. A tick superseded by an earlier one stays in the timed queue as a
 * void entry, as it did when ticks were timed-queue entries, so that the
 * scheduler still stops at its time (time, delta count, time limit and
 * deadlock checks unchanged); it fires nothing unless it matches the clock's
 * scheduled edge (ks__clock_tick_entry). */

static inline int cq_before(const ks_clock *a, const ks_clock *b)
{
    return a->tick_t < b->tick_t || (a->tick_t == b->tick_t && a->idx < b->idx);
}

/* (capacity: one entry per clock, reserved by ks_clock_create) */
static inline void cq_insert(ks_sim *sim, ks_clock *c)
{
    uint32_t i = sim->n_cq++;
    while (i > 0 && cq_before(sim->cq[i - 1], c)) {
        sim->cq[i] = sim->cq[i - 1];
        i--;
    }
    sim->cq[i] = c;
    c->in_cq = 1;
}

/* Drops c's clock-queue entry, leaving a void one in the timed queue. */
static void cq_supersede(ks_sim *sim, ks_clock *c)
{
    uint32_t i = 0;
    while (sim->cq[i] != c)
        i++;
    for (; i + 1 < sim->n_cq; i++)
        sim->cq[i] = sim->cq[i + 1];
    sim->n_cq--;
    c->in_cq = 0;
    ks__heap_push(sim, c->tick_t, ((uint64_t)c->idx << 2) | KS_K_CLOCK, c);
}

static inline void schedule_tick(ks_clock *c, uint64_t cycle)
{
    ks_sim *sim = c->sim;
    c->scheduled = 1;
    c->sched_cycle = cycle;
    ks_time t = ks_clock_time_of(c, cycle);
    if (t < sim->now)
        t = sim->now; /* cannot happen for cycle >= next_min; defensive */
    if (c->in_cq)
        cq_supersede(sim, c);
    c->tick_t = t;
    cq_insert(sim, c);
}

/* A clock's entry firing at now: its stepper runs when the entry is for the
 * scheduled edge. */
static inline void clock_fire(ks_clock *c)
{
    if (!c->scheduled || ks_clock_time_of(c, c->sched_cycle) != c->sim->now)
        return; /* superseded by an earlier reschedule */
    ks__make_runnable(c->sim, c->stepper);
}

void ks__clock_tick_entry(ks_clock *c, uint64_t key)
{
    (void)key; /* fixed per clock: an entry is current when its time is the scheduled edge's */
    clock_fire(c);
}

void ks__clock_fire_due(ks_sim *sim, ks_time t)
{
    while (sim->n_cq && sim->cq[sim->n_cq - 1]->tick_t == t) {
        ks_clock *c = sim->cq[--sim->n_cq];
        c->in_cq = 0;
        clock_fire(c);
    }
}

/* ---- timers ---- */

static inline int tless(const ks_timer *a, const ks_timer *b)
{
    return a->cycle < b->cycle || (a->cycle == b->cycle && a->idx < b->idx);
}

static void timer_push(ks_clock *c, uint64_t cycle, uint32_t idx)
{
    KS_GROW(c->timers, c->n_timers, c->cap_timers);
    ks_timer e = {cycle, idx, 0};
    uint32_t i = c->n_timers++;
    while (i > 0) {
        uint32_t p = (i - 1) >> 1;
        if (!tless(&e, &c->timers[p]))
            break;
        c->timers[i] = c->timers[p];
        i = p;
    }
    c->timers[i] = e;
}

static void timer_pop(ks_clock *c)
{
    uint32_t n = --c->n_timers;
    if (n == 0)
        return;
    ks_timer last = c->timers[n];
    uint32_t i = 0;
    for (;;) {
        uint32_t l = 2 * i + 1;
        if (l >= n)
            break;
        if (l + 1 < n && tless(&c->timers[l + 1], &c->timers[l]))
            l++;
        if (!tless(&c->timers[l], &last))
            break;
        c->timers[i] = c->timers[l];
        i = l;
    }
    c->timers[i] = last;
}

/* ---- waking ---- */

/* Before the clock's scheduled tick moves earlier: the processes woken for
 * it must still step at that later cycle, so their woken bits become
 * timers. */
static void keep_woken_for_scheduled_tick(ks_clock *c)
{
    if (!c->scheduled)
        return;
    for (uint32_t w = 0; w < c->n_words; w++)
        for (uint64_t m = c->woken[w]; m; m &= m - 1) {
            uint32_t idx = w * 64 + (uint32_t)__builtin_ctzll(m);
            ks_clocked *q = c->procs[idx];
            if (q->last_timer != c->sched_cycle) {
                q->last_timer = c->sched_cycle;
                timer_push(c, c->sched_cycle, idx);
            }
        }
}

/* Process p's clock has an edge (cycle k) at now that it has not ticked,
 * and the clock ticking now precedes it in creation order: in the
 * exhaustive mode it would tick after that one in this evaluation phase,
 * so it does, with p awake. Its stepper goes into the run list right after
 * the ticking clock's and the steppers of clocks created before it. */
static void tick_later_in_this_edge(ks_clocked *p, uint64_t k)
{
    ks_clock *c = p->clk;
    ks_sim *sim = c->sim;
    if (c->scheduled && c->sched_cycle == k) {
        /* its entry fired with the ticking clock's: the stepper is runnable */
        c->woken[p->idx >> 6] |= p->bit;
        return;
    }
    keep_woken_for_scheduled_tick(c);
    c->woken[p->idx >> 6] |= p->bit;
    c->scheduled = 1;
    c->sched_cycle = k;
    if (c->in_cq) /* its entry for the old cycle is now void */
        cq_supersede(sim, c);
    ks_method *st = c->stepper;
    if (st->runnable)
        return;
    size_t j = sim->run_i; /* the ticking clock's stepper */
    for (j++; j < sim->n_run; j++) {
        const ks_clock *o = sim->run[j]->clock;
        if (!o || o->idx > c->idx)
            break;
    }
    if (sim->n_run == sim->cap_run)
        ks__grow_run(sim);
    memmove(&sim->run[j + 1], &sim->run[j], (sim->n_run - j) * sizeof *sim->run);
    sim->run[j] = st;
    sim->n_run++;
    st->runnable = 1;
}

static void wake_cycle(ks_clocked *p, uint64_t k)
{
    ks_clock *c = p->clk;
    if (k < c->next_min)
        k = c->next_min;
    uint64_t bit = (uint64_t)1 << (p->idx & 63);
    if (c->in_tick) {
        /* next_min == cur_cycle + 1 here */
        if (k == c->next_min)
            c->woken[p->idx >> 6] |= bit;
        else if (p->last_timer != k) {
            p->last_timer = k;
            timer_push(c, k, p->idx);
        }
        return;
    }
    if (!c->scheduled || k < c->sched_cycle) {
        keep_woken_for_scheduled_tick(c);
        schedule_tick(c, k);
    }
    if (k == c->sched_cycle)
        c->woken[p->idx >> 6] |= bit;
    else if (p->last_timer != k) {
        p->last_timer = k;
        timer_push(c, k, p->idx);
    }
}

void ks__clocked_wake_after_now(ks_clocked *p)
{
    ks_clock *c = p->clk;
    ks_sim *sim = c->sim;
    ks_time now = sim->now;
    uint64_t k;
    if (c->in_tick) { /* in this tick if p steps later in it, else the next */
        ks__clocked_wake_in_tick(p);
        return;
    }
    if (c->started && now >= c->cur_time && now < c->next_time) {
        /* at or after the last edge, before the next: no division, and now
         * is an edge of this clock only when it is the last one */
        k = c->cur_cycle + 1;
        if (c->scheduled && k == c->sched_cycle) { /* wake_cycle's outcome, directly */
            *p->woken_word |= p->bit;
            return;
        }
    } else {
        k = (uint64_t)(now / c->period);
        if (now % c->period == 0 && sim->ticking && sim->ticking->idx < c->idx) {
            tick_later_in_this_edge(p, k);
            return;
        }
        k++;
    }
    wake_cycle(p, k);
}

void ks__clocked_wake_at_time(ks_clocked *p, ks_time t)
{
    ks_clock *c = p->clk;
    uint64_t k;
    if (c->started && t == c->cur_time + c->period) {
        k = c->cur_cycle + 1;
        if (c->scheduled && k == c->sched_cycle) { /* wake_cycle's outcome, directly */
            *p->woken_word |= p->bit;
            return;
        }
    } else
        k = ks_clock_cycle_at_or_after(c, t);
    wake_cycle(p, k);
}

void ks_clocked_wake(ks_clocked *p) { ks__clocked_wake_after_now(p); }
void ks_clocked_wake_at_cycle(ks_clocked *p, uint64_t cycle) { wake_cycle(p, cycle); }

/* ---- processes ---- */

ks_clocked *ks_clocked_create(ks_clock *c, const char *name, ks_step_fn step, void *user)
{
    ks_sim *sim = c->sim;
    if (!step) {
        ks__set_error(sim, "clocked process '%s': no step function", name ? name : "?");
        return NULL;
    }
    ks_clocked *p = ks__xcalloc(1, sizeof *p);
    p->clk = c;
    p->name = ks__xstrdup(name ? name : "clocked");
    p->step = step;
    p->user = user;
    p->idx = c->n_procs;
    p->last_timer = UINT64_MAX;
    KS_GROW(c->procs, c->n_procs, c->cap_procs);
    c->procs[c->n_procs++] = p;
    uint32_t words = (c->n_procs + 63) / 64;
    if (words > c->n_words) {
        c->awake = ks__xrealloc(c->awake, words * sizeof *c->awake);
        c->woken = ks__xrealloc(c->woken, words * sizeof *c->woken);
        c->awake[words - 1] = c->woken[words - 1] = 0;
        c->n_words = words;
        for (uint32_t i = 0; i < c->n_procs; i++) {
            c->procs[i]->awake_word = &c->awake[i >> 6];
            c->procs[i]->woken_word = &c->woken[i >> 6];
        }
    }
    p->bit = (uint64_t)1 << (p->idx & 63);
    p->awake_word = &c->awake[p->idx >> 6];
    p->woken_word = &c->woken[p->idx >> 6];
    sim->n_clocked++;
    /* Starts awake at the first edge at or after now that has not ticked. */
    uint64_t k = ks_clock_cycle_at_or_after(c, sim->now);
    if (c->started && k <= c->cur_cycle)
        k = c->cur_cycle + 1;
    wake_cycle(p, k);
    return p;
}

const char *ks_clocked_name(const ks_clocked *p) { return p->name; }
ks_clock *ks_clocked_clock(const ks_clocked *p) { return p->clk; }
uint64_t ks_clocked_steps(const ks_clocked *p) { return p->steps; }
uint64_t ks_clocked_progress(const ks_clocked *p) { return p->progress; }

void ks_clocked_wake_on(ks_clocked *p, ks_event *ev)
{
    KS_GROW(ev->clocked, ev->n_clocked, ev->cap_clocked);
    ev->clocked[ev->n_clocked++] = p;
    ev->any_waiters = 1;
    ks__event_refresh(ev);
    KS_GROW(p->wake_events, p->n_wake, p->cap_wake);
    p->wake_events[p->n_wake++] = ev;
}

void ks_clocked_sleep_until_cycle(ks_clocked *p, uint64_t cycle)
{
    /* Effective from p's own step only (the step resets `slept` after
     * reading it, so that steps need not clear it first); a call made
     * anywhere else has no effect, as when each step began by clearing it. */
    const ks_clock *c = p->clk;
    if (c->in_tick && c->stepping == p->idx) {
        p->slept = 1;
        p->sleep_until = cycle;
    }
}

void ks_clocked_set_describe(ks_clocked *p, ks_busy_fn busy, ks_describe_fn describe)
{
    p->busy = busy;
    p->describe = describe;
}

void ks_clock_set_exhaustive(ks_clock *c, int on) { c->exhaustive = (uint8_t)(on != 0); }

/* ---- the tick ---- */

/* Steps process p (index i); returns its progress. The awake bit of a
 * process being stepped is set; it is cleared when the process goes to
 * sleep. `slept` is 0 outside p's step (ks_clocked_sleep_until_cycle). */
static inline __attribute__((always_inline)) uint64_t step_one(ks_clock *c, ks_clocked *p,
                                                                uint32_t i, uint64_t cycle,
                                                                int exhaustive)
{
    c->stepping = i;
    int r = p->step(p->user, cycle);
    p->steps++;
    if (r > 0) {
        p->progress += (uint64_t)r;
        if (!p->slept) {
            if (exhaustive)
                c->awake[i >> 6] |= p->bit;
            return (uint64_t)r;
        }
    }
    c->awake[i >> 6] &= ~p->bit;
    if (p->slept) {
        p->slept = 0;
        if (p->sleep_until > cycle && p->last_timer != p->sleep_until) {
            p->last_timer = p->sleep_until;
            timer_push(c, p->sleep_until, i);
        }
    }
    return r > 0 ? (uint64_t)r : 0;
}

/* Exhaustive mode: is anything besides clock c still to happen (another
 * clock's awake process or timer, or a timed entry of a method or event)?
 * While so, c ticks every cycle; when not, the simulation is over unless a
 * wake-up restarts it, as with idle skipping. */
static int sim_has_other_work(ks_sim *sim, const ks_clock *c)
{
    for (size_t i = 0; i < sim->n_clocks; i++) {
        const ks_clock *o = sim->clocks[i];
        if (o != c && (o->n_timers || ks__clock_any_awake(o)))
            return 1;
    }
    return ks__queue_has_non_clock(sim);
}

/* awake |= woken, woken = 0; returns whether any process is awake. One
 * word (up to 64 processes) without the loop. */
static inline int merge_woken(ks_clock *c, uint32_t nw)
{
    if (nw == 1) {
        uint64_t a = c->awake[0] | c->woken[0];
        c->awake[0] = a;
        c->woken[0] = 0;
        return a != 0;
    }
    int any = 0;
    for (uint32_t w = 0; w < nw; w++) {
        c->awake[w] |= c->woken[w];
        c->woken[w] = 0;
        any |= c->awake[w] != 0;
    }
    return any;
}

/* One tick at `cycle` (time sim->now); returns the next cycle to tick or
 * UINT64_MAX. */
static inline uint64_t tick(ks_clock *c, ks_sim *sim, uint64_t cycle)
{
    c->cur_cycle = cycle;
    c->cur_time = sim->now;
    c->next_time = sim->now + c->period;
    c->next_min = cycle + 1;
    c->started = 1;
    c->in_tick = 1;
    sim->ticking = c;
    c->ticks++;
    uint32_t nw = c->n_words;
    while (c->n_timers && c->timers[0].cycle <= cycle) {
        uint32_t i = c->timers[0].idx;
        c->awake[i >> 6] |= (uint64_t)1 << (i & 63);
        if (c->procs[i]->last_timer == c->timers[0].cycle)
            c->procs[i]->last_timer = UINT64_MAX;
        timer_pop(c);
    }
    merge_woken(c, nw);
    uint64_t progress = 0, steps = 0;
    if (c->exhaustive) {
        for (uint32_t i = 0; i < c->n_procs; i++)
            progress += step_one(c, c->procs[i], c->procs[i]->idx, cycle, 1);
        steps = c->n_procs;
    } else {
        ks_clocked **procs = c->procs;
        if (nw == 1) { /* up to 64 processes: one word, the bit is the index */
            uint64_t bits = c->awake[0];
            while (bits) {
                uint32_t b = (uint32_t)__builtin_ctzll(bits);
                progress += step_one(c, procs[b], b, cycle, 0);
                steps++;
                bits &= bits - 1;
                if (c->woke_later) {
                    c->woke_later = 0;
                    bits = c->awake[0] & (~(uint64_t)1 << b);
                }
            }
        } else for (uint32_t w = 0; w < nw; w++) {
            uint64_t bits = c->awake[w];
            while (bits) {
                uint32_t b = (uint32_t)__builtin_ctzll(bits);
                ks_clocked *p = procs[(w << 6) | b];
                progress += step_one(c, p, p->idx, cycle, 0);
                steps++;
                bits &= bits - 1;
                if (c->woke_later) { /* re-read: processes after b woken by it */
                    c->woke_later = 0;
                    bits = c->awake[w] & (~(uint64_t)1 << b);
                }
            }
        }
    }
    sim->activations += steps;
    if (progress) {
        sim->progress += progress;
        sim->last_progress = sim->now;
    }
    c->in_tick = 0;
    sim->ticking = NULL;
    if (c->posedge.n_statics || c->posedge.dyn_head)
        ks_event_notify(&c->posedge);
    int any = merge_woken(c, nw); /* woken for the next cycle */
    uint64_t next = UINT64_MAX;
    if (any || c->posedge.n_statics)
        next = cycle + 1;
    else if (c->exhaustive)
        next = c->n_timers || sim_has_other_work(sim, c) ? cycle + 1 : UINT64_MAX;
    else if (c->n_timers)
        next = c->timers[0].cycle;
    return next;
}

/* Would the scheduler, after this activation, go straight on to the next
 * time with nothing else to do? Only when the activation is the last
 * runnable one, no delta or update is pending, no stop request, no new
 * method to initialise. */
static inline int nothing_else_now(const ks_sim *sim)
{
    return sim->run_i + 1 == sim->n_run && !sim->n_delta && !sim->n_upd && !sim->stop &&
           sim->n_uninit_from >= sim->n_methods;
}

/* ... and would the next time be t, reached without stopping: t within the
 * run's limit, the deadlock detector silent at t, and no timed-queue entry
 * at or before t (those fire after the clocks of their time). */
static inline int next_time_clear(ks_sim *sim, ks_time t)
{
    if (t > sim->until)
        return 0;
    if (sim->dl_cycles && sim->n_clocked &&
        t - sim->last_progress > (ks_time)sim->dl_cycles * sim->clocks[0]->period)
        return 0;
    return sim->n_heap == 0 || ks__queue_clear_until(sim, t);
}

/* After an activation that scheduled this clock's next tick (or none):
 * when the scheduler would next advance time to the clock queue's first
 * entry and fire only clock ticks there, do that here (time, delta count,
 * the steppers made runnable in creation order) and return the clock whose
 * stepper is now running in place of the finished one (its run count and
 * the activation counted); the steppers of other clocks due at that time
 * stay in the run list after it, for the scheduler's evaluation loop. NULL
 * when the scheduler has to take over (nothing changed then, or time was
 * advanced with nothing made runnable, where the scheduler goes on as it
 * would have). */
static ks_clock *advance_to_next_edge(ks_sim *sim)
{
    if (!sim->n_cq || !nothing_else_now(sim))
        return NULL;
    ks_time t = sim->cq[sim->n_cq - 1]->tick_t;
    if (!next_time_clear(sim, t))
        return NULL;
    sim->now = t;
    sim->n_run = sim->run_i; /* the finished activation's slot is reused */
    ks__clock_fire_due(sim, t);
    sim->deltas++;
    if (sim->n_run == sim->run_i)
        return NULL;
    ks_method *m = sim->run[sim->run_i];
    m->runnable = 0;
    m->runs++;
    sim->activations++;
    return m->clock;
}

/* The clock's method: ticks, and as long as the next thing to happen in the
 * whole sim is an edge of this or another clock, advances time and ticks
 * that clock here (the same steps, deltas and counters as going through the
 * scheduler). */
static void clock_step(void *user)
{
    ks_clock *c = user;
    ks_sim *sim = c->sim;
    uint64_t cycle = c->sched_cycle;
    c->scheduled = 0;
    for (;;) {
        uint64_t next = tick(c, sim, cycle);
        if (c->scheduled)
            return;
        if (next != UINT64_MAX && nothing_else_now(sim)) {
            ks_time tn = next == cycle + 1 ? c->next_time : ks_clock_time_of(c, next);
            ks_clock *d = sim->n_cq ? sim->cq[sim->n_cq - 1] : NULL;
            if (!d || tn < d->tick_t || (tn == d->tick_t && c->idx < d->idx)) {
                /* this clock's edge is next: tick again here */
                if (!next_time_clear(sim, tn)) {
                    schedule_tick(c, next);
                    return;
                }
                sim->now = tn;
                sim->deltas++;
                c->stepper->runs++;
                sim->activations++;
                cycle = next;
                continue;
            }
            ks_time t = d->tick_t;
            if (t != tn && (sim->n_cq < 2 || sim->cq[sim->n_cq - 2]->tick_t != t) && d->scheduled &&
                ks_clock_time_of(d, d->sched_cycle) == t && next_time_clear(sim, t)) {
                /* clock d's edge alone is next: its entry fires, its stepper
                 * runs in place of this one */
                sim->n_cq--;
                d->in_cq = 0;
                schedule_tick(c, next);
                sim->now = t;
                sim->deltas++;
                sim->run[sim->run_i] = d->stepper;
                d->stepper->runs++;
                sim->activations++;
                c = d;
                cycle = d->sched_cycle;
                d->scheduled = 0;
                continue;
            }
        }
        if (next != UINT64_MAX)
            schedule_tick(c, next);
        c = advance_to_next_edge(sim);
        if (!c)
            return;
        cycle = c->sched_cycle;
        c->scheduled = 0;
    }
}

/* Called at the start of each run: a clock whose posedge has method
 * waiters ticks every cycle even with no clocked process awake. */
void ks__clock_start(ks_clock *c)
{
    if (c->posedge.n_statics && !c->scheduled && !c->in_tick) {
        uint64_t k = ks_clock_cycle_at_or_after(c, c->sim->now);
        if (k < c->next_min)
            k = c->next_min;
        schedule_tick(c, k);
    }
}
