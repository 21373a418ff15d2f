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

/* ---- timed queue order against a reference ----
 * 40 methods re-arm themselves with next_trigger_time after delays mixing
 * equal small ones (many ties) and huge ones (up to 2^38 ps, crossing the
 * queue's digit boundaries); the run is cut into slices by time limits and
 * after each slice an event is notified 1 ps after the stop time (earlier
 * than entries the queue already looked at). Every activation must be the
 * (time, arming order) minimum of a reference list of pending arms. */
enum { QO_PROCS = 40, QO_MAX = 4096 };
typedef struct qo_arm {
    ks_time t;
    uint64_t seq;
    int id;
} qo_arm;
static qo_arm qo_pend[QO_PROCS + 64];
static int qo_npend, qo_acts, qo_bad, qo_inits;
static uint64_t qo_seq, qo_rng = 12345;
static ks_method *qo_m[QO_PROCS + 1];
static int qo_id[QO_PROCS + 1];
static ks_event qo_ev;
static uint64_t qo_next(void)
{
    qo_rng = qo_rng * 6364136223846793005ull + 1442695040888963407ull;
    return qo_rng >> 24;
}
static void qo_check(int id)
{
    ks_time now = ks_sim_now(g_sim);
    int best = -1;
    for (int i = 0; i < qo_npend; i++)
        if (best < 0 || qo_pend[i].t < qo_pend[best].t ||
            (qo_pend[i].t == qo_pend[best].t && qo_pend[i].seq < qo_pend[best].seq))
            best = i;
    if (best < 0 || qo_pend[best].id != id || qo_pend[best].t != now) {
        if (!qo_bad)
            TB_CHECK(0, "activation %d: process %d at %lld, expected %d at %lld", qo_acts, id,
                     (long long)now, best < 0 ? -1 : qo_pend[best].id,
                     best < 0 ? -1LL : (long long)qo_pend[best].t);
        qo_bad = 1;
        return;
    }
    qo_pend[best] = qo_pend[--qo_npend];
}
static void qo_proc(void *u)
{
    int id = *(int *)u;
    int armed = 0;
    for (int i = 0; i < qo_npend; i++)
        armed |= qo_pend[i].id == id;
    if (armed || id == QO_PROCS)
        qo_check(id);
    else
        qo_inits++; /* initialisation run at time 0 */
    if (id == QO_PROCS || ++qo_acts >= QO_MAX)
        return;
    uint64_t r = qo_next();
    ks_time d = r % 4 == 0 ? (ks_time)(1 + qo_next() % ((uint64_t)1 << 38))
                           : (ks_time)(1 + r % 3) * 1000;
    ks_next_trigger_time(qo_m[id], d);
    qo_pend[qo_npend++] = (qo_arm){ks_sim_now(g_sim) + d, ++qo_seq, id};
}
static void test_queue_order(void)
{
    tb_begin("timed_queue_pops_in_time_then_notification_order");
    g_sim = ks_sim_create();
    ks_event_init(&qo_ev, g_sim, "qo.ev");
    for (int i = 0; i <= QO_PROCS; i++) {
        qo_id[i] = i;
        qo_m[i] = ks_method_create(g_sim, "qo", qo_proc, &qo_id[i]);
    }
    ks_method_sensitive(qo_m[QO_PROCS], &qo_ev);
    ks_method_dont_initialize(qo_m[QO_PROCS]);
    int slices = 0;
    while (ks_sim_run(g_sim, ks_sim_now(g_sim) + ((ks_time)1 << 33)) == KS_RUN_TIME_LIMIT &&
           !qo_bad && slices < 100000) {
        slices++;
        ks_event_notify_at(&qo_ev, ks_sim_now(g_sim) + 1);
        qo_pend[qo_npend++] = (qo_arm){ks_sim_now(g_sim) + 1, ++qo_seq, QO_PROCS};
    }
    TB_EQ_INT(qo_inits, QO_PROCS);
    TB_CHECK(qo_acts >= QO_MAX, "%d activations", qo_acts);
    TB_CHECK(slices > 10, "only %d slices", slices);
    TB_EQ_INT(qo_npend, 0);
    ks_event_destroy(&qo_ev);
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
    test_queue_order();
    return tb_finish();
}
