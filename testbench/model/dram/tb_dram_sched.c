/* tb_dram_sched — the fast scheduler (per-bank readiness counters, idle skipping)
 * against the reference mode (dram_set_exhaustive: every queue entry examined every
 * cycle, no skipping) on seeded random traces under several controller
 * configurations (ranks, row-hit cap, tiny queues, write watermarks, mapping):
 * identical command streams, completion order and latencies, final cycle; and the
 * timing checker finds no violation in either. Also dram_advance_to against ticking. */
#include "testbench/tb.h"

#include <stdint.h>

#include "model/dram/dram_checker.h"
#include "model/dram/dram_ctrl.h"
#include "model/dram/dram_timing.h"
#include "model/dram/dram_trace.h"

typedef struct digest {
    uint64_t cmd_hash, done_hash;
    uint64_t ncmd, ndone;
    int64_t cycles;
    uint64_t violations;
    char first_violation[256];
    dram_checker *k;
} digest;

static uint64_t fnv(uint64_t h, uint64_t v)
{
    for (int i = 0; i < 8; i++) {
        h ^= (v >> (8 * i)) & 0xff;
        h *= 1099511628211ull;
    }
    return h;
}

static void on_cmd(void *u, const dram_cmd_rec *r)
{
    digest *d = u;
    d->cmd_hash = fnv(fnv(fnv(d->cmd_hash, (uint64_t)r->cycle), (uint64_t)(r->channel * 64 + r->rank * 8 + r->cmd)),
                      (uint64_t)((int64_t)r->bank * 1000003 + r->row));
    d->ncmd++;
    dram_checker_feed(d->k, r);
}

static void on_done(void *u, uint64_t addr, uint64_t tag, bool is_write, int64_t lat)
{
    digest *d = u;
    d->done_hash = fnv(fnv(fnv(d->done_hash, addr), tag * 2 + is_write), (uint64_t)lat);
    d->ndone++;
}

/* Seeded trace: runs of sequential 32 B requests, random rows in a small region (hits,
 * misses, conflicts on every bank), 30 % writes, some reads of just-written addresses. */
static char *make_trace(uint64_t seed, int n)
{
    char *t = malloc((size_t)n * 24 + 1);
    size_t u = 0;
    uint64_t x = seed, addr = 0, last_w = 0;
    for (int i = 0; i < n; i++) {
        x = x * 6364136223846793005ull + 1442695040888963407ull;
        const unsigned r = (unsigned)(x >> 33);
        if (r % 8 < 4)
            addr += 32;
        else
            addr = ((uint64_t)(r >> 3) % (4u << 20)) & ~31ull;
        int w = r % 10 < 3;
        uint64_t a = addr;
        if (!w && r % 16 == 5)
            a = last_w;
        if (w)
            last_w = a;
        u += (size_t)sprintf(t + u, "0x%llx %c\n", (unsigned long long)a, w ? 'W' : 'R');
    }
    t[u] = 0;
    return t;
}

static int run_trace(const dram_spec *spec, const char *trace, int exhaustive, digest *d, char *err, size_t errlen)
{
    memset(d, 0, sizeof *d);
    d->cmd_hash = d->done_hash = 1469598103934665603ull;
    dram_ctrl *c = dram_ctrl_create(spec, on_done, d, err, errlen);
    if (!c)
        return -1;
    d->k = dram_checker_create(spec, NULL, 0);
    dram_set_cmd_sink(c, on_cmd, d);
    dram_set_exhaustive(c, exhaustive);
    FILE *f = fmemopen((void *)trace, strlen(trace), "r");
    dram_trace_result res;
    int rc = dram_trace_run(c, f, "generated", &res, err, errlen);
    fclose(f);
    d->cycles = dram_clock(c);
    d->violations = dram_checker_finish(d->k, d->cycles);
    snprintf(d->first_violation, sizeof d->first_violation, "%s", dram_checker_first(d->k));
    dram_checker_destroy(d->k);
    dram_ctrl_destroy(c);
    return rc;
}

