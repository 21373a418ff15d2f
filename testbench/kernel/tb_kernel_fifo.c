/* tb_kernel_fifo — timed FIFO channels and clocked processes: latency,
 * capacity and back-pressure, occupancy statistics, resizing, idle skipping
 * (bit-identical to stepping every process every cycle) and the deadlock
 * detector on a deliberately blocked pair. */
#include <string.h>

#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/process.h"
#include "kernel/sim.h"
#include "testbench/tb.h"

/* ---- latency ---- */
typedef struct lat_ctx {
    ks_fifo *f;
    uint64_t wrote_at, read_at;
    int written, got;
    uint32_t value;
} lat_ctx;

static int lat_prod(void *u, uint64_t cycle)
{
    lat_ctx *c = u;
    if (c->written || cycle < 5)
        return cycle < 5 ? 1 : 0; /* busy until cycle 5, then write once */
    uint32_t v = 42;
    ks_fifo_write(c->f, &v);
    c->written = 1;
    c->wrote_at = cycle;
    return 1;
}

static int lat_cons(void *u, uint64_t cycle)
{
    lat_ctx *c = u;
    if (!ks_fifo_can_read(c->f))
        return 0;
    ks_fifo_read(c->f, &c->value);
    c->got = 1;
    c->read_at = cycle;
    return 1;
}

static void test_latency(void)
{
    for (uint32_t lat = 1; lat <= 4; lat += 3) {
        char name[64];
        snprintf(name, sizeof name, "fifo_latency_%u_cycles", lat);
        tb_begin(name);
        ks_sim *sim = ks_sim_create();
        ks_clock *clk = ks_clock_create(sim, "clk", 0);
        TB_EQ_INT(ks_clock_period(clk), 2000);
        lat_ctx c = {0};
        c.f = ks_fifo_create(sim, "top.ch", sizeof(uint32_t), 4, lat, clk);
        ks_clocked_create(clk, "prod", lat_prod, &c);
        ks_clocked *cons = ks_clocked_create(clk, "cons", lat_cons, &c);
        ks_clocked_wake_on(cons, ks_fifo_ev_written(c.f));
        TB_EQ_INT(ks_sim_run(sim, KS_TIME_MAX), KS_RUN_FINISHED);
        TB_CHECK(c.got && c.value == 42, "item not received");
        TB_EQ_INT(c.wrote_at, 5);
        TB_EQ_INT(c.read_at, 5 + lat);
        /* the consumer slept in between: stepped at cycle 0, when the item
         * became ready, and once more after that progress */
        TB_EQ_INT(ks_clocked_steps(cons), 3);
        ks_sim_destroy(sim);
        tb_end();
    }
}

/* ---- capacity and back-pressure ---- */
typedef struct bp_ctx {
    ks_fifo *f;
    uint32_t next, n, got[64];
    int ngot;
    uint64_t stalls;
} bp_ctx;

static int bp_prod(void *u, uint64_t cycle)
{
    (void)cycle;
    bp_ctx *c = u;
    if (c->next >= c->n)
        return 0;
    if (!ks_fifo_can_write(c->f)) {
        c->stalls++;
        return 0; /* sleeps until freed */
    }
    TB_CHECK(ks_fifo_write(c->f, &c->next), "write refused although can_write");
    c->next++;
    return 1;
}

static ks_clocked *g_cons;
static int bp_cons_wrap(void *u, uint64_t cycle)
{
    bp_ctx *c = u;
    if (cycle % 4 != 0) {
        ks_clocked_sleep_until_cycle(g_cons, (cycle / 4 + 1) * 4);
        return 0;
    }
    uint32_t v;
    if (!ks_fifo_read(c->f, &v))
        return 0;
    if (c->ngot < 64)
        c->got[c->ngot++] = v;
    ks_clocked_sleep_until_cycle(g_cons, cycle + 4);
    return 1;
}

