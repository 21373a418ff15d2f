/* tb_dram_port — the DRAM kernel module (model/dram/dram_port.h) against the standalone
 * driver (model/dram/dram_trace.h, Ramulator's injection policy):
 *  - a producer keeps the request FIFO full, a consumer drains the response FIFO:
 *    every request's accept cycle and latency and the whole command stream equal
 *    the standalone run of the same trace (32 B requests; and 64 B requests split
 *    into two bursts vs the trace with both halves as separate lines);
 *  - long idle gaps: the DRAM clock sleeps (ticks << cycles) yet commands (refresh
 *    included) and responses equal the kernel's exhaustive reference mode;
 *  - back-pressure: with the consumer stalled, the response FIFO fills, the port
 *    stops accepting, the request FIFO fills and the producer is refused; after the
 *    consumer resumes, everything completes; never drained -> deadlock report;
 *  - statistics registered and described; bad FIFO item sizes rejected. */
#include "testbench/tb.h"

#include <math.h>
#include <stdint.h>

#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/module_desc.h"
#include "kernel/sim.h"
#include "kernel/stats.h"
#include "model/dram/dram_checker.h"
#include "model/dram/dram_ctrl.h"
#include "model/dram/dram_port.h"
#include "model/dram/dram_timing.h"
#include "model/dram/dram_trace.h"

static dram_spec spec;

/* ---- command logs ---- */

typedef struct cmdlog {
    dram_cmd_rec *v;
    size_t n, cap;
} cmdlog;

static void log_cmd(void *u, const dram_cmd_rec *r)
{
    cmdlog *l = u;
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 1024;
        l->v = realloc(l->v, l->cap * sizeof *l->v);
    }
    l->v[l->n++] = *r;
}

/* Index of the first differing command, or -1 when equal. */
static long cmd_diff(const cmdlog *a, const cmdlog *b)
{
    size_t n = a->n < b->n ? a->n : b->n;
    for (size_t i = 0; i < n; i++)
        if (a->v[i].cycle != b->v[i].cycle || a->v[i].channel != b->v[i].channel || a->v[i].rank != b->v[i].rank ||
            a->v[i].bank != b->v[i].bank || a->v[i].row != b->v[i].row || a->v[i].cmd != b->v[i].cmd)
            return (long)i;
    return a->n == b->n ? -1 : (long)n;
}

/* ---- traces ---- */

typedef struct treq {
    uint64_t addr;
    int is_write;
} treq;

/* Seeded mix: sequential runs, random rows of a 4 MiB region, 30 % writes, reads of
 * just-written addresses (forwarded). Addresses aligned to `align`. */
static treq *make_reqs(uint64_t seed, int n, uint64_t align)
{
    treq *t = calloc((size_t)n, sizeof *t);
    uint64_t x = seed, addr = 0, last_w = 0;
    for (int i = 0; i < n; i++) {
        x = x * 6364136223846793005ull + 1442695040888963407ull;
        const unsigned r = (unsigned)(x >> 33);
        addr = r % 8 < 4 ? addr + align : ((uint64_t)(r >> 3) % (4u << 20)) & ~(align - 1);
        t[i].is_write = r % 10 < 3;
        t[i].addr = !t[i].is_write && r % 16 == 5 ? last_w : addr;
        if (t[i].is_write)
            last_w = t[i].addr;
    }
    return t;
}

/* ---- standalone reference ---- */

typedef struct ref_run {
    int64_t *done, *lat;   /* per trace line (tag = line number, 1-based) */
    int n;
    cmdlog cmds;
    int64_t end_cycle;
} ref_run;

static void ref_done(void *u, uint64_t addr, uint64_t tag, bool is_write, int64_t lat)
{
    (void)addr;
    (void)is_write;
    ref_run *r = u;
    r->lat[tag - 1] = lat;
    r->done[tag - 1] = r->end_cycle; /* set by the clock hook below */
}

typedef struct ref_ctx {
    ref_run *r;
    dram_ctrl *c;
} ref_ctx;

static void ref_done_clk(void *u, uint64_t addr, uint64_t tag, bool is_write, int64_t lat)
{
    ref_ctx *x = u;
    x->r->end_cycle = dram_clock(x->c);
    ref_done(x->r, addr, tag, is_write, lat);
}