static void sched_case(const char *name, const char *const *sets, int nsets, uint64_t seed, int n)
{
    tb_begin(name);
    static dram_spec spec;
    char err[512];
    if (!TB_CHECK(dram_spec_load(&spec, "model/data/lpddr3_1600.ini", sets, nsets, err, sizeof err) == 0, "%s",
                  err)) {
        tb_end();
        return;
    }
    char *trace = make_trace(seed, n);
    digest fast, slow;
    TB_CHECK(run_trace(&spec, trace, 0, &fast, err, sizeof err) == 0, "fast: %s", err);
    TB_CHECK(run_trace(&spec, trace, 1, &slow, err, sizeof err) == 0, "exhaustive: %s", err);
    TB_EQ_INT(fast.ndone, (uint64_t)n);
    TB_EQ_INT(fast.ncmd, slow.ncmd);
    TB_CHECK(fast.cmd_hash == slow.cmd_hash, "command streams differ (%llu commands)", (unsigned long long)fast.ncmd);
    TB_CHECK(fast.done_hash == slow.done_hash, "completions (order, latency) differ");
    TB_EQ_INT(fast.cycles, slow.cycles);
    TB_CHECK(fast.violations == 0, "timing checker (fast): %s", fast.first_violation);
    TB_CHECK(slow.violations == 0, "timing checker (exhaustive): %s", slow.first_violation);
    free(trace);
    tb_end();
}

/* dram_advance_to over long idle stretches (refreshes inside) equals ticking through. */
static void advance_case(void)
{
    tb_begin("dram_sched_advance_to_equals_ticking");
    static dram_spec spec;
    char err[512];
    if (!TB_CHECK(dram_spec_load(&spec, "model/data/lpddr3_1600.ini", NULL, 0, err, sizeof err) == 0, "%s", err)) {
        tb_end();
        return;
    }
    digest d[2];
    for (int mode = 0; mode < 2; mode++) {
        memset(&d[mode], 0, sizeof d[mode]);
        d[mode].cmd_hash = d[mode].done_hash = 1469598103934665603ull;
        d[mode].k = dram_checker_create(&spec, NULL, 0);
        dram_ctrl *c = dram_ctrl_create(&spec, on_done, &d[mode], err, sizeof err);
        dram_set_cmd_sink(c, on_cmd, &d[mode]);
        dram_set_exhaustive(c, mode == 1);
        uint64_t x = 7;
        int64_t at = 0;
        for (int burst = 0; burst < 12; burst++) {
            for (int i = 0; i < 20; i++) {
                x = x * 6364136223846793005ull + 1442695040888963407ull;
                while (!dram_add(c, (x >> 20) & 0x3ffffe0, (x >> 60) & 1, (uint64_t)i))
                    dram_tick(c);
                dram_tick(c);
            }
            at = dram_clock(c) + 1000 + 4000 * burst; /* idle gaps up to ~15 refresh intervals */
            if (mode == 0)
                dram_advance_to(c, at);
            else
                while (dram_clock(c) < at)
                    dram_tick(c);
            TB_EQ_INT(dram_clock(c), at);
        }
        d[mode].cycles = dram_clock(c);
        d[mode].violations = dram_checker_finish(d[mode].k, d[mode].cycles);
        dram_chan_stats st;
        dram_chan_stats_get(c, 0, &st);
        d[mode].done_hash = fnv(d[mode].done_hash, st.queue_occupancy_sum);
        d[mode].done_hash = fnv(d[mode].done_hash, st.open_cycles);
        dram_checker_destroy(d[mode].k);
        dram_ctrl_destroy(c);
    }
    TB_EQ_INT(d[0].ndone, 240);
    TB_EQ_INT(d[0].ncmd, d[1].ncmd);
    TB_CHECK(d[0].cmd_hash == d[1].cmd_hash, "command streams differ");
    TB_CHECK(d[0].done_hash == d[1].done_hash, "completions or statistics differ");
    TB_CHECK(d[0].violations == 0 && d[1].violations == 0, "timing violations");
    tb_end();
}

int main(void)
{
    const int n = tb_is_sanitized() ? 1500 : 6000;
    sched_case("dram_sched_default", NULL, 0, 1, n);
    sched_case("dram_sched_two_ranks", (const char *const[]){"organization.ranks=2"}, 1, 2, n);
    sched_case("dram_sched_row_hit_cap_1", (const char *const[]){"controller.row_hit_cap=1"}, 1, 3, n);
    sched_case("dram_sched_tiny_queues",
               (const char *const[]){"controller.read_queue=3", "controller.write_queue=5",
                                     "controller.write_high_pct=60", "controller.write_low_pct=20"},
               4, 4, n);
    sched_case("dram_sched_mapping_ChRaBaRoCo", (const char *const[]){"controller.mapping=ChRaBaRoCo"}, 1, 5, n);
    sched_case("dram_sched_one_channel_16_banks",
               (const char *const[]){"organization.channels=1", "organization.banks=16"}, 2, 6, n);
    advance_case();
    return tb_finish();
}