static void test_backpressure(void)
{
    tb_begin("fifo_capacity_and_back_pressure");
    ks_sim *sim = ks_sim_create();
    ks_clock *clk = ks_clock_create(sim, "clk", 0);
    bp_ctx c = {0};
    c.n = 20;
    c.f = ks_fifo_create(sim, "top.bp", sizeof(uint32_t), 2, 1, clk);
    ks_clocked *p = ks_clocked_create(clk, "prod", bp_prod, &c);
    ks_clocked_wake_on(p, ks_fifo_ev_freed(c.f));
    g_cons = ks_clocked_create(clk, "cons", bp_cons_wrap, &c);
    ks_clocked_wake_on(g_cons, ks_fifo_ev_written(c.f));
    TB_EQ_INT(ks_sim_run(sim, KS_TIME_MAX), KS_RUN_FINISHED);
    TB_EQ_INT(c.ngot, 20);
    for (int i = 0; i < c.ngot; i++)
        if (!TB_EQ_INT(c.got[i], i))
            break;
    TB_EQ_INT(ks_fifo_max_occupancy(c.f), 2);
    TB_EQ_INT(ks_fifo_total_writes(c.f), 20);
    TB_EQ_INT(ks_fifo_total_reads(c.f), 20);
    TB_CHECK(c.stalls > 0, "producer never saw a full FIFO");
    /* a write into a full FIFO is refused and counted */
    uint32_t v = 7;
    TB_EQ_INT(ks_fifo_write(c.f, &v), 1);
    TB_EQ_INT(ks_fifo_write(c.f, &v), 1);
    TB_EQ_INT(ks_fifo_write(c.f, &v), 0);
    TB_EQ_INT(ks_fifo_rejected_writes(c.f), 1);
    TB_EQ_INT(ks_fifo_occupancy(c.f), 2);
    ks_sim_destroy(sim);
    tb_end();
}

/* ---- occupancy statistics and resizing (method processes, no clock) ---- */
typedef struct occ_ctx {
    ks_fifo *f;
    ks_method *m;
    int phase;
} occ_ctx;

static void occ_proc(void *u)
{
    occ_ctx *c = u;
    uint64_t v = 1;
    switch (c->phase++) {
    case 0: /* t=0: two items */
        KS_FIFO_WRITE(c->f, &v);
        KS_FIFO_WRITE(c->f, &v);
        KS_FIFO_WRITE(c->f, &v);
        ks_fifo_read(c->f, NULL);
        ks_next_trigger_time(c->m, KS_NS(10));
        break;
    case 1: /* t=10: one left */
        KS_FIFO_READ(c->f, &v);
        ks_next_trigger_time(c->m, KS_NS(20));
        break;
    case 2: /* t=30: empty */
        ks_fifo_read(c->f, NULL);
        break;
    }
}

