/* tb_cache_memsys.c — the memory side as kernel modules (cache.c,
 * mem_arbiter, fixed_mem, memsys_build): fills travel L1 -> L2 -> memory and
 * back with the configured latencies, L2 hits are faster than memory, misses
 * of several L1s to one line merge at the L2, the arbiter is fair, the fixed
 * memory honours its bandwidth, idle skipping changes nothing, statistics
 * and module tables are complete, impossible builds are refused. */
#include "kernel/clock.h"
#include "kernel/sim.h"
#include "kernel/stats.h"
#include "config/config.h"
#include "model/dram/dram_port.h"
#include "model/mem/fixed_mem.h"
#include "model/mem/mem_arbiter.h"
#include "model/mem/mem_dram_adapter.h"
#include "model/mem/memsys.h"
#include "testbench/tb.h"

#define MAXREQ 256
#define MAXSTREAM 32

/* A scripted requester stands for a TRV (or the IST) with several rays in
 * flight: each stream is one ray's address list, probed in order, each entry
 * not before its start cycle, retrying until it hits ("looping for next
 * chance"). One probe per cycle, streams served round robin as a pipeline
 * would; the cycle of every hit is recorded. */
typedef struct stream {
    int n, next;
    uint64_t addr[MAXREQ], start[MAXREQ], hit_cycle[MAXREQ];
} stream;

typedef struct requester {
    cache_core *c;
    ks_clocked *proc;
    uint32_t bytes;
    int ns, rr;
    stream st[MAXSTREAM];
    uint64_t probes;
} requester;

/* About 1.8 MB (9 requesters of 32 streams): the tests keep theirs static,
 * as on the stack clang's ASan build (-O1 inlines every test into main, no
 * frame reuse) overflowed the 8 MB stack. */
typedef struct bench {
    ks_sim *sim;
    ks_clock *clk;
    rtcfg *cfg;
    ks_stats *stats;
    memsys *ms;
    requester req[9];
    int nreq;
} bench;

static int req_step(void *user, uint64_t cycle)
{
    requester *r = user;
    uint64_t wake = UINT64_MAX;
    for (int k = 0; k < r->ns; k++) {
        stream *s = &r->st[(r->rr + k) % r->ns];
        if (s->next >= s->n)
            continue;
        if (cycle < s->start[s->next]) {
            if (s->start[s->next] < wake)
                wake = s->start[s->next];
            continue;
        }
        r->rr = (r->rr + k + 1) % r->ns;
        r->probes++;
        if (cache_core_access(r->c, s->addr[s->next], r->bytes, (int64_t)cycle) == CACHE_HIT)
            s->hit_cycle[s->next++] = cycle;
        return 1;
    }
    if (wake != UINT64_MAX)
        ks_clocked_sleep_until_cycle(r->proc, wake);
    return 0;
}

static void push_to(requester *r, int si, uint64_t addr, uint64_t start)
{
    stream *s = &r->st[si];
    if (si >= r->ns)
        r->ns = si + 1;
    s->addr[s->n] = addr;
    s->start[s->n++] = start;
}
static void push(requester *r, uint64_t addr, uint64_t start) { push_to(r, 0, addr, start); }

static bool bench_init(bench *b, const char *preset, const char *const *sets, int ntrv, bool exhaustive)
{
    memset(b, 0, sizeof *b);
    char err[512];
    b->cfg = rtcfg_create();
    b->sim = ks_sim_create();
    b->clk = ks_clock_create(b->sim, "clk", 0);
    b->stats = ks_stats_create();
    if (exhaustive)
        ks_clock_set_exhaustive(b->clk, 1);
    if (memsys_add_schemas(b->cfg, err, sizeof err) || rtcfg_load(b->cfg, preset, err, sizeof err))
        return TB_CHECK(false, "config: %s", err);
    for (int i = 0; sets && sets[i]; i++)
        if (rtcfg_set(b->cfg, sets[i], err, sizeof err))
            return TB_CHECK(false, "set: %s", err);
    if (rtcfg_finish(b->cfg, err, sizeof err))
        return TB_CHECK(false, "finish: %s", err);
    b->ms = memsys_build(b->sim, b->clk, b->cfg, ntrv, b->stats, err, sizeof err);
    if (!b->ms)
        return TB_CHECK(false, "memsys_build: %s", err);
    return true;
}