/* Runs `lines` 32 B trace lines through dram_trace_run. */
static int run_standalone(const treq *lines, int n, ref_run *r)
{
    memset(r, 0, sizeof *r);
    r->n = n;
    r->done = calloc((size_t)n, sizeof *r->done);
    r->lat = calloc((size_t)n, sizeof *r->lat);
    char *text = malloc((size_t)n * 24 + 1);
    size_t u = 0;
    for (int i = 0; i < n; i++)
        u += (size_t)sprintf(text + u, "0x%llx %c\n", (unsigned long long)lines[i].addr, lines[i].is_write ? 'W' : 'R');
    text[u] = 0;
    char err[256];
    ref_ctx x = {r, NULL};
    dram_ctrl *c = dram_ctrl_create(&spec, ref_done_clk, &x, err, sizeof err);
    x.c = c;
    dram_set_cmd_sink(c, log_cmd, &r->cmds);
    FILE *f = fmemopen(text, u, "r");
    dram_trace_result res;
    int rc = dram_trace_run(c, f, "generated", &res, err, sizeof err);
    fclose(f);
    r->end_cycle = dram_clock(c);
    dram_ctrl_destroy(c);
    free(text);
    return rc;
}

static void ref_free(ref_run *r)
{
    free(r->done);
    free(r->lat);
    free(r->cmds.v);
}

/* ---- kernel harness: producer -> [req fifo] -> dram -> [resp fifo] -> consumer ---- */

typedef struct harness {
    ks_sim *sim;
    ks_fifo *req, *resp;
    dram_port *port;
    ks_stats *stats;
    ks_clocked *prod, *cons;
    /* producer */
    const dram_port_req *reqs;
    int n, next;
    int group, gap;          /* after every `group` requests wait `gap` cycles (0: none) */
    uint64_t release;        /* cycle the next group may start */
    uint64_t refused;        /* writes refused by the full request FIFO */
    /* consumer */
    int consume;             /* 0: stalled (back-pressure tests) */
    dram_port_resp *got;
    int ngot;
    cmdlog cmds;
} harness;

static int prod_step(void *u, uint64_t cycle)
{
    harness *h = u;
    int made = 0;
    while (h->next < h->n && cycle >= h->release) {
        if (!ks_fifo_write(h->req, &h->reqs[h->next])) {
            h->refused++;
            break;
        }
        h->next++;
        made++;
        if (h->group && h->next % h->group == 0) {
            h->release = cycle + (uint64_t)h->gap;
            ks_clocked_sleep_until_cycle(h->prod, h->release);
        }
    }
    if (h->next == h->n && made)
        dram_port_input_done(h->port);
    return made;
}

static int cons_step(void *u, uint64_t cycle)
{
    (void)cycle;
    harness *h = u;
    if (!h->consume)
        return 0;
    int made = 0;
    dram_port_resp r;
    while (ks_fifo_read(h->resp, &r)) {
        h->got[h->ngot++] = r;
        made++;
    }
    return made;
}

static int harness_init(harness *h, const dram_port_req *reqs, int n, uint32_t req_cap, uint32_t resp_cap,
                        char *err, size_t errlen)
{
    memset(h, 0, sizeof *h);
    h->sim = ks_sim_create();
    h->stats = ks_stats_create();
    h->req = ks_fifo_create(h->sim, "dram.req", sizeof(dram_port_req), req_cap, 0, NULL);
    h->resp = ks_fifo_create(h->sim, "dram.resp", sizeof(dram_port_resp), resp_cap, 0, NULL);
    h->port = dram_port_create(h->sim, "dram", &spec, NULL, h->req, h->resp, h->stats, err, errlen);
    if (!h->port)
        return -1;
    dram_port_set_cmd_sink(h->port, log_cmd, &h->cmds);
    h->reqs = reqs;
    h->n = n;
    h->consume = 1;
    h->got = calloc((size_t)n + 1, sizeof *h->got);
    /* created after the port: stepped after it at each edge of the DRAM clock */
    h->prod = ks_clocked_create(dram_port_clock(h->port), "producer", prod_step, h);
    ks_clocked_wake_on(h->prod, ks_fifo_ev_freed(h->req));
    h->cons = ks_clocked_create(dram_port_clock(h->port), "consumer", cons_step, h);
    ks_clocked_wake_on(h->cons, ks_fifo_ev_written(h->resp));
    /* the trace is there from cycle 0, as in the standalone driver */
    prod_step(h, 0);
    return 0;
}