static void test_occupancy_stats(void)
{
    tb_begin("fifo_occupancy_max_and_time_weighted_mean");
    ks_sim *sim = ks_sim_create();
    occ_ctx c = {0};
    c.f = ks_fifo_create(sim, "top.occ", sizeof(uint64_t), 4, 0, NULL);
    c.m = ks_method_create(sim, "occ", occ_proc, &c);
    TB_EQ_INT(ks_sim_run(sim, KS_NS(40)), KS_RUN_FINISHED);
    TB_EQ_INT(ks_sim_now(sim), KS_NS(30)); /* nothing after the last read */
    TB_EQ_INT(ks_fifo_max_occupancy(c.f), 3);
    /* (2 x 10 + 1 x 20) / 30 = 4/3 */
    double mean = ks_fifo_mean_occupancy(c.f);
    TB_CHECK(mean > 4.0 / 3 - 1e-9 && mean < 4.0 / 3 + 1e-9, "mean occupancy %g, expected 4/3", mean);
    TB_EQ_INT(ks_fifo_suggested_capacity(c.f), 4);
    TB_CHECK(!strcmp(ks_fifo_name(c.f), "top.occ"), "name");
    TB_EQ_INT(ks_sim_fifo_count(sim), 1);
    TB_CHECK(ks_sim_fifo_at(sim, 0) == c.f && ks_sim_fifo_at(sim, 1) == NULL, "fifo list");
    ks_sim_destroy(sim);
    tb_end();

    tb_begin("fifo_resize_keeps_items_in_order");
    sim = ks_sim_create();
    ks_fifo *f = ks_fifo_create(sim, "top.rs", sizeof(uint32_t), 4, 0, NULL);
    for (uint32_t i = 0; i < 6; i++) { /* wrap the ring: 4 in, 2 out, 2 in */
        if (i == 4) {
            uint32_t x;
            ks_fifo_read(f, &x);
            ks_fifo_read(f, &x);
        }
        ks_fifo_write(f, &i);
    }
    TB_EQ_INT(ks_fifo_occupancy(f), 4);
    TB_EQ_INT(ks_fifo_set_capacity(f, 5), 0);
    TB_EQ_INT(ks_fifo_capacity(f), 5);
    TB_EQ_INT(ks_fifo_set_capacity(f, 8), 0);
    TB_EQ_INT(ks_fifo_set_capacity(f, 3), -1);
    TB_CHECK(strstr(ks_sim_error(sim), "top.rs") && strstr(ks_sim_error(sim), "occupancy"),
             "error text: %s", ks_sim_error(sim));
    TB_EQ_INT(ks_fifo_set_capacity(f, 0), -1);
    for (uint32_t want = 2; want < 6; want++) {
        uint32_t x = 99;
        TB_EQ_INT(ks_fifo_read(f, &x), 1);
        TB_EQ_INT(x, want);
    }
    TB_EQ_INT(ks_fifo_occupancy(f), 0);
    TB_EQ_INT(ks_fifo_read(f, NULL), 0);
    ks_sim_destroy(sim);
    tb_end();

    tb_begin("fifo_zero_copy_access");
    sim = ks_sim_create();
    f = ks_fifo_create(sim, "top.zc", 2 * sizeof(uint64_t), 2, 0, NULL);
    for (uint64_t i = 0; i < 2; i++) {
        uint64_t *slot = ks_fifo_write_slot(f);
        TB_CHECK(slot != NULL, "no slot with room left");
        if (slot) {
            slot[0] = i;
            slot[1] = 10 + i;
            ks_fifo_commit(f);
        }
    }
    TB_CHECK(ks_fifo_write_slot(f) == NULL, "slot offered while full");
    TB_EQ_INT(ks_fifo_total_writes(f), 2);
    const uint64_t *head = ks_fifo_peek(f);
    TB_CHECK(head && head[0] == 0 && head[1] == 10, "peek");
    TB_EQ_INT(ks_fifo_pop(f), 1);
    head = ks_fifo_peek(f);
    TB_CHECK(head && head[0] == 1 && head[1] == 11, "peek after pop");
    TB_EQ_INT(ks_fifo_pop(f), 1);
    TB_EQ_INT(ks_fifo_pop(f), 0);
    TB_CHECK(ks_fifo_peek(f) == NULL, "peek on empty");
    ks_sim_destroy(sim);
    tb_end();

    tb_begin("fifo_bad_parameters_rejected");
    sim = ks_sim_create();
    TB_CHECK(!ks_fifo_create(sim, "top.z", 4, 0, 0, NULL), "capacity 0 accepted");
    TB_CHECK(strstr(ks_sim_error(sim), "top.z") && strstr(ks_sim_error(sim), "capacity"),
             "error: %s", ks_sim_error(sim));
    TB_CHECK(!ks_fifo_create(sim, "top.l", 4, 2, 3, NULL), "latency without clock accepted");
    TB_CHECK(!ks_fifo_create(sim, "top.e", 0, 2, 0, NULL), "element size 0 accepted");
    ks_sim_destroy(sim);
    tb_end();
}

/* ---- idle skipping equivalence ----
 * A source emits items at pseudo-random cycles, two stages with different
 * FIFO latencies and service times forward them, a sink records (cycle,
 * item). Run once with idle skipping and once stepping every process every
 * cycle: the records and statistics must be identical. */
