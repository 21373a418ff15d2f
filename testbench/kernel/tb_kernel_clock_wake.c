/* tb_kernel_clock_wake — a clocked process woken for a future cycle S must
 * still step at S when another process of the same clock later asks for an
 * earlier cycle k < S (the clock's scheduled tick moves to k). The lost
 * wake-up left a line in a FIFO unread forever and livelocked the
 * accelerator with LPDDR3 (docs/accel.md, "LPDDR3 livelock"). Also checked
 * against the exhaustive (every cycle) reference: the same useful steps. */
#include "kernel/clock.h"
#include "kernel/process.h"
#include "kernel/sim.h"
#include "testbench/tb.h"

enum { WANT_A = 100, WANT_B = 50, WAKE_AT = 10 };

typedef struct sleeper {
    uint64_t want;        /* the cycle it has work for */
    uint64_t did_work_at; /* 0 until it found its work */
} sleeper;

static int sleeper_step(void *u, uint64_t cycle)
{
    sleeper *s = u;
    if (s->want && cycle >= s->want && !s->did_work_at) {
        s->did_work_at = cycle;
        return 1;
    }
    return 0;   /* nothing to do: sleep (spurious wake-ups are allowed) */
}

typedef struct waker {
    ks_method *m;
    ks_clock *clk;
    ks_clocked *a, *b;
    sleeper *sa, *sb;
    int fired;
} waker;

/* A timed method at cycle WAKE_AT: first wakes A for cycle 100 (the clock's
 * tick is scheduled there), then B for cycle 50 (the tick moves earlier). */
static void waker_fn(void *u)
{
    waker *w = u;
    if (w->fired++ == 0) {   /* initialisation run at time 0: both processes still run their first steps */
        ks_next_trigger_time(w->m, ks_clock_time_of(w->clk, WAKE_AT) + 1);
        return;
    }
    if (w->fired > 2)
        return;
    w->sa->want = WANT_A;
    ks_clocked_wake_at_cycle(w->a, WANT_A);
    w->sb->want = WANT_B;
    ks_clocked_wake_at_cycle(w->b, WANT_B);
}

static void run_case(const char *name, int exhaustive)
{
    tb_begin(name);
    ks_sim *sim = ks_sim_create();
    ks_clock *clk = ks_clock_create(sim, "clk", 0);
    sleeper sa = {0}, sb = {0};
    ks_clocked *a = ks_clocked_create(clk, "a", sleeper_step, &sa);
    ks_clocked *b = ks_clocked_create(clk, "b", sleeper_step, &sb);
    ks_clock_set_exhaustive(clk, exhaustive);
    waker w = {NULL, clk, a, b, &sa, &sb, 0};
    w.m = ks_method_create(sim, "waker", waker_fn, &w);
    ks_sim_run(sim, ks_clock_time_of(clk, 200));
    TB_EQ_INT(sb.did_work_at, WANT_B);
    TB_EQ_INT(sa.did_work_at, WANT_A);
    ks_sim_destroy(sim);
    tb_end();
}

int main(void)
{
    run_case("kernel_clock_wake_survives_earlier_tick", 0);
    run_case("kernel_clock_wake_exhaustive_reference", 1);
    return tb_finish();
}