static requester *add_requester(bench *b, cache_core *c, uint32_t bytes)
{
    requester *r = &b->req[b->nreq++];
    r->c = c;
    r->bytes = bytes;
    char name[32];
    snprintf(name, sizeof name, "requester%d", b->nreq - 1);
    r->proc = ks_clocked_create(b->clk, name, req_step, r);
    return r;
}

/* Runs until everything is done (or the time limit: a failure). */
static ks_run_status bench_run(bench *b, uint64_t max_cycles)
{
    return ks_sim_run(b->sim, (ks_time)max_cycles * KS_DEFAULT_PERIOD_PS);
}

static void bench_free(bench *b)
{
    memsys_destroy(b->ms);
    ks_stats_destroy(b->stats);
    ks_sim_destroy(b->sim);
    rtcfg_destroy(b->cfg);
}

static double stat(bench *b, const char *name)
{
    double v = -1;
    if (ks_stats_value(b->stats, name, &v))
        TB_CHECK(false, "no statistic %s", name);
    return v;
}

static const char *const unlimited_bw[] = {"memory.model=fixed", "memory.fixed_bandwidth_gbs=0",
                                           "memory.fixed_latency=50", NULL};

static void test_fill_path_latency(void)
{
    tb_begin("fill_path_l1_l2_memory_and_l2_hit");
    static bench b;   /* 1.8 MB: see bench */
    if (bench_init(&b, "mbvh4", unlimited_bw, 2, false)) {
        requester *r0 = add_requester(&b, memsys_node_l1(b.ms, 0), 128);
        requester *r1 = add_requester(&b, memsys_node_l1(b.ms, 1), 128);
        push(r0, 0x4000, 0);
        push(r0, 0x4000, 0);       /* a hit in the L1 right after the fill */
        push(r1, 0x4000, 1000);    /* much later from TRV 1: a hit in the L2 */
        TB_EQ_INT(bench_run(&b, 5000), KS_RUN_FINISHED);
        uint64_t mem_path = r0->st[0].hit_cycle[0];
        /* memory latency 50, plus FIFO hops (1 cycle each, 8 on the way) and
         * the L2's hit latency 4 for the response */
        TB_CHECK(mem_path >= 50 + 8 + 4 && mem_path < 50 + 30, "memory round trip %llu cycles",
                 (unsigned long long)mem_path);
        TB_EQ_INT(r0->st[0].hit_cycle[1], r0->st[0].hit_cycle[0] + 1);
        uint64_t l2_path = r1->st[0].hit_cycle[0] - 1000;
        fprintf(stderr, "  L1 miss served by memory in %llu cycles, by the L2 in %llu\n", (unsigned long long)mem_path,
                (unsigned long long)l2_path);
        TB_CHECK(l2_path >= 4 + 4 && l2_path + 50 <= mem_path, "L2 hit round trip %llu vs memory %llu",
                 (unsigned long long)l2_path, (unsigned long long)mem_path);
        TB_EQ_INT(stat(&b, "node_l2.hits"), 1);
        TB_EQ_INT(stat(&b, "node_l2.misses"), 1);
        /* every retry of a waiting probe is an access that merges (looping) */
        TB_EQ_INT(stat(&b, "node_l1_0.miss_lines"), 1);
        TB_EQ_INT(stat(&b, "node_l1_0.hits"), 2);
        TB_EQ_INT(stat(&b, "node_l1_0.misses"), r0->probes - 2);
        TB_EQ_INT(stat(&b, "node_l1_0.merged"), r0->probes - 3);
        TB_EQ_INT(stat(&b, "node_l1_1.miss_lines"), 1);
        TB_CHECK(stat(&b, "node_l1_0.line_hit_rate") == 2.0 / 3.0, "line hit rate %g", stat(&b, "node_l1_0.line_hit_rate"));
        TB_CHECK(stat(&b, "node_l1_0.hit_rate") == 2.0 / (double)r0->probes, "hit rate %g", stat(&b, "node_l1_0.hit_rate"));
        TB_EQ_INT(stat(&b, "memory.requests"), 1);
        TB_EQ_INT(stat(&b, "memory.bytes"), 128);
        TB_EQ_INT(stat(&b, "memory.bytes_total"), 128);
        TB_EQ_INT(memsys_busy(b.ms), 0);
    }
    bench_free(&b);
    tb_end();
}