typedef struct eq_model {
    ks_fifo *f[3];
    ks_clocked *src, *st[2], *sink;
    uint64_t rng, next_emit, emitted, n;
    uint64_t busy_until[2];
    uint32_t hold[2];
    int holding[2];
    uint64_t hash, received, last_cycle;
} eq_model;

static uint64_t rnd(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return *s >> 33;
}

static int eq_src(void *u, uint64_t cycle)
{
    eq_model *m = u;
    if (m->emitted >= m->n)
        return 0;
    if (cycle < m->next_emit) {
        ks_clocked_sleep_until_cycle(m->src, m->next_emit);
        return 0;
    }
    if (!ks_fifo_can_write(m->f[0]))
        return 0; /* woken by freed */
    uint32_t v = (uint32_t)m->emitted++;
    ks_fifo_write(m->f[0], &v);
    /* bursts and long gaps */
    m->next_emit = cycle + 1 + (rnd(&m->rng) % 8 == 0 ? 200 + rnd(&m->rng) % 500 : rnd(&m->rng) % 3);
    ks_clocked_sleep_until_cycle(m->src, m->next_emit);
    return 1;
}

static int eq_stage(eq_model *m, int i, uint64_t cycle)
{
    int progress = 0;
    if (m->holding[i] && cycle >= m->busy_until[i] && ks_fifo_can_write(m->f[i + 1])) {
        ks_fifo_write(m->f[i + 1], &m->hold[i]);
        m->holding[i] = 0;
        progress++;
    }
    if (!m->holding[i] && ks_fifo_read(m->f[i], &m->hold[i])) {
        m->holding[i] = 1;
        m->busy_until[i] = cycle + 1 + (m->hold[i] * 7 + (uint32_t)i) % 5;
        progress++;
    }
    if (m->holding[i] && cycle < m->busy_until[i])
        ks_clocked_sleep_until_cycle(m->st[i], m->busy_until[i]);
    return progress;
}
static int eq_stage0(void *u, uint64_t c) { return eq_stage(u, 0, c); }
static int eq_stage1(void *u, uint64_t c) { return eq_stage(u, 1, c); }

static int eq_sink(void *u, uint64_t cycle)
{
    eq_model *m = u;
    uint32_t v;
    if (cycle % 3 == 1) { /* the sink refuses on every third cycle */
        ks_clocked_sleep_until_cycle(m->sink, cycle + 1);
        return 0;
    }
    if (!ks_fifo_read(m->f[2], &v))
        return 0;
    m->hash = (m->hash ^ (v + 0x9E3779B97F4A7C15ull * cycle)) * 1099511628211ull;
    m->received++;
    m->last_cycle = cycle;
    return 1;
}

typedef struct eq_result {
    uint64_t hash, received, last_cycle, ticks, steps, max[3], writes[3];
    double mean[3];
    ks_time end;
} eq_result;

