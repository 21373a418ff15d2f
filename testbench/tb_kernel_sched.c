/* tb_kernel_sched — scheduler semantics of the kernel: evaluate/update/delta
 * phases, immediate/delta/timed notification, deterministic order at equal
 * times, static and dynamic (next-trigger) sensitivity, signals. */
#include <string.h>

#include "kernel/event.h"
#include "kernel/process.h"
#include "kernel/signal.h"
#include "kernel/sim.h"
#include "testbench/tb.h"

/* ---- a log of (process tag, time, delta) ---- */
typedef struct logent {
    char tag;
    ks_time t;
    uint64_t delta;
    uint64_t val;
} logent;
static logent logbuf[256];
static int nlog;
static ks_sim *g_sim;
static void logit(char tag, uint64_t val)
{
    if (nlog < 256)
        logbuf[nlog++] = (logent){tag, ks_sim_now(g_sim), ks_sim_delta_count(g_sim), val};
}

/* Signal semantics: writer writes 5 in delta 0; a reader running in the same
 * delta (after the writer) must still see the old value 0; a reader
 * sensitive to the change runs in the next delta and sees 5. */
static ks_signal *g_sig;
static void sig_writer(void *u)
{
    (void)u;
    ks_signal_write(g_sig, 5);
    logit('W', ks_signal_read(g_sig));
}
static void sig_same_delta(void *u)
{
    (void)u;
    logit('S', ks_signal_read(g_sig));
}
static void sig_on_change(void *u)
{
    (void)u;
    logit('C', ks_signal_read(g_sig));
}

static void test_signal_delta(void)
{
    tb_begin("signal_written_in_one_delta_seen_in_the_next");
    g_sim = ks_sim_create();
    nlog = 0;
    g_sig = ks_signal_create(g_sim, "top.sig", 8, 0);
    ks_method_create(g_sim, "writer", sig_writer, NULL);
    ks_method_create(g_sim, "same", sig_same_delta, NULL);
    ks_method *c = ks_method_create(g_sim, "onchange", sig_on_change, NULL);
    ks_method_sensitive(c, ks_signal_ev_changed(g_sig));
    ks_method_dont_initialize(c);
    TB_EQ_INT(ks_sim_run(g_sim, KS_TIME_MAX), KS_RUN_FINISHED);
    TB_EQ_INT(nlog, 3);
    TB_CHECK(logbuf[0].tag == 'W' && logbuf[0].val == 0, "writer reads its own write at once");
    TB_CHECK(logbuf[1].tag == 'S' && logbuf[1].val == 0 && logbuf[1].delta == logbuf[0].delta,
             "same-delta reader saw %llu", (unsigned long long)logbuf[1].val);
    TB_CHECK(logbuf[2].tag == 'C' && logbuf[2].val == 5, "change reader saw %llu",
             (unsigned long long)logbuf[2].val);
    TB_EQ_INT(logbuf[2].delta, logbuf[0].delta + 1);
    TB_EQ_INT(ks_signal_read(g_sig), 5);
    /* writing the same value again is not a change */
    ks_signal_write(g_sig, 5);
    nlog = 0;
    ks_sim_run(g_sim, KS_TIME_MAX);
    TB_EQ_INT(nlog, 0);
    ks_sim_destroy(g_sim);
    tb_end();
}

/* ---- notifications ---- */
typedef struct nctx {
    ks_event ev;
    char tag;
} nctx;
static void on_ev(void *u) { logit(((nctx *)u)->tag, 0); }

static ks_event g_e1;
static int g_mode;
static void notifier(void *u)
{
    (void)u;
    logit('N', 0);
    if (g_mode == 0)
        ks_event_notify(&g_e1);
    else if (g_mode == 1)
        ks_event_notify_delta(&g_e1);
    else if (g_mode == 2)
        ks_event_notify_after(&g_e1, KS_NS(7));
    else if (g_mode == 3) { /* timed then delta: delta wins, fires once */
        ks_event_notify_after(&g_e1, KS_NS(7));
        ks_event_notify_delta(&g_e1);
    } else if (g_mode == 4) { /* later timed does not override earlier */
        ks_event_notify_after(&g_e1, KS_NS(3));
        ks_event_notify_after(&g_e1, KS_NS(9));
    } else if (g_mode == 5) { /* cancelled */
        ks_event_notify_after(&g_e1, KS_NS(3));
        ks_event_cancel(&g_e1);
    }
}
static void waiter(void *u)
{
    (void)u;
    logit('R', 0);
}