static void test_l2_merge_and_fairness(void)
{
    tb_begin("l2_merges_l1_misses_and_arbiter_is_fair");
    static bench b;   /* 1.8 MB: see bench */
    if (bench_init(&b, "bvh2", unlimited_bw, 4, false)) {
        requester *r[4];
        for (int i = 0; i < 4; i++) {
            r[i] = add_requester(&b, memsys_node_l1(b.ms, i), 64);
            /* all four walk the same 64 lines: the L2 merges or hits */
            for (int k = 0; k < 64; k++)
                push(r[i], 0x10000 + (uint64_t)k * 64, 0);
        }
        TB_EQ_INT(bench_run(&b, 100000), KS_RUN_FINISHED);
        TB_EQ_INT(stat(&b, "memory.requests"), 64);
        TB_EQ_INT(stat(&b, "node_l2.miss_lines"), 64);
        double merged = stat(&b, "node_l2.merged"), hits = stat(&b, "node_l2.hits");
        TB_EQ_INT(stat(&b, "node_l2.accesses"), 4 * 64);
        TB_CHECK(merged + hits == 3 * 64, "L2: merged %g + hits %g = 192", merged, hits);
        TB_CHECK(merged > 0, "simultaneous misses merge at the L2");
        char name[64];
        for (int i = 0; i < 4; i++) {
            TB_EQ_INT(r[i]->st[0].next, 64);
            snprintf(name, sizeof name, "l2_arbiter.grants_%d", i);
            TB_EQ_INT(stat(&b, name), 64);
        }
        TB_CHECK(stat(&b, "l2_arbiter.conflict_cycles") > 0, "arbiter saw contention");
        double hr = stat(&b, "node_l1.hit_rate");
        TB_CHECK(hr > 0 && hr < 1, "aggregate L1 hit rate %g", hr);
    }
    bench_free(&b);
    tb_end();
}

/* The smallest legal memory side (every FIFO 1 entry, one MSHR per cache,
 * no merging) is slow but never deadlocks: the response path never waits on
 * the request path. */
static void test_tiny_resources(const char *model)
{
    char name[80], m[40];
    snprintf(name, sizeof name, "one_entry_fifos_one_mshr_complete_%s", model);
    snprintf(m, sizeof m, "memory.model=%s", model);
    tb_begin(name);
    const char *sets[] = {m, "fifo.mem_l1_miss=1", "fifo.mem_l1_fill=1", "fifo.mem_l2_req=1", "fifo.mem_l2_resp=1",
                          "fifo.mem_l2_miss=1", "fifo.mem_l2_fill=1", "fifo.mem_prim_miss=1", "fifo.mem_prim_fill=1",
                          "fifo.mem_req=1", "fifo.mem_resp=1", "fifo.mem_dram_req=1", "fifo.mem_dram_resp=1",
                          "node_l1.mshrs=1", "node_l2.mshrs=1", "prim.mshrs=1", "node_l2.mshr_merge=1",
                          "memory.max_outstanding=1", NULL};
    static bench b;   /* 1.8 MB: see bench */
    if (bench_init(&b, "bvh2", sets, 4, false)) {
        for (int i = 0; i < 4; i++) {
            requester *r = add_requester(&b, memsys_node_l1(b.ms, i), 64);
            for (int k = 0; k < 16; k++)
                push_to(r, k % 4, 0x10000 + (uint64_t)((k * 5 + i) % 24) * 64, 0);
        }
        requester *ist = add_requester(&b, memsys_prim(b.ms), 48);
        for (int k = 0; k < 32; k++)
            push_to(ist, k % 8, 0x90000 + (uint64_t)k * 48, 0);
        ks_run_status st = bench_run(&b, 400000);
        TB_CHECK(st == KS_RUN_FINISHED, "run: %s %s", ks_run_status_name(st), ks_sim_deadlock_report(b.sim));
        for (int i = 0; i < 5; i++)
            for (int k = 0; k < b.req[i].ns; k++)
                TB_CHECK(b.req[i].st[k].next == b.req[i].st[k].n, "requester %d stream %d unfinished", i, k);
        TB_EQ_INT(memsys_busy(b.ms), 0);
    }
    bench_free(&b);
    tb_end();
}