static eq_result run_eq(int exhaustive, uint64_t n)
{
    eq_model m = {0};
    m.rng = 12345;
    m.n = n;
    ks_sim *sim = ks_sim_create();
    ks_clock *clk = ks_clock_create(sim, "clk", 0);
    ks_clock_set_exhaustive(clk, exhaustive);
    static const uint32_t lat[3] = {1, 3, 2}, cap[3] = {4, 2, 3};
    for (int i = 0; i < 3; i++) {
        char name[32];
        snprintf(name, sizeof name, "eq.f%d", i);
        m.f[i] = ks_fifo_create(sim, name, sizeof(uint32_t), cap[i], lat[i], clk);
    }
    m.src = ks_clocked_create(clk, "eq.src", eq_src, &m);
    m.st[0] = ks_clocked_create(clk, "eq.st0", eq_stage0, &m);
    m.st[1] = ks_clocked_create(clk, "eq.st1", eq_stage1, &m);
    m.sink = ks_clocked_create(clk, "eq.sink", eq_sink, &m);
    ks_clocked_wake_on(m.src, ks_fifo_ev_freed(m.f[0]));
    for (int i = 0; i < 2; i++) {
        ks_clocked_wake_on(m.st[i], ks_fifo_ev_written(m.f[i]));
        ks_clocked_wake_on(m.st[i], ks_fifo_ev_freed(m.f[i + 1]));
    }
    ks_clocked_wake_on(m.sink, ks_fifo_ev_written(m.f[2]));
    ks_run_status st = ks_sim_run(sim, KS_TIME_MAX);
    TB_EQ_INT(st, KS_RUN_FINISHED);
    eq_result r = {m.hash, m.received, m.last_cycle, ks_clock_ticks(clk), 0, {0}, {0}, {0}, 0};
    r.steps = ks_clocked_steps(m.src) + ks_clocked_steps(m.st[0]) + ks_clocked_steps(m.st[1]) +
              ks_clocked_steps(m.sink);
    /* statistics up to the last item, so that both runs measure the same span */
    for (int i = 0; i < 3; i++) {
        r.max[i] = ks_fifo_max_occupancy(m.f[i]);
        r.writes[i] = ks_fifo_total_writes(m.f[i]);
    }
    ks_sim_destroy(sim);
    return r;
}

/* Occupancy integral with a latency: items written at cycles 0, 0 and 4
 * of a 2 ns clock through a 3-cycle FIFO, the first read at cycle 3; at
 * t = 10 ns one item is still waiting for its ready time (14 ns). Residence
 * times: 6 + 10 + 2 ns = 18 ns over 10 ns = 1.8; at 20 ns, with the second
 * item read at cycle 7 (14 ns) and the third at 15 ns: 6 + 14 + 7 = 27 ns
 * over 20 ns = 1.35. */
typedef struct wlat_ctx {
    ks_fifo *f;
} wlat_ctx;

static int wlat_step(void *u, uint64_t cycle)
{
    wlat_ctx *c = u;
    uint32_t v = (uint32_t)cycle;
    if (cycle == 0) {
        KS_FIFO_WRITE(c->f, &v);
        KS_FIFO_WRITE(c->f, &v);
    } else if (cycle == 3 || cycle == 7) {
        TB_CHECK(KS_FIFO_READ(c->f, &v), "read at cycle %llu failed", (unsigned long long)cycle);
    } else if (cycle == 4) {
        KS_FIFO_WRITE(c->f, &v);
    }
    return cycle < 12;
}

static void wlat_read_late(void *u)
{
    wlat_ctx *c = u;
    uint32_t v;
    TB_CHECK(KS_FIFO_READ(c->f, &v), "read at 15 ns failed");
}

static void test_occupancy_with_latency(void)
{
    tb_begin("fifo_time_weighted_mean_with_latency_and_pending_items");
    ks_sim *sim = ks_sim_create();
    ks_clock *clk = ks_clock_create(sim, "clk", 2000);
    wlat_ctx c;
    c.f = ks_fifo_create(sim, "top.lat", sizeof(uint32_t), 4, 3, clk);
    ks_clocked_create(clk, "top.p", wlat_step, &c);
    TB_EQ_INT(ks_sim_run(sim, KS_NS(10)), KS_RUN_TIME_LIMIT);
    TB_EQ_INT(ks_fifo_occupancy(c.f), 2);
    TB_EQ_INT(ks_fifo_head_ready_time(c.f), KS_NS(6));
    double mean = ks_fifo_mean_occupancy(c.f);
    TB_CHECK(mean > 1.8 - 1e-12 && mean < 1.8 + 1e-12, "mean occupancy %.15g at 10 ns, expected 1.8",
             mean);
    ks_method *m = ks_method_create(sim, "top.late", wlat_read_late, &c);
    ks_method_dont_initialize(m);
    ks_next_trigger_time(m, KS_NS(5)); /* 15 ns */
    TB_EQ_INT(ks_sim_run(sim, KS_NS(20)), KS_RUN_TIME_LIMIT);
    TB_EQ_INT(ks_fifo_occupancy(c.f), 0);
    TB_EQ_INT(ks_fifo_total_reads(c.f), 3);
    mean = ks_fifo_mean_occupancy(c.f);
    TB_CHECK(mean > 1.35 - 1e-12 && mean < 1.35 + 1e-12, "mean occupancy %.15g at 20 ns, expected 1.35",
             mean);
    ks_sim_destroy(sim);
    tb_end();
}