static void run_mode(int mode)
{
    g_sim = ks_sim_create();
    nlog = 0;
    g_mode = mode;
    ks_event_init(&g_e1, g_sim, "e1");
    ks_method_create(g_sim, "notifier", notifier, NULL);
    ks_method *w = ks_method_create(g_sim, "waiter", waiter, NULL);
    ks_method_sensitive(w, &g_e1);
    ks_method_dont_initialize(w);
    ks_sim_run(g_sim, KS_TIME_MAX);
}
static void done_mode(void)
{
    ks_event_destroy(&g_e1);
    ks_sim_destroy(g_sim);
}

static void test_notifications(void)
{
    tb_begin("immediate_notification_runs_in_the_same_delta");
    run_mode(0);
    TB_EQ_INT(nlog, 2);
    TB_EQ_INT(logbuf[1].tag, 'R');
    TB_EQ_INT(logbuf[1].delta, logbuf[0].delta);
    TB_EQ_INT(logbuf[1].t, 0);
    done_mode();
    tb_end();

    tb_begin("delta_notification_runs_in_the_next_delta");
    run_mode(1);
    TB_EQ_INT(nlog, 2);
    TB_EQ_INT(logbuf[1].delta, logbuf[0].delta + 1);
    TB_EQ_INT(logbuf[1].t, 0);
    done_mode();
    tb_end();

    tb_begin("timed_notification_runs_at_now_plus_delay");
    run_mode(2);
    TB_EQ_INT(nlog, 2);
    TB_EQ_INT(logbuf[1].t, KS_NS(7));
    TB_EQ_INT(ks_sim_now(g_sim), KS_NS(7));
    TB_EQ_INT(ks_event_trigger_count(&g_e1), 1);
    done_mode();
    tb_end();

    tb_begin("earlier_notification_overrides_later");
    run_mode(3);
    TB_EQ_INT(nlog, 2);
    TB_EQ_INT(logbuf[1].t, 0);
    TB_EQ_INT(ks_event_trigger_count(&g_e1), 1);
    done_mode();
    run_mode(4);
    TB_EQ_INT(nlog, 2);
    TB_EQ_INT(logbuf[1].t, KS_NS(3));
    TB_EQ_INT(ks_event_trigger_count(&g_e1), 1);
    done_mode();
    tb_end();

    tb_begin("cancelled_notification_never_fires");
    run_mode(5);
    TB_EQ_INT(nlog, 1);
    TB_EQ_INT(ks_event_trigger_count(&g_e1), 0);
    done_mode();
    tb_end();
}

/* ---- deterministic order at equal times ---- */
static nctx g_ctx[6];
static void kick(void *u)
{
    (void)u;
    /* notify in a scrambled order, all at 5 ns */
    static const int order[6] = {3, 0, 5, 1, 4, 2};
    for (int i = 0; i < 6; i++)
        ks_event_notify_after(&g_ctx[order[i]].ev, KS_NS(5));
}

static void test_equal_time_order(void)
{
    tb_begin("equal_time_events_fire_in_notification_order");
    char runs[2][8];
    for (int r = 0; r < 2; r++) {
        g_sim = ks_sim_create();
        nlog = 0;
        for (int i = 0; i < 6; i++) {
            char name[16];
            snprintf(name, sizeof name, "e%d", i);
            ks_event_init(&g_ctx[i].ev, g_sim, name);
            g_ctx[i].tag = (char)('0' + i);
            ks_method *m = ks_method_create(g_sim, name, on_ev, &g_ctx[i]);
            ks_method_sensitive(m, &g_ctx[i].ev);
            ks_method_dont_initialize(m);
        }
        ks_method_create(g_sim, "kick", kick, NULL);
        ks_sim_run(g_sim, KS_TIME_MAX);
        for (int i = 0; i < 6 && i < nlog; i++)
            runs[r][i] = logbuf[i].tag;
        runs[r][6] = 0;
        TB_EQ_INT(nlog, 6);
        for (int i = 0; i < 6; i++)
            ks_event_destroy(&g_ctx[i].ev);
        ks_sim_destroy(g_sim);
    }
    TB_CHECK(!strcmp(runs[0], "305142"), "order %s, expected 305142", runs[0]);
    TB_CHECK(!strcmp(runs[0], runs[1]), "two runs differ: %s vs %s", runs[0], runs[1]);
    tb_end();
}