/* The primitive cache streams distinct lines: the fixed memory's bandwidth
 * (12.8 GB/s at 500 MHz = 25.6 B/cycle, paper sec. 3.2) bounds the time. */
static void test_bandwidth(void)
{
    tb_begin("fixed_memory_bandwidth_bounds_streaming");
    static bench b;   /* 1.8 MB: see bench */
    const char *sets[] = {"memory.model=fixed", "memory.fixed_latency=20", "prim.mshrs=64", NULL};
    if (bench_init(&b, "mbvh4", sets, 1, false)) {
        /* one IST with 32 rays in flight, each reading 12 triangles of its own */
        const int per = 12, ns = 32;
        requester *r = add_requester(&b, memsys_prim(b.ms), 48);
        for (int i = 0; i < ns; i++)
            for (int k = 0; k < per; k++)
                push_to(r, i, 0x200000 + (uint64_t)(i * per + k) * 48, 0);
        TB_EQ_INT(bench_run(&b, 200000), KS_RUN_FINISHED);
        uint64_t last = 0;
        for (int i = 0; i < ns; i++)
            if (r->st[i].hit_cycle[per - 1] > last)
                last = r->st[i].hit_cycle[per - 1];
        double lines = stat(&b, "memory.requests");
        TB_EQ_INT(lines, ns * per * 48 / 64);   /* every line once */
        double min_cycles = lines * 64 / 25.6;
        fprintf(stderr, "  %g lines streamed in %llu cycles (bandwidth bound %.0f)\n", lines, (unsigned long long)last,
                min_cycles);
        TB_CHECK(last >= min_cycles && last < min_cycles * 1.25 + 100, "%g lines in %llu cycles (bound %.0f)", lines,
                 (unsigned long long)last, min_cycles);
        TB_CHECK(stat(&b, "memory.bus_busy_cycles") >= min_cycles - 1, "bus busy %g", stat(&b, "memory.bus_busy_cycles"));
        TB_EQ_INT(stat(&b, "prim.blocked_bank"), 0);
    }
    bench_free(&b);
    tb_end();
}

/* Idle skipping must not change a single cycle (kernel contract). */
static void test_idle_skipping_equivalence(const char *model)
{
    char name[80];
    snprintf(name, sizeof name, "idle_skipping_equals_exhaustive_stepping_%s", model);
    tb_begin(name);
    uint64_t hits[2][4][32];
    double mem[2];
    char set[64];
    snprintf(set, sizeof set, "memory.model=%s", model);
    const char *sets[] = {set, NULL};
    for (int mode = 0; mode < 2; mode++) {
        static bench b;   /* 1.8 MB: see bench */
        if (!bench_init(&b, "mbvh4", sets, 4, mode == 1))
            break;
        /* only the accelerator clock (our units) steps exhaustively: the DRAM
         * port's own lazy/exhaustive equivalence is tb_dram_port's subject */
        for (int i = 0; i < 4; i++) {
            requester *r = add_requester(&b, memsys_node_l1(b.ms, i), 128);
            for (int k = 0; k < 32; k++) /* overlapping, strided, with pauses */
                push(r, 0x8000 + (uint64_t)((k * 7 + i * 3) % 40) * 128, (uint64_t)(k / 8) * 300);
        }
        requester *ist = add_requester(&b, memsys_prim(b.ms), 48);
        for (int k = 0; k < 32; k++)
            push(ist, 0x300000 + (uint64_t)k * 48 * 5, (uint64_t)k * 10);
        bench_run(&b, 20000);
        for (int i = 0; i < 4; i++)
            memcpy(hits[mode][i], b.req[i].st[0].hit_cycle, sizeof hits[mode][i]);
        mem[mode] = stat(&b, "memory.latency_sum");
        TB_EQ_INT(b.req[4].st[0].next, 32);
        bench_free(&b);
    }
    TB_CHECK(memcmp(hits[0], hits[1], sizeof hits[0]) == 0, "hit cycles differ between modes");
    TB_CHECK(mem[0] == mem[1], "memory latency sum %g vs %g", mem[0], mem[1]);
    tb_end();
}