static void harness_free(harness *h)
{
    dram_port_destroy(h->port);
    ks_sim_destroy(h->sim);
    ks_stats_destroy(h->stats);
    free(h->got);
    free(h->cmds.v);
}

/* Value of a statistic, NaN when absent. */
static double stat_value(const ks_stats *st, const char *name)
{
    double v;
    return ks_stats_value(st, name, &v) == 0 ? v : 0.0 / 0.0;
}

static int by_tag(const void *a, const void *b)
{
    const dram_port_resp *x = a, *y = b;
    return x->tag < y->tag ? -1 : x->tag > y->tag;
}

/* ---- cases ---- */

/* 32 B requests (one burst each): identical to the standalone driver. */
static void equals_standalone_32(const char *name, uint64_t seed, int n)
{
    tb_begin(name);
    treq *t = make_reqs(seed, n, 32);
    ref_run ref;
    TB_EQ_INT(run_standalone(t, n, &ref), 0);
    dram_port_req *reqs = calloc((size_t)n, sizeof *reqs);
    for (int i = 0; i < n; i++)
        reqs[i] = (dram_port_req){t[i].addr, (uint64_t)i + 1, 32, (uint8_t)t[i].is_write};
    harness h;
    char err[256];
    if (TB_CHECK(harness_init(&h, reqs, n, 4, 8, err, sizeof err) == 0, "%s", err)) {
        ks_run_status st = ks_sim_run(h.sim, KS_TIME_MAX);
        TB_CHECK(st == KS_RUN_FINISHED, "run ended %s: %s", ks_run_status_name(st), ks_sim_deadlock_report(h.sim));
        TB_EQ_INT(h.ngot, n);
        qsort(h.got, (size_t)h.ngot, sizeof *h.got, by_tag);
        int bad = 0;
        int64_t last = 0;
        for (int i = 0; i < h.ngot && i < n && !bad; i++) {
            const dram_port_resp *r = &h.got[i];
            bad = !TB_CHECK(r->tag == (uint64_t)i + 1 && r->bursts == 1, "response %d: tag %llu bursts %u", i,
                            (unsigned long long)r->tag, r->bursts);
            /* forwarded reads (standalone latency 1) complete in order behind earlier reads */
            bad |= !TB_CHECK(r->done_cycle == ref.done[i] &&
                                 (ref.lat[i] == 1 || r->done_cycle - r->accept_cycle == ref.lat[i]),
                             "request %d (%s 0x%llx): accepted %lld done %lld (latency %lld), standalone done %lld "
                             "latency %lld", i, t[i].is_write ? "W" : "R", (unsigned long long)t[i].addr,
                             (long long)r->accept_cycle, (long long)r->done_cycle,
                             (long long)(r->done_cycle - r->accept_cycle), (long long)ref.done[i],
                             (long long)ref.lat[i]);
            if (r->done_cycle > last)
                last = r->done_cycle;
        }
        long d = cmd_diff(&h.cmds, &ref.cmds);
        TB_CHECK(d < 0, "command %ld differs (port %zu commands, standalone %zu)", d, h.cmds.n, ref.cmds.n);
        if (d >= 0 && getenv("TB_VERBOSE"))
            for (long k = d > 3 ? d - 3 : 0; k < d + 3; k++)
                fprintf(stderr, "%ld: port %lld ch%d b%d %s | ref %lld ch%d b%d %s\n", k, (long long)h.cmds.v[k].cycle,
                        h.cmds.v[k].channel, h.cmds.v[k].bank, dram_cmd_name[h.cmds.v[k].cmd],
                        (long long)ref.cmds.v[k].cycle, ref.cmds.v[k].channel, ref.cmds.v[k].bank,
                        dram_cmd_name[ref.cmds.v[k].cmd]);
        TB_EQ_INT(last, ref.end_cycle);
        /* the FIFO that was kept full: producer refused only while the port stalled */
        TB_CHECK(ks_fifo_total_writes(h.req) == (uint64_t)n, "request FIFO writes %llu",
                 (unsigned long long)ks_fifo_total_writes(h.req));
        TB_EQ_INT(stat_value(h.stats, "dram.requests"), n);
        size_t nrd = 0;
        for (size_t k = 0; k < ref.cmds.n; k++)
            nrd += ref.cmds.v[k].cmd == DRAM_RD;
        TB_EQ_INT(stat_value(h.stats, "dram.cmd_rd"), (double)nrd);
        harness_free(&h);
    }
    ref_free(&ref);
    free(reqs);
    free(t);
    tb_end();
}