/* ---- dynamic sensitivity ---- */
static ks_method *g_dyn;
static ks_event g_static_ev, g_dyn_ev;
static int g_step;
static void dyn_proc(void *u)
{
    (void)u;
    logit('D', (uint64_t)g_step);
    switch (g_step++) {
    case 0: ks_next_trigger_time(g_dyn, KS_NS(10)); break;      /* -> t=10 */
    case 1: ks_next_trigger_event(g_dyn, &g_dyn_ev); break;     /* -> t=25 via poke */
    case 2: ks_next_trigger_event_timeout(g_dyn, &g_dyn_ev, KS_NS(4)); break; /* timeout at 29 */
    default: break; /* back to static sensitivity */
    }
}
static void poker(void *u)
{
    (void)u;
    /* static event at 12 must not wake the method (waiting on g_dyn_ev) */
    ks_event_notify_at(&g_static_ev, KS_NS(12));
    ks_event_notify_at(&g_dyn_ev, KS_NS(25));
}
static void test_dynamic(void)
{
    tb_begin("next_trigger_overrides_static_sensitivity_once");
    g_sim = ks_sim_create();
    nlog = 0;
    g_step = 0;
    ks_event_init(&g_static_ev, g_sim, "static");
    ks_event_init(&g_dyn_ev, g_sim, "dyn");
    g_dyn = ks_method_create(g_sim, "dyn", dyn_proc, NULL);
    ks_method_sensitive(g_dyn, &g_static_ev);
    ks_method_create(g_sim, "poker", poker, NULL);
    TB_EQ_INT(ks_sim_run(g_sim, KS_NS(100)), KS_RUN_FINISHED);
    /* runs: t=0 (init), 10 (time), 25 (event), 29 (timeout) */
    TB_EQ_INT(nlog, 4);
    if (nlog == 4) {
        TB_EQ_INT(logbuf[0].t, 0);
        TB_EQ_INT(logbuf[1].t, KS_NS(10));
        TB_EQ_INT(logbuf[2].t, KS_NS(25));
        TB_EQ_INT(logbuf[3].t, KS_NS(29));
    }
    /* now statically sensitive again */
    ks_event_notify_at(&g_static_ev, KS_NS(50));
    ks_sim_run(g_sim, KS_NS(100));
    TB_EQ_INT(nlog, 5);
    TB_EQ_INT(logbuf[nlog - 1].t, KS_NS(50));
    TB_EQ_INT(ks_method_runs(g_dyn), 5);
    ks_event_destroy(&g_static_ev);
    ks_event_destroy(&g_dyn_ev);
    ks_sim_destroy(g_sim);
    tb_end();
}

/* ---- run control ---- */
static ks_method *g_tick;
static void ticker(void *u)
{
    (void)u;
    logit('T', 0);
    if (ks_sim_now(g_sim) == KS_NS(30))
        ks_sim_stop(g_sim);
    ks_next_trigger_time(g_tick, KS_NS(10));
}

static void test_run_control(void)
{
    tb_begin("time_limit_stop_and_resume");
    g_sim = ks_sim_create();
    nlog = 0;
    g_tick = ks_method_create(g_sim, "ticker", ticker, NULL);
    TB_EQ_INT(ks_sim_run(g_sim, KS_NS(15)), KS_RUN_TIME_LIMIT);
    TB_EQ_INT(ks_sim_now(g_sim), KS_NS(15));
    TB_EQ_INT(nlog, 2); /* 0, 10 */
    TB_EQ_INT(ks_sim_run(g_sim, KS_TIME_MAX), KS_RUN_STOPPED);
    TB_EQ_INT(ks_sim_now(g_sim), KS_NS(30));
    TB_EQ_INT(nlog, 4);
    TB_EQ_INT(ks_sim_run(g_sim, KS_NS(55)), KS_RUN_TIME_LIMIT);
    TB_EQ_INT(nlog, 6); /* 40, 50 */
    TB_CHECK(!strcmp(ks_run_status_name(KS_RUN_DEADLOCK), "deadlock"), "status name");
    ks_sim_destroy(g_sim);
    tb_end();

    tb_begin("bad_parameters_are_rejected_with_a_message");
    g_sim = ks_sim_create();
    TB_CHECK(ks_signal_create(g_sim, "wide", 65, 0) == NULL, "65-bit signal accepted");
    TB_CHECK(strstr(ks_sim_error(g_sim), "1..64") != NULL, "error: %s", ks_sim_error(g_sim));
    TB_CHECK(ks_method_create(g_sim, "nofn", NULL, NULL) == NULL, "method without function");
    ks_sim_destroy(g_sim);
    tb_end();
}

int main(void)
{
    test_signal_delta();
    test_notifications();
    test_equal_time_order();
    test_dynamic();
    test_run_control();
    return tb_finish();
}