static void test_build_errors_and_tables(void)
{
    tb_begin("build_refuses_impossible_and_tables_are_complete");
    char err[512];
    rtcfg *cfg = rtcfg_create();
    TB_EQ_INT(memsys_add_schemas(cfg, err, sizeof err), 0);
    TB_EQ_INT(rtcfg_load(cfg, "mbvh4", err, sizeof err), 0);
    ks_sim *sim = ks_sim_create();
    ks_clock *clk = ks_clock_create(sim, "clk", 0);
    TB_CHECK(memsys_build(sim, clk, cfg, 0, NULL, err, sizeof err) == NULL && strstr(err, "allowed 1..64"), "0 TRVs: %s",
             err);
    TB_EQ_INT(rtcfg_set(cfg, "node_l1.line=256", err, sizeof err), 0);
    TB_CHECK(memsys_build(sim, clk, cfg, 4, NULL, err, sizeof err) == NULL && strstr(err, "node_l1.line = 256"),
             "L1 line above L2: %s", err);
    TB_EQ_INT(rtcfg_set(cfg, "node_l1.line=128", err, sizeof err), 0);
    TB_EQ_INT(rtcfg_set(cfg, "memory.model=lpddr3", err, sizeof err), 0);
    TB_EQ_INT(rtcfg_set(cfg, "memory.dram_config=/nonexistent/x.ini", err, sizeof err), 0);
    TB_CHECK(memsys_build(sim, clk, cfg, 4, NULL, err, sizeof err) == NULL &&
                 strstr(err, "memory.dram_config = /nonexistent/x.ini: /nonexistent/x.ini: cannot open"),
             "bad DRAM spec: %s", err);
    ks_sim_destroy(sim);
    rtcfg_destroy(cfg);
    const ks_module_desc *d[] = {&cache_module_desc, &mem_arbiter_module_desc, &fixed_mem_module_desc, &mem_dram_adapter_module_desc,
                                 &dram_port_module_desc};
    TB_CHECK(memsys_module_desc("node_l1") == &cache_module_desc && memsys_module_desc("prim") == &cache_module_desc &&
                 memsys_module_desc("l2_arbiter") == &mem_arbiter_module_desc && memsys_module_desc("fixed_mem") == &fixed_mem_module_desc &&
                 memsys_module_desc("dram") == &dram_port_module_desc && memsys_module_desc("trv") == NULL,
             "module lookup by name and instance");
    for (int i = 0; i < 5; i++) {
        TB_CHECK(ks_module_desc_check(d[i], err, sizeof err) == 0, "%s", err);
        /* parameters: configuration keys (the arbiter's requester count is
         * set by the assembly, so it is a row of its own) */
        TB_CHECK((d[i] == &mem_arbiter_module_desc ? ks_module_desc_count(d[i], KS_DESC_PARAM) > 0
                                            : d[i]->config_sections && ks_module_desc_count(d[i], KS_DESC_PARAM) == 0) &&
                     ks_module_desc_count(d[i], KS_DESC_PORT) > 0 && ks_module_desc_count(d[i], KS_DESC_STAT) > 0,
                 "%s lacks a section", d[i]->name);
    }
    /* every statistic the cache registers is documented */
    ks_stats *reg = ks_stats_create();
    sim = ks_sim_create();
    clk = ks_clock_create(sim, "clk", 0);
    cache_params p = {1024, 64, 4, 1, 1, 4, 4, 1, 0};
    cache_unit *u = cache_create(sim, clk, "c", &p, err, sizeof err);
    TB_EQ_INT(cache_register(u, reg, "c"), 0);
    TB_EQ_INT(ks_stats_count(reg), ks_module_desc_count(&cache_module_desc, KS_DESC_STAT));
    cache_destroy(u);
    ks_sim_destroy(sim);
    ks_stats_destroy(reg);
    tb_end();
}