/* 64 B requests = two bursts (L, L+32): the standalone trace lists both halves. */
static void equals_standalone_64(const char *name, uint64_t seed, int n)
{
    tb_begin(name);
    treq *t = make_reqs(seed, n, 64);
    treq *lines = calloc((size_t)(2 * n), sizeof *lines);
    dram_port_req *reqs = calloc((size_t)n, sizeof *reqs);
    for (int i = 0; i < n; i++) {
        lines[2 * i] = t[i];
        lines[2 * i + 1] = (treq){t[i].addr + 32, t[i].is_write};
        reqs[i] = (dram_port_req){t[i].addr, (uint64_t)i, 64, (uint8_t)t[i].is_write};
    }
    ref_run ref;
    TB_EQ_INT(run_standalone(lines, 2 * n, &ref), 0);
    harness h;
    char err[256];
    if (TB_CHECK(harness_init(&h, reqs, n, 4, 8, err, sizeof err) == 0, "%s", err)) {
        ks_run_status st = ks_sim_run(h.sim, KS_TIME_MAX);
        TB_CHECK(st == KS_RUN_FINISHED, "run ended %s", ks_run_status_name(st));
        TB_EQ_INT(h.ngot, n);
        qsort(h.got, (size_t)h.ngot, sizeof *h.got, by_tag);
        for (int i = 0; i < h.ngot && i < n; i++) {
            const dram_port_resp *r = &h.got[i];
            const int64_t a0 = ref.done[2 * i] - ref.lat[2 * i];
            const int64_t done = ref.done[2 * i] > ref.done[2 * i + 1] ? ref.done[2 * i] : ref.done[2 * i + 1];
            if (!TB_CHECK(r->bursts == 2 && (ref.lat[2 * i] == 1 || r->accept_cycle == a0) && r->done_cycle == done,
                          "request %d: bursts %u accepted %lld done %lld; standalone halves arrive %lld, done %lld/%lld",
                          i, r->bursts, (long long)r->accept_cycle, (long long)r->done_cycle, (long long)a0,
                          (long long)ref.done[2 * i], (long long)ref.done[2 * i + 1]))
                break;
        }
        long d = cmd_diff(&h.cmds, &ref.cmds);
        TB_CHECK(d < 0, "command %ld differs (port %zu commands, standalone %zu)", d, h.cmds.n, ref.cmds.n);
        harness_free(&h);
    }
    ref_free(&ref);
    free(reqs);
    free(lines);
    free(t);
    tb_end();
}

