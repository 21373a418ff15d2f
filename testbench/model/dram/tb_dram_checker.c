/* tb_dram_checker — the timing checker against the controller:
 *  - the controller's own command streams (several configurations, mixed
 *    read/write traffic with locality, long enough for refresh) have zero
 *    violations, and the fast mode (scheduler wake caching, idle skipping) gives a
 *    bit-identical stream to the exhaustive every-cycle mode;
 *  - deliberately broken streams are caught, each with the rule it breaks. */
#include "testbench/tb.h"

#include <stdint.h>

#include "model/dram/dram_checker.h"
#include "model/dram/dram_ctrl.h"
#include "model/dram/dram_timing.h"
#include "model/dram/dram_trace.h"

static uint64_t rng_state;
static uint64_t rng(void)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return rng_state >> 33;
}

/* Mixed traffic: runs of sequential 64 B lines (two 32 B halves) and random lines, ~30 % writes. */
static char *make_trace(int lines, uint64_t seed, int write_pct)
{
    rng_state = seed;
    size_t cap = (size_t)lines * 24 + 16, used = 0;
    char *t = malloc(cap);
    uint64_t addr = 0;
    int run = 0;
    for (int i = 0; i < lines; i += 2) {
        if (run-- <= 0) {
            addr = (rng() % (1u << 20)) * 64; /* 64 MiB */
            run = (int)(rng() % 16);
        } else {
            addr += 64;
        }
        char rw = (int)(rng() % 100) < write_pct ? 'W' : 'R';
        used += (size_t)snprintf(t + used, cap - used, "0x%llx %c\n0x%llx %c\n", (unsigned long long)addr, rw,
                                 (unsigned long long)(addr + 32), rw);
    }
    return t;
}

typedef struct stream {
    dram_cmd_rec *v;
    size_t n, cap;
    uint64_t hash;
} stream;

static void on_cmd(void *u, const dram_cmd_rec *r)
{
    stream *s = u;
    if (s->n == s->cap) {
        s->cap = s->cap ? 2 * s->cap : 1024;
        s->v = realloc(s->v, s->cap * sizeof *s->v);
    }
    s->v[s->n++] = *r;
    uint64_t x = (uint64_t)r->cycle * 31 + (uint64_t)(r->channel * 7 + r->bank * 131 + r->cmd * 1009 + r->row);
    s->hash = (s->hash ^ x) * 1099511628211ull;
}

static int run_trace(const dram_spec *spec, const char *trace, int exhaustive, stream *s, int64_t *cycles)
{
    char err[256];
    memset(s, 0, sizeof *s);
    s->hash = 1469598103934665603ull;
    dram_ctrl *c = dram_ctrl_create(spec, NULL, NULL, err, sizeof err);
    if (!c)
        return -1;
    dram_set_exhaustive(c, exhaustive);
    dram_set_cmd_sink(c, on_cmd, s);
    FILE *f = fmemopen((void *)trace, strlen(trace), "r");
    dram_trace_result res;
    int rc = dram_trace_run(c, f, "synthetic", &res, err, sizeof err);
    fclose(f);
    *cycles = dram_clock(c);
    dram_ctrl_destroy(c);
    return rc;
}

static uint64_t check_stream(const dram_spec *spec, const dram_cmd_rec *v, size_t n, int64_t end, char *first,
                             size_t firstlen)
{
    dram_checker *k = dram_checker_create(spec, NULL, 0);
    for (size_t i = 0; i < n; i++)
        dram_checker_feed(k, &v[i]);
    uint64_t viol = dram_checker_finish(k, end);
    snprintf(first, firstlen, "%s", dram_checker_first(k));
    dram_checker_destroy(k);
    return viol;
}

static void controller_case(const char *name, const char *const *sets, int nsets, int lines, int write_pct)
{
    tb_begin(name);
    dram_spec spec;
    char err[512];
    if (!TB_CHECK(dram_spec_load(&spec, "model/data/lpddr3_1600.ini", sets, nsets, err, sizeof err) == 0, "%s",
                  err)) {
        tb_end();
        return;
    }
    char *trace = make_trace(lines, 42 + (uint64_t)lines, write_pct);
    stream fast, slow;
    int64_t cf, cs;
    TB_EQ_INT(run_trace(&spec, trace, 0, &fast, &cf), 0);
    TB_EQ_INT(run_trace(&spec, trace, 1, &slow, &cs), 0);
    TB_CHECK(fast.n > (size_t)lines / 2, "only %zu commands", fast.n);
    TB_CHECK(cf == cs && fast.n == slow.n && fast.hash == slow.hash,
             "fast mode differs from exhaustive: cycles %lld vs %lld, commands %zu vs %zu", (long long)cf,
             (long long)cs, fast.n, slow.n);
    size_t refs = 0, wrs = 0;
    for (size_t i = 0; i < fast.n; i++) {
        refs += fast.v[i].cmd == DRAM_REF;
        wrs += fast.v[i].cmd == DRAM_WR;
    }
    TB_CHECK(refs > 0, "stream has no refresh (too short)");
    TB_CHECK(write_pct == 0 || wrs > 0, "stream has no writes");
    char first[256];
    uint64_t viol = check_stream(&spec, fast.v, fast.n, cf, first, sizeof first);
    TB_CHECK(viol == 0, "%llu violations, first: %s", (unsigned long long)viol, first);
    free(fast.v);
    free(slow.v);
    free(trace);
    tb_end();
}