static void test_idle_skipping(void)
{
    tb_begin("idle_skipping_is_bit_identical_to_ticking_every_cycle");
    uint64_t n = tb_is_sanitized() ? 300 : 3000;
    eq_result a = run_eq(0, n), b = run_eq(1, n);
    TB_EQ_INT(a.received, n);
    TB_EQ_INT(b.received, n);
    TB_CHECK(a.hash == b.hash, "trace hash differs: %llx vs %llx", (unsigned long long)a.hash,
             (unsigned long long)b.hash);
    TB_EQ_INT(a.last_cycle, b.last_cycle);
    for (int i = 0; i < 3; i++) {
        TB_EQ_INT(a.max[i], b.max[i]);
        TB_EQ_INT(a.writes[i], b.writes[i]);
    }
    /* skipping must actually skip: far fewer ticks and steps */
    TB_CHECK(a.ticks * 2 < b.ticks, "ticks: skipping %llu, every cycle %llu",
             (unsigned long long)a.ticks, (unsigned long long)b.ticks);
    TB_CHECK(a.steps * 4 < b.steps, "steps: skipping %llu, every cycle %llu",
             (unsigned long long)a.steps, (unsigned long long)b.steps);
    tb_end();
}

/* ---- deadlock ---- */
typedef struct dl_unit {
    ks_fifo *out, *in;
    int to_send, received;
    ks_clocked *p;
} dl_unit;

/* Sends all its items before reading any: with both FIFOs too small the
 * pair blocks (each waits for space the other never frees). */
static int dl_step(void *u, uint64_t cycle)
{
    (void)cycle;
    dl_unit *d = u;
    if (d->to_send) {
        uint32_t v = 1;
        if (!ks_fifo_write(d->out, &v))
            return 0;
        d->to_send--;
        return 1;
    }
    if (ks_fifo_read(d->in, NULL)) {
        d->received++;
        return 1;
    }
    return 0;
}
static int dl_busy(void *u) { return ((dl_unit *)u)->to_send > 0; }
static void dl_describe(void *u, char *buf, unsigned cap)
{
    snprintf(buf, cap, "%d items left to send", ((dl_unit *)u)->to_send);
}

static ks_run_status run_pair(int items, uint32_t cap, char *report, size_t rcap)
{
    ks_sim *sim = ks_sim_create();
    ks_clock *clk = ks_clock_create(sim, "clk", 0);
    dl_unit a = {0}, b = {0};
    ks_fifo *ab = ks_fifo_create(sim, "pair.a_to_b", 4, cap, 1, clk);
    ks_fifo *ba = ks_fifo_create(sim, "pair.b_to_a", 4, cap, 1, clk);
    a.out = ab, a.in = ba, a.to_send = items;
    b.out = ba, b.in = ab, b.to_send = items;
    a.p = ks_clocked_create(clk, "pair.a", dl_step, &a);
    b.p = ks_clocked_create(clk, "pair.b", dl_step, &b);
    ks_clocked_wake_on(a.p, ks_fifo_ev_freed(ab));
    ks_clocked_wake_on(a.p, ks_fifo_ev_written(ba));
    ks_clocked_wake_on(b.p, ks_fifo_ev_freed(ba));
    ks_clocked_wake_on(b.p, ks_fifo_ev_written(ab));
    ks_clocked_set_describe(a.p, dl_busy, dl_describe);
    ks_clocked_set_describe(b.p, dl_busy, dl_describe);
    ks_run_status st = ks_sim_run(sim, KS_TIME_MAX);
    snprintf(report, rcap, "%s", ks_sim_deadlock_report(sim));
    ks_sim_destroy(sim);
    return st;
}