/* LPDDR3 behind the memory side: the same traffic completes, byte counts
 * agree between the front end and the DRAM port, a sequential stream hits
 * open rows, and the bandwidth never exceeds the 12.8 GB/s peak. */
static void test_lpddr3(void)
{
    tb_begin("lpddr3_memory_streams_within_peak_bandwidth");
    static bench b;   /* 1.8 MB: see bench */
    const char *sets[] = {"memory.model=lpddr3", "prim.mshrs=64", NULL};
    if (bench_init(&b, "mbvh4", sets, 1, false)) {
        TB_CHECK(memsys_dram_port(b.ms) != NULL, "port built");
        const int per = 12, ns = 32;
        requester *r = add_requester(&b, memsys_prim(b.ms), 48);
        for (int i = 0; i < ns; i++)
            for (int k = 0; k < per; k++)
                push_to(r, i, 0x200000 + (uint64_t)(i * per + k) * 48, 0);
        requester *t = add_requester(&b, memsys_node_l1(b.ms, 0), 128);
        push(t, 0x40000, 0);
        push(t, 0x40000, 0);
        TB_EQ_INT(bench_run(&b, 400000), KS_RUN_FINISHED);
        uint64_t last = 0;
        for (int i = 0; i < ns; i++)
            if (r->st[i].hit_cycle[per - 1] > last)
                last = r->st[i].hit_cycle[per - 1];
        double lines = stat(&b, "memory.requests");
        TB_EQ_INT(lines, ns * per * 48 / 64 + 1);
        TB_EQ_INT(stat(&b, "memory.bytes"), stat(&b, "dram.bytes"));
        TB_EQ_INT(stat(&b, "dram.bursts"), stat(&b, "memory.bytes") / 32);
        double min_cycles = stat(&b, "memory.bytes") / 25.6;
        fprintf(stderr, "  LPDDR3: %g lines in %llu cycles (peak-bandwidth bound %.0f), row hit rate %g, "
                "mean latency %.1f cycles, single L1 miss %llu cycles\n", lines, (unsigned long long)last, min_cycles,
                stat(&b, "dram.row_hit_rate"), stat(&b, "memory.latency_sum") / lines,
                (unsigned long long)t->st[0].hit_cycle[0]);
        TB_CHECK(last >= min_cycles, "faster than the peak bandwidth");
        TB_CHECK(stat(&b, "dram.row_hit_rate") > 0.5, "sequential lines hit open rows");
        /* an idle DRAM read takes at least tRCD + CL + burst = 31 DRAM cycles = 20 accelerator cycles */
        TB_CHECK(t->st[0].hit_cycle[0] > 20 && t->st[0].hit_cycle[1] == t->st[0].hit_cycle[0] + 1, "L1 miss via DRAM");
        TB_EQ_INT(memsys_busy(b.ms), 0);
    }
    bench_free(&b);
    tb_end();

}

int main(void)
{
    test_fill_path_latency();
    test_l2_merge_and_fairness();
    test_bandwidth();
    test_tiny_resources("fixed");
    test_tiny_resources("lpddr3");
    test_idle_skipping_equivalence("fixed");
    test_idle_skipping_equivalence("lpddr3");
    test_lpddr3();
    test_build_errors_and_tables();
    return tb_finish();
}