/* ---- broken streams ---- */

static dram_spec base;

static void broken_case(const char *name, const dram_cmd_rec *v, size_t n, const char *expect)
{
    tb_begin(name);
    char first[256];
    uint64_t viol = check_stream(&base, v, n, v[n - 1].cycle, first, sizeof first);
    TB_CHECK(viol >= 1, "not caught");
    TB_CHECK(strstr(first, expect) != NULL, "first violation '%s' does not mention '%s'", first, expect);
    tb_end();
}

#define R(cyc, bank, cmd, row) {cyc, 0, 0, bank, row, cmd}

int main(void)
{
    char err[512];
    const int sanitized = tb_is_sanitized();
    const int lines = sanitized ? 12000 : 60000;
    controller_case("dram_checker_default_mixed", NULL, 0, lines, 30);
    controller_case("dram_checker_reads_only", NULL, 0, lines, 0);
    controller_case("dram_checker_writes_heavy", NULL, 0, lines, 80);
    controller_case("dram_checker_cap2_queue8", (const char *const[]){"controller.row_hit_cap=2",
                    "controller.read_queue=8", "controller.write_queue=8"}, 3, lines, 30);
    controller_case("dram_checker_one_channel_two_ranks", (const char *const[]){"organization.channels=1",
                    "organization.ranks=2"}, 2, lines, 30);
    controller_case("dram_checker_slow_grade", (const char *const[]){"timing.nCL=14", "timing.nRCD=18",
                    "timing.nRAS=42", "timing.nRC=60", "timing.nFAW=50"}, 5, lines, 30);

    if (dram_spec_load(&base, "model/data/lpddr3_1600.ini", NULL, 0, err, sizeof err)) {
        printf("FAIL dram_checker_load: %s\n", err);
        return 1;
    }
    {   /* a valid reference stream first: m3 of the micro tests */
        tb_begin("dram_checker_valid_m3_stream");
        const dram_cmd_rec v[] = {R(1, 0, DRAM_ACT, 0), R(16, 0, DRAM_RD, -1), R(35, 0, DRAM_PRE, -1),
                                  R(50, 0, DRAM_ACT, 1), R(65, 0, DRAM_RD, -1)};
        char first[256];
        TB_EQ_INT(check_stream(&base, v, 5, 70, first, sizeof first), 0);
        tb_end();
    }
    broken_case("dram_checker_catches_tRCD", (const dram_cmd_rec[]){R(1, 0, DRAM_ACT, 0), R(15, 0, DRAM_RD, -1)}, 2,
                "bank ACT -> RD needs 15 cycles, got 14");
    broken_case("dram_checker_catches_tRAS",
                (const dram_cmd_rec[]){R(1, 0, DRAM_ACT, 0), R(16, 0, DRAM_RD, -1), R(34, 0, DRAM_PRE, -1)}, 3,
                "bank ACT -> PRE needs 34 cycles, got 33");
    broken_case("dram_checker_catches_tRP",
                (const dram_cmd_rec[]){R(1, 0, DRAM_ACT, 0), R(35, 0, DRAM_PRE, -1), R(49, 0, DRAM_ACT, 1)}, 3,
                "bank PRE -> ACT needs 15 cycles, got 14");
    broken_case("dram_checker_catches_tRRD", (const dram_cmd_rec[]){R(1, 0, DRAM_ACT, 0), R(8, 1, DRAM_ACT, 0)}, 2,
                "rank ACT -> ACT needs 8 cycles, got 7");
    broken_case("dram_checker_catches_tFAW",
                (const dram_cmd_rec[]){R(1, 0, DRAM_ACT, 0), R(9, 1, DRAM_ACT, 0), R(17, 2, DRAM_ACT, 0),
                                       R(25, 3, DRAM_ACT, 0), R(40, 4, DRAM_ACT, 0)}, 5,
                "rank ACT -> ACT (window) needs 40 cycles, got 39");
    broken_case("dram_checker_catches_tCCD",
                (const dram_cmd_rec[]){R(1, 0, DRAM_ACT, 0), R(16, 0, DRAM_RD, -1), R(19, 0, DRAM_RD, -1)}, 3,
                "RD -> RD needs 4 cycles, got 3");
    broken_case("dram_checker_catches_tWTR",
                (const dram_cmd_rec[]){R(1, 0, DRAM_ACT, 0), R(16, 0, DRAM_WR, -1), R(32, 0, DRAM_RD, -1)}, 3,
                "rank WR -> RD needs 17 cycles, got 16");
    broken_case("dram_checker_catches_RD_to_WR",
                (const dram_cmd_rec[]){R(1, 0, DRAM_ACT, 0), R(16, 0, DRAM_RD, -1), R(28, 0, DRAM_WR, -1)}, 3,
                "rank RD -> WR needs 13 cycles, got 12");
    broken_case("dram_checker_catches_tWR",
                (const dram_cmd_rec[]){R(1, 0, DRAM_ACT, 0), R(16, 0, DRAM_WR, -1), R(37, 0, DRAM_PRE, -1)}, 3,
                "bank WR -> PRE needs 22 cycles, got 21");
    broken_case("dram_checker_catches_missing_PRE",
                (const dram_cmd_rec[]){R(1, 0, DRAM_ACT, 0), R(16, 0, DRAM_RD, -1), R(60, 0, DRAM_ACT, 1)}, 3,
                "ACT to an open bank");
    broken_case("dram_checker_catches_RD_closed_bank", (const dram_cmd_rec[]){R(5, 3, DRAM_RD, -1)}, 1,
                "RD to a closed bank");
    broken_case("dram_checker_catches_REF_open_bank",
                (const dram_cmd_rec[]){R(1, 0, DRAM_ACT, 0), R(100, -1, DRAM_REF, -1)}, 2, "REF with 1 open bank");
    broken_case("dram_checker_catches_tRFC",
                (const dram_cmd_rec[]){R(1, -1, DRAM_REF, -1), R(104, 0, DRAM_ACT, 0)}, 2,
                "rank REF -> ACT needs 104 cycles, got 103");
    broken_case("dram_checker_catches_PREA_to_REF",
                (const dram_cmd_rec[]){R(1, 0, DRAM_ACT, 0), R(40, -1, DRAM_PREA, -1), R(56, -1, DRAM_REF, -1)}, 3,
                "rank PREA -> REF needs 17 cycles, got 16");
    broken_case("dram_checker_catches_bus_conflict",
                (const dram_cmd_rec[]){R(1, 0, DRAM_ACT, 0), R(1, 1, DRAM_PRE, -1)}, 2, "command bus");
    broken_case("dram_checker_catches_refresh_starvation",
                (const dram_cmd_rec[]){R(1, 0, DRAM_ACT, 0), R(40000, 0, DRAM_RD, -1)}, 2, "refresh:");
    {   /* mutate a real controller stream: shift one RD a cycle earlier; must be caught */
        tb_begin("dram_checker_catches_mutated_controller_stream");
        char *trace = make_trace(4000, 7, 30);
        stream s;
        int64_t cyc;
        run_trace(&base, trace, 0, &s, &cyc);
        size_t mutated = 0;
        for (size_t i = 0; i < s.n && !mutated; i++) {
            if (s.v[i].cmd != DRAM_RD)
                continue;
            int64_t act = -1, busy = 0;
            for (size_t j = i; j-- > 0 && s.v[j].cycle >= s.v[i].cycle - 20;) {
                if (s.v[j].channel != s.v[i].channel)
                    continue;
                busy |= s.v[j].cycle == s.v[i].cycle - 1;
                if (act < 0 && s.v[j].bank == s.v[i].bank && s.v[j].cmd == DRAM_ACT)
                    act = s.v[j].cycle;
            }
            if (act >= 0 && s.v[i].cycle - act == 15 && !busy) {
                s.v[i].cycle--;
                mutated = 1;
            }
        }
        char first[256];
        TB_CHECK(mutated == 1, "no ACT->RD pair at exactly tRCD found to mutate");
        uint64_t viol = check_stream(&base, s.v, s.n, cyc, first, sizeof first);
        TB_CHECK(viol >= 1 && strstr(first, "ACT -> RD") != NULL, "violations %llu, first '%s'",
                 (unsigned long long)viol, first);
        free(s.v);
        free(trace);
        tb_end();
    }
    return tb_finish();
}