/* Groups of requests separated by long idle gaps: sleeping vs exhaustive kernel mode. */
static void idle_gaps(void)
{
    tb_begin("dram_port_idle_sleeps_and_equals_exhaustive");
    const int n = 96, group = 8, gap = 25000; /* 8 refresh intervals per gap */
    treq *t = make_reqs(13, n, 32);
    dram_port_req *reqs = calloc((size_t)n, sizeof *reqs);
    for (int i = 0; i < n; i++)
        reqs[i] = (dram_port_req){t[i].addr, (uint64_t)i, 32, (uint8_t)t[i].is_write};
    harness h[2];
    char err[256];
    const ks_time until = (ks_time)spec.tck_ps * (ks_time)(gap + 2000) * (n / group + 1);
    uint64_t ticks[2] = {0, 0};
    for (int m = 0; m < 2; m++) {
        if (!TB_CHECK(harness_init(&h[m], reqs, n, 4, 8, err, sizeof err) == 0, "%s", err)) {
            tb_end();
            return;
        }
        h[m].group = group;
        h[m].gap = gap;
        ks_clock_set_exhaustive(dram_port_clock(h[m].port), m == 1);
        ks_sim_run(h[m].sim, until);
        if (ks_sim_now(h[m].sim) < until)
            ks_sim_run(h[m].sim, until); /* finished early: time stays; sync below uses now */
        dram_port_sync(h[m].port);
        ticks[m] = ks_clock_ticks(dram_port_clock(h[m].port));
        TB_EQ_INT(h[m].ngot, n);
    }
    /* align both controllers to the same final cycle before comparing */
    const int64_t end = dram_clock(dram_port_ctrl(h[0].port)) > dram_clock(dram_port_ctrl(h[1].port))
                            ? dram_clock(dram_port_ctrl(h[0].port))
                            : dram_clock(dram_port_ctrl(h[1].port));
    for (int m = 0; m < 2; m++)
        dram_advance_to(dram_port_ctrl(h[m].port), end);
    long d = cmd_diff(&h[0].cmds, &h[1].cmds);
    TB_CHECK(d < 0, "command %ld differs (sleeping %zu commands, exhaustive %zu)", d, h[0].cmds.n, h[1].cmds.n);
    int same = h[0].ngot == h[1].ngot;
    for (int i = 0; same && i < h[0].ngot; i++) {
        const dram_port_resp *x = &h[0].got[i], *y = &h[1].got[i];
        same = x->tag == y->tag && x->addr == y->addr && x->accept_cycle == y->accept_cycle &&
               x->done_cycle == y->done_cycle && x->bursts == y->bursts;
    }
    TB_CHECK(same, "responses differ between sleeping and exhaustive modes");
    size_t nref = 0;
    for (size_t i = 0; i < h[0].cmds.n; i++)
        nref += h[0].cmds.v[i].cmd == DRAM_REF;
    /* refresh keeps running through the gaps: one REF per channel per interval */
    const size_t expect_ref = (size_t)(end / spec.refresh_interval) * (size_t)spec.channels;
    TB_CHECK(nref + 2 >= expect_ref && nref <= expect_ref + 2, "%zu REF commands over %lld cycles, expected ~%zu",
             nref, (long long)end, expect_ref);
    TB_CHECK(ticks[0] * 10 < (uint64_t)end, "sleeping DRAM clock ticked %llu times over %lld cycles",
             (unsigned long long)ticks[0], (long long)end);
    TB_CHECK(ticks[1] >= ticks[0], "exhaustive ticks %llu < sleeping %llu", (unsigned long long)ticks[1],
             (unsigned long long)ticks[0]);
    for (int m = 0; m < 2; m++)
        harness_free(&h[m]);
    free(reqs);
    free(t);
    tb_end();
}