/* Polls every cycle without progress while holding an item: a livelock the
 * timed part of the detector must catch. */
typedef struct spin_ctx {
    ks_clocked *p;
    ks_fifo *f;
} spin_ctx;
static int spin_step(void *u, uint64_t cycle)
{
    spin_ctx *s = u;
    if (cycle == 0) {
        uint32_t v = 3;
        ks_fifo_write(s->f, &v);
    }
    ks_clocked_sleep_until_cycle(s->p, cycle + 1);
    return 0;
}

/* Sleeps a long time with nothing pending: must not be taken for a deadlock. */
static int nap_step(void *u, uint64_t cycle)
{
    ks_clocked *p = *(ks_clocked **)u;
    if (cycle < 500000) {
        ks_clocked_sleep_until_cycle(p, 500000);
        return cycle == 0;
    }
    return 0;
}

static void test_deadlock(void)
{
    tb_begin("deadlock_of_a_blocked_pair_is_reported");
    char rep[4096];
    ks_run_status st = run_pair(5, 2, rep, sizeof rep);
    TB_EQ_INT(st, KS_RUN_DEADLOCK);
    if (getenv("TB_VERBOSE"))
        fputs(rep, stderr);
    TB_CHECK(strstr(rep, "pair.a (clocked") && strstr(rep, "pair.b (clocked"),
             "report lacks the processes:\n%s", rep);
    TB_CHECK(strstr(rep, "pair.a_to_b.freed [fifo 2/2 full]"), "report lacks what a waits on:\n%s", rep);
    TB_CHECK(strstr(rep, "3 items left to send"), "report lacks the unit state:\n%s", rep);
    TB_CHECK(strstr(rep, "pair.b_to_a: 2/2 entries (full)"), "report lacks the channels:\n%s", rep);
    /* the same pair with room enough completes */
    TB_EQ_INT(run_pair(5, 8, rep, sizeof rep), KS_RUN_FINISHED);
    TB_EQ_INT(strlen(rep), 0);
    tb_end();

    tb_begin("livelock_without_progress_is_reported_after_the_window");
    ks_sim *sim = ks_sim_create();
    ks_clock *clk = ks_clock_create(sim, "clk", 0);
    ks_sim_set_deadlock_cycles(sim, 1000);
    spin_ctx s = {0};
    s.f = ks_fifo_create(sim, "spin.f", 4, 2, 0, clk);
    s.p = ks_clocked_create(clk, "spin", spin_step, &s);
    st = ks_sim_run(sim, KS_TIME_MAX);
    TB_EQ_INT(st, KS_RUN_DEADLOCK);
    TB_CHECK(ks_sim_now(sim) >= 1000 * 2000 && ks_sim_now(sim) < 1100 * 2000, "stopped at %lld ps",
             (long long)ks_sim_now(sim));
    TB_CHECK(strstr(ks_sim_deadlock_report(sim), "no progress for 1000 cycles"), "report:\n%s",
             ks_sim_deadlock_report(sim));
    ks_sim_destroy(sim);
    tb_end();

    tb_begin("long_idle_sleep_is_not_a_deadlock");
    sim = ks_sim_create();
    clk = ks_clock_create(sim, "clk", 0);
    ks_sim_set_deadlock_cycles(sim, 1000);
    ks_clocked *p = NULL;
    p = ks_clocked_create(clk, "nap", nap_step, &p);
    TB_EQ_INT(ks_sim_run(sim, KS_TIME_MAX), KS_RUN_FINISHED);
    TB_EQ_INT(ks_sim_now(sim), (ks_time)500000 * 2000);
    TB_EQ_INT(ks_clock_ticks(clk), 2);
    ks_sim_destroy(sim);
    tb_end();
}

int main(void)
{
    test_latency();
    test_backpressure();
    test_occupancy_stats();
    test_occupancy_with_latency();
    test_idle_skipping();
    test_deadlock();
    return tb_finish();
}