/* Stalled consumer: response FIFO full -> port stops -> request FIFO full -> producer refused. */
static void back_pressure(void)
{
    tb_begin("dram_port_back_pressure");
    const int n = 200;
    treq *t = make_reqs(14, n, 32);
    dram_port_req *reqs = calloc((size_t)n, sizeof *reqs);
    for (int i = 0; i < n; i++)
        reqs[i] = (dram_port_req){t[i].addr, (uint64_t)i, 32, 0};
    harness h;
    char err[256];
    if (TB_CHECK(harness_init(&h, reqs, n, 8, 4, err, sizeof err) == 0, "%s", err)) {
        h.consume = 0;
        /* the consumer never reads: everything stops and the kernel reports it */
        ks_run_status st = ks_sim_run(h.sim, KS_TIME_MAX);
        TB_CHECK(st == KS_RUN_DEADLOCK, "stalled run ended %s", ks_run_status_name(st));
        TB_CHECK(strstr(ks_sim_deadlock_report(h.sim), "responses waiting for the response FIFO") != NULL,
                 "deadlock report lacks the DRAM state: %s", ks_sim_deadlock_report(h.sim));
        TB_EQ_INT(ks_fifo_occupancy(h.resp), 4);
        TB_EQ_INT(ks_fifo_occupancy(h.req), 8);
        TB_CHECK(h.refused > 0, "producer never refused");
        TB_CHECK(h.next < n, "all %d requests entered despite back-pressure", h.next);
        /* accepted = responses in the FIFO + held in the port; bounded by the controller */
        const uint64_t held = dram_port_outstanding(h.port);
        TB_CHECK(held > 4 && held <= 4 + (uint64_t)(spec.channels * (spec.read_queue + spec.write_queue)),
                 "outstanding %llu", (unsigned long long)held);
        TB_EQ_INT(stat_value(h.stats, "dram.requests"), (double)held + 4);
        const double stalled_at = (double)ks_sim_now(h.sim) / spec.tck_ps;
        /* resume */
        h.consume = 1;
        ks_clocked_wake(h.cons);
        st = ks_sim_run(h.sim, KS_TIME_MAX);
        TB_CHECK(st == KS_RUN_FINISHED, "resumed run ended %s: %s", ks_run_status_name(st),
                 ks_sim_deadlock_report(h.sim));
        TB_EQ_INT(h.ngot, n);
        TB_EQ_INT(dram_port_outstanding(h.port), 0);
        const double blocked = stat_value(h.stats, "dram.resp_blocked_cycles");
        TB_CHECK(blocked > stalled_at / 2 && blocked < stat_value(h.stats, "dram.dram_cycles"),
                 "resp_blocked_cycles %g (stalled at cycle %g)", blocked, stalled_at);
        harness_free(&h);
    }
    free(reqs);
    free(t);
    tb_end();
}

/* Request FIFO with a latency: requests written at given cycles enter exactly when
 * they become readable, also when several written events merge into one. */
typedef struct timed_prod {
    ks_fifo *req;
    ks_clocked *proc;
    const uint64_t *at;      /* write cycles, ascending */
    int n, next;
} timed_prod;

static int timed_prod_step(void *u, uint64_t cycle)
{
    timed_prod *t = u;
    int made = 0;
    while (t->next < t->n && t->at[t->next] <= cycle) {
        dram_port_req r = {(uint64_t)t->next * 0x2000, (uint64_t)t->next, 32, 0}; /* bank t->next % 8 */
        if (!ks_fifo_write(t->req, &r))
            break;
        t->next++;
        made++;
    }
    if (t->next < t->n)
        ks_clocked_sleep_until_cycle(t->proc, t->at[t->next]);
    return made;
}

static void latency_fifo(void)
{
    tb_begin("dram_port_request_fifo_latency");
    /* latency 500: later writes happen while an earlier item's written notification is
     * pending (the kernel keeps only the earliest), and the DRAM is idle again by then */
    const uint64_t at[] = {0, 0, 0, 5, 7, 400, 450, 1300, 1301};
    const int64_t expect[] = {500, 501, 502, 505, 507, 900, 950, 1800, 1801}; /* write + 500, one per cycle */
    const int n = (int)(sizeof at / sizeof at[0]);
    ks_sim *sim = ks_sim_create();
    ks_fifo *resp = ks_fifo_create(sim, "lat.resp", sizeof(dram_port_resp), 16, 0, NULL);
    /* the request FIFO needs the port's clock for its latency: create it on a helper clock of
     * the same period, so its cycles coincide with the DRAM clock's */
    ks_clock *clk = ks_clock_create(sim, "lat.producer_clk", (ks_time)spec.tck_ps);
    ks_fifo *req = ks_fifo_create(sim, "lat.req", sizeof(dram_port_req), 16, 500, clk);
    char err[256];
    dram_port *p = dram_port_create(sim, "lat", &spec, NULL, req, resp, NULL, err, sizeof err);
    if (TB_CHECK(p != NULL, "%s", err)) {
        timed_prod tp = {req, NULL, at, n, 0};
        tp.proc = ks_clocked_create(clk, "lat.producer", timed_prod_step, &tp);
        ks_run_status st = ks_sim_run(sim, KS_TIME_MAX);
        /* nobody reads the responses: the kernel ends with "work pending" in lat.resp */
        TB_CHECK(st == KS_RUN_FINISHED || (st == KS_RUN_DEADLOCK && ks_fifo_occupancy(resp) == (uint32_t)n),
                 "run ended %s: %s", ks_run_status_name(st), ks_sim_deadlock_report(sim));
        dram_port_resp r[16];
        int got = 0;
        while (got < 16 && ks_fifo_read(resp, &r[got]))
            got++;
        TB_EQ_INT(got, n);
        qsort(r, (size_t)got, sizeof r[0], by_tag);
        for (int i = 0; i < got && i < n; i++)
            TB_CHECK(r[i].accept_cycle == expect[i], "request %d written at cycle %llu accepted at %lld, expected %lld",
                     i, (unsigned long long)at[i], (long long)r[i].accept_cycle, (long long)expect[i]);
    }
    dram_port_destroy(p);
    ks_sim_destroy(sim);
    tb_end();
}

/* Does nothing at its wake-up cycle: keeps sim time running. */
static int timer_step(void *u, uint64_t cycle)
{
    (void)u;
    (void)cycle;
    return 0;
}

static void stats_and_desc(void)
{
    tb_begin("dram_port_stats_described");
    char err[256];
    TB_CHECK(ks_module_desc_check(&dram_port_module_desc, err, sizeof err) == 0, "%s", err);
    TB_CHECK(ks_module_desc_find(&dram_port_module_desc, KS_DESC_PORT, "req") != NULL, "no req port");
    TB_CHECK(ks_module_desc_find(&dram_port_module_desc, KS_DESC_PORT, "resp") != NULL, "no resp port");
    /* its parameters are the DRAM standard file's keys (rtsim's [dram]
     * section, whose schema is made from the file): none is repeated here */
    TB_CHECK(dram_port_module_desc.config_sections && !strcmp(dram_port_module_desc.config_sections, "dram") &&
                 ks_module_desc_count(&dram_port_module_desc, KS_DESC_PARAM) == 0,
             "parameters named by section, not repeated");
    static dram_power_spec pw;
    TB_CHECK(dram_power_spec_load(&pw, "model/data/lpddr3_1600_idd.ini", err, sizeof err) == 0, "%s", err);
    ks_sim *sim = ks_sim_create();
    ks_stats *st = ks_stats_create();
    ks_fifo *req = ks_fifo_create(sim, "m.req", sizeof(dram_port_req), 2, 0, NULL);
    ks_fifo *resp = ks_fifo_create(sim, "m.resp", sizeof(dram_port_resp), 2, 0, NULL);
    dram_port *p = dram_port_create(sim, "mem", &spec, &pw, req, resp, st, err, sizeof err);
    if (TB_CHECK(p != NULL, "%s", err)) {
        /* every statistic of the table is registered under "mem." */
        TB_EQ_INT(ks_stats_count(st), ks_module_desc_count(&dram_port_module_desc, KS_DESC_STAT));
        for (const ks_desc_item *d = dram_port_module_desc.items; d->kind != KS_DESC_END; d++) {
            if (d->kind != KS_DESC_STAT)
                continue;
            char name[96];
            double v;
            snprintf(name, sizeof name, "mem.%s", d->name);
            TB_CHECK(ks_stats_value(st, name, &v) == 0, "statistic %s not registered", name);
        }
        /* idle for 10 refresh intervals (another unit keeps time running): refreshes
         * and background energy still count although the DRAM clock slept */
        ks_clocked *timer = ks_clocked_create(dram_port_clock(p), "timer", timer_step, NULL);
        ks_clocked_wake_at_cycle(timer, (uint64_t)spec.refresh_interval * 10 + 100);
        ks_run_status rs = ks_sim_run(sim, KS_TIME_MAX);
        TB_CHECK(rs == KS_RUN_FINISHED && ks_sim_now(sim) == (ks_time)spec.tck_ps * (spec.refresh_interval * 10 + 100),
                 "idle run ended %s at %lld ps", ks_run_status_name(rs), (long long)ks_sim_now(sim));
        TB_CHECK(ks_clock_ticks(dram_port_clock(p)) <= 3, "idle DRAM clock ticked %llu times",
                 (unsigned long long)ks_clock_ticks(dram_port_clock(p)));
        TB_EQ_INT(stat_value(st, "mem.cmd_ref"), 2 * 10);
        TB_EQ_INT(stat_value(st, "mem.dram_cycles"), spec.refresh_interval * 10 + 100);
        /* idle energy: per channel 10 refreshes plus precharged standby over every cycle */
        const double e = stat_value(st, "mem.energy_uJ");
        dram_energy_in in = {0, 0, 0, 0, 10, 0, (uint64_t)spec.refresh_interval * 10 + 100};
        dram_energy one;
        dram_energy_compute(&pw, &in, &one);
        TB_CHECK(fabs(e - 2 * one.total_pJ * 1e-6) < 1e-9 * e && one.ref_pJ > 0 && one.pre_stby_pJ > 0,
                 "idle energy %.9g uJ, expected %.9g uJ", e, 2 * one.total_pJ * 1e-6);
        /* a second module with the same name: duplicate statistics are refused */
        ks_fifo *req2 = ks_fifo_create(sim, "m2.req", sizeof(dram_port_req), 2, 0, NULL);
        ks_fifo *resp2 = ks_fifo_create(sim, "m2.resp", sizeof(dram_port_resp), 2, 0, NULL);
        dram_port *q = dram_port_create(sim, "mem", &spec, &pw, req2, resp2, st, err, sizeof err);
        TB_CHECK(q == NULL && strstr(err, "'mem.requests' already exists") != NULL, "duplicate names accepted: %s",
                 err);
        dram_port_destroy(q);
        /* a partial collision (one name taken by another unit) registers nothing */
        ks_stats *st2 = ks_stats_create();
        uint64_t *other = ks_stat_counter(st2, "mem2.cmd_rd", "commands", "another unit's counter");
        ks_fifo *req3 = ks_fifo_create(sim, "m3.req", sizeof(dram_port_req), 2, 0, NULL);
        ks_fifo *resp3 = ks_fifo_create(sim, "m3.resp", sizeof(dram_port_resp), 2, 0, NULL);
        q = dram_port_create(sim, "mem2", &spec, &pw, req3, resp3, st2, err, sizeof err);
        TB_CHECK(q == NULL && other != NULL && ks_stats_count(st2) == 1, "partial collision: %u statistics, %s",
                 ks_stats_count(st2), err);
        dram_port_destroy(q);
        ks_stats_destroy(st2);
    }
    dram_port_destroy(p);
    ks_sim_destroy(sim);
    ks_stats_destroy(st);
    tb_end();

    tb_begin("dram_port_rejects_bad_fifo_items");
    sim = ks_sim_create();
    ks_fifo *bad = ks_fifo_create(sim, "b.req", 8, 2, 0, NULL);
    ks_fifo *ok = ks_fifo_create(sim, "b.resp", sizeof(dram_port_resp), 2, 0, NULL);
    p = dram_port_create(sim, "b", &spec, NULL, bad, ok, NULL, err, sizeof err);
    TB_CHECK(p == NULL && strstr(err, "dram_port_req") != NULL, "accepted an 8-byte request FIFO: %s", err);
    dram_port_destroy(p);
    ks_sim_destroy(sim);
    tb_end();
}

int main(void)
{
    char err[512];
    if (dram_spec_load(&spec, "model/data/lpddr3_1600.ini", NULL, 0, err, sizeof err)) {
        printf("FAIL dram_port_load: %s\n", err);
        return 1;
    }
    const int n = tb_is_sanitized() ? 800 : 4000;
    /* several seeds and lengths: the end of the trace (write drain) lands in different states */
    equals_standalone_32("dram_port_equals_standalone_32B", 11, n);
    equals_standalone_32("dram_port_equals_standalone_32B_seed2", 21, n / 3 + 7);
    equals_standalone_32("dram_port_equals_standalone_32B_seed3", 31, 257);
    equals_standalone_64("dram_port_64B_split_equals_standalone", 12, n / 2);
    equals_standalone_64("dram_port_64B_split_equals_standalone_seed2", 22, 400);
    equals_standalone_64("dram_port_64B_split_equals_standalone_seed3", 32, 133);
    idle_gaps();
    back_pressure();
    latency_fifo();
    stats_and_desc();
    return tb_finish();
}
