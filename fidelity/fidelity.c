/* fidelity.c — the fidelity levels (fidelity.h, docs/fidelity.md); the
 * automatic choice of --accuracy is accuracy.c. */
#include "fidelity/fidelity.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "frame/frame.h"
#include "fidelity/fidelity_params.h"
#include "fidelity/levels.h"
#include "kernel/fork_pool.h"
#include "kernel/json.h"
#include "fidelity/functional.h"
#include "fidelity/subset.h"
#include "fidelity/estimator.h"
#include "fidelity/windowed.h"
#include "model/mem/memsys_config.h"

static const char *const level_names[FID_LEVEL_COUNT] = {"full",    "fixed-mem", "functional",
                                                         "sampled", "windowed"};

const char *fid_level_name(fid_level l) { return l < FID_LEVEL_COUNT ? level_names[l] : "?"; }

bool fid_level_parse(const char *s, fid_level *out)
{
    for (int i = 0; i < FID_LEVEL_COUNT; i++)
        if (!strcmp(s, level_names[i])) {
            *out = (fid_level)i;
            return true;
        }
    return false;
}

bool fid_accuracy_parse(const char *s, double *fraction)
{
    char *end;
    if (!s || !*s)
        return false;
    double v = strtod(s, &end);
    if (end == s || (*end && strcmp(end, "%")) || !(v > 0) || v > 100)
        return false;
    *fraction = v / 100.0;
    return true;
}

void fid_result_full(fid_result *r)
{
    memset(r, 0, sizeof *r);
    r->level = FID_FULL;
}

/* ---- statistics, summary, JSON ---------------------------------------- */


static double pct_fn(const ks_stats *reg, void *user)
{
    (void)reg;
    return *(const double *)user * 100.0;
}

static double level_fn(const ks_stats *reg, void *user)
{
    (void)reg;
    return (double)((const fid_result *)user)->level;
}

static const ks_desc_item fid_items[] = {
    {KS_DESC_STAT, "fidelity_level", "level", "", "",
     "fidelity of the figures: 0 full, 1 fixed-mem, 2 functional, 3 sampled, 4 windowed (the string is "
     "\"fidelity\")"},
    {KS_DESC_STAT, "unreliable", "flag", "", "",
     "1 when a figure may lie outside its error estimate (reason: \"unreliable_reason\")"},
    {KS_DESC_STAT, "error_estimate.mrps", "%", "", "", "estimated relative error of mrps against the full model"},
    {KS_DESC_STAT, "error_estimate.dram_mb", "%", "", "",
     "estimated relative error of dram_bytes against the full model"},
    {KS_DESC_STAT, "error_estimate.energy_mj", "%", "", "",
     "estimated relative error of energy_mj against the full model"},
    {KS_DESC_END, 0, 0, 0, 0, 0}};
const ks_module_desc fid_module_desc = {"fidelity", "fidelity of a run's figures and their error estimates",
                                        fid_items, NULL};

int fid_register_stats(fid_result *r, ks_stats *st)
{
    const ks_module_desc *d = &fid_module_desc;
    int rc = 0;
    rc |= ks_stat_decl_formula(st, d, NULL, "fidelity_level", level_fn, r);
    rc |= ks_stat_decl_counter(st, d, NULL, "unreliable", &r->unreliable);
    rc |= ks_stat_decl_formula(st, d, NULL, "error_estimate.mrps", pct_fn, &r->err_mrps);
    rc |= ks_stat_decl_formula(st, d, NULL, "error_estimate.dram_mb", pct_fn, &r->err_dram_mb);
    rc |= ks_stat_decl_formula(st, d, NULL, "error_estimate.energy_mj", pct_fn, &r->err_energy_mj);
    return rc;
}

void fid_print_summary(const fid_result *r, FILE *out)
{
    fprintf(out, "fidelity    %s; error estimate MRPS %.1f%%, DRAM MB %.1f%%, mJ/frame %.1f%%%s\n",
            fid_level_name(r->level), 100.0 * r->err_mrps, 100.0 * r->err_dram_mb, 100.0 * r->err_energy_mj,
            r->unreliable ? "; UNRELIABLE" : "");
    if (r->unreliable)
        fprintf(out, "unreliable  %s\n", r->reason);
    if (r->detail[0])
        fprintf(out, "method      %s\n", r->detail);
    if (r->choice[0])
        fprintf(out, "accuracy    %s\n", r->choice);
}

/* The level's JSON members; strings through the project's one escaping
 * (kernel/json.h: control characters as \u00XX). */
void fid_json_strings(const fid_result *r, char *buf, size_t len)
{
    char *text = NULL;
    size_t n = 0;
    FILE *m = open_memstream(&text, &n);
    if (!m) {
        if (len)
            buf[0] = 0;
        return;
    }
    fprintf(m, "  \"fidelity\": \"%s\",\n  \"unreliable_reason\": ", fid_level_name(r->level));
    ks_json_string(m, r->reason);
    fputs(",\n  \"fidelity_choice\": ", m);
    ks_json_string(m, r->choice);
    fputs(",\n", m);
    fclose(m);
    snprintf(buf, len, "%s", text ? text : "");
    free(text);
}

/* ---- pixel subsets: interleaved row bands ------------------------------- */

/* Pixels of group g of `groups` interleaved sets of bands (fp->band_rows rows
 * each, the full width), each set taking one band in `period`, in scanline
 * order. Whole rows keep the frame's order of rays within a row, and so its
 * cache locality (tiles spread over a row lose it: docs/fidelity.md). */
static uint32_t *band_subset(const fid_job *job, uint32_t period, uint32_t group, uint32_t groups, uint32_t *n)
{
    const fid_params *fp = fid_params_get();
    uint32_t T = (uint32_t)fp->band_rows, w = job->width, h = job->height;
    uint32_t *px = malloc((size_t)w * h * sizeof *px);
    *n = 0;
    if (!px)
        return NULL;
    uint32_t step = period / groups ? period / groups : 1;
    for (uint32_t y = 0; y < h; y++) {
        if ((y / T) % period != (group * step) % period)
            continue;
        for (uint32_t x = 0; x < w; x++)
            px[(*n)++] = y * w + x;
    }
    return px;
}

/* ---- running the cycle model on a pixel subset (subset.h) -------------- */

/* Figures of a cycle-model run. */
typedef struct model_fig {
    double cycles, rays, mrps, dram_bytes, energy_mj, static_mj, dram_mj, dram_static_mj;
    double mem_latency, dram_gbs, row_hit, mem_requests;
    double unit_dyn_mj[EU_DRAM];  /* dynamic energy of the units before DRAM (energy.h order: trv .. fifo) */
} model_fig;

/* A statistic the levels need: absent, it is a renamed one, which must not
 * read as 0 (the first missing name is kept in *missing). */
static double stat_need(ks_stats *st, const char *name, const char **missing)
{
    double v = 0;
    if (ks_stats_value(st, name, &v) && !*missing)
        *missing = name;
    return v;
}

/* The figures of a cycle-model run; 0, or -1 with the first statistic that
 * is missing named in err. The energy figures are needed when the run has
 * an energy model; the memory's when it has the LPDDR3 model (the fixed
 * memory has neither rows nor a latency sum). */
static int get_fig(accel_top *t, model_fig *f, char *err, size_t errlen)
{
    ks_stats *st = accel_top_stats(t);
    const char *missing = NULL, *opt = NULL;
    char names[2 * EU_COUNT][64];
    memset(f, 0, sizeof *f);
    f->cycles = stat_need(st, "cycles", &missing);
    f->rays = stat_need(st, "rays", &missing);
    f->mrps = stat_need(st, "mrps", &missing);
    f->dram_bytes = stat_need(st, "dram_bytes", &missing);
    f->dram_gbs = stat_need(st, "dram_bandwidth_gbs", &missing);
    bool energy = ks_stats_value(st, "energy_mj", &f->energy_mj) == 0;
    for (int u = 0; energy && u < EU_COUNT; u++) {
        snprintf(names[2 * u], sizeof names[0], "energy.%s_static_mj", energy_unit_name((energy_unit)u));
        f->static_mj += stat_need(st, names[2 * u], &missing);
        snprintf(names[2 * u + 1], sizeof names[0], "energy.%s_dynamic_mj", energy_unit_name((energy_unit)u));
        if (u < EU_DRAM)
            f->unit_dyn_mj[u] = stat_need(st, names[2 * u + 1], &missing);
    }
    if (energy) {
        f->dram_mj = stat_need(st, "energy.dram_mj", &missing);
        f->dram_static_mj = stat_need(st, "energy.dram_static_mj", &missing);
    }
    bool lpddr3 = ks_stats_value(st, "memory.requests", &f->mem_requests) == 0;
    if (lpddr3) {
        f->mem_latency = f->mem_requests > 0 ? stat_need(st, "memory.latency_sum", &missing) / f->mem_requests : 0;
        f->row_hit = stat_need(st, "dram.row_hit_rate", &opt);   /* only with a row-level DRAM model */
    }
    if (missing) {
        snprintf(err, errlen, "the model's statistic %s is missing (renamed?); the fidelity levels read it", missing);
        return -1;
    }
    return 0;
}

/* Runs the cycle model with cfg on the pixels map[0..n) (map NULL: the
 * whole frame). *keep: the top is handed back (else destroyed). tag: the
 * run's figures make the result, so with --series it writes its rows
 * (fid_subset_open_series; NULL: it does not). */
static int run_model_series(const fid_job *job, const rtcfg *cfg, const uint32_t *map, uint32_t n, model_fig *fig,
                            accel_top **keep, const char *tag, uint32_t piece, char *err, size_t errlen)
{
    fid_subset sub;
    if (fid_subset_open_series(&sub, job, cfg, map, n, tag, piece, tag, err, errlen))
        return 2;
    int rc = accel_top_run(sub.top, map ? NULL : job->progress, job->progress_user, err, errlen) ? 1 : 0;
    if (get_fig(sub.top, fig, err, errlen) && rc == 0)
        rc = 2;
    if (keep && rc == 0) {
        accel_top_detach_series(sub.top);
        *keep = sub.top;
        sub.top = NULL;
    }
    if (fid_subset_close(&sub) && rc == 0) {
        snprintf(err, errlen, "--series: writing the rows of a run failed");
        rc = 2;
    }
    return rc;
}


static int run_model(const fid_job *job, const rtcfg *cfg, const uint32_t *map, uint32_t n, model_fig *fig,
                     accel_top **keep, char *err, size_t errlen)
{
    return run_model_series(job, cfg, map, n, fig, keep, NULL, 0, err, errlen);
}

/* ---- own statistics registry (functional, sampled) ---------------------- */

/* the most windows whose residuals the JSON carries (--windows goes to
 * 4096; a sweep's paired estimate with more runs without them) */
enum { FID_PAIRED_MAX_WINDOWS = 1024 };

typedef struct fid_own {
    uint64_t cycles, rays, primaries, bounces, dram_bytes, visits, box_tests, leaves, tri_tests;
    double mrps, dram_gbs, energy_mj, l1_hit, l2_hit, prim_hit, row_hit;
    double cyc_trv, cyc_ist, cyc_dram, cyc_lat, mem_latency, runner_up, phase_excess;
    uint64_t samples, sample_rays;
    double sample_rate;
    uint64_t windows, window_pixels, warm_pixels, model_pixels, lattice_pixels;
    double cold_share;
    /* windowed, with an energy model: Table 1's figures per unit
     * (model/energy/energy.h order) and each power's error estimate (%) */
    double unit_dyn_mj[EU_COUNT], unit_static_mj[EU_COUNT], unit_mj[EU_COUNT], unit_mw[EU_COUNT];
    double unit_mm2[EU_COUNT], unit_mw_err[EU_COUNT];
    /* windowed: what a sweep's paired estimate needs (docs/fidelity.md
     * "Paired estimates"): each window's residual per headline figure, in
     * image order, as it enters the interval; the random errors beside it
     * that do not pair (the lattice's and the start correction's, in
     * quadrature, %); the bias bounds (%); the t of the interval */
    double resid[FID_WIN_HEADLINE][FID_PAIRED_MAX_WINDOWS];
    double other_err[FID_WIN_HEADLINE], bias_err[FID_WIN_HEADLINE], t95;
    uint64_t paired_windows;
    const char *bound;
    bool has_func, is_sampled, is_windowed, has_units;
} fid_own;

static int own_stats(fid_outcome *o)
{
    fid_own *w = o->own;
    ks_stats *st = o->stats = ks_stats_create();
    if (!st)
        return -1;
    int rc = 0;
    rc |= ks_stat_counter_ref(st, "cycles", "cycles", "estimated accelerator cycles of the frame", &w->cycles);
    rc |= ks_stat_counter_ref(st, "rays", "rays", "rays traced (primary and bounce)", &w->rays);
    rc |= ks_stat_real_ref(st, "mrps", "Mrays/s", "estimated million rays per second at the machine clock", &w->mrps);
    rc |= ks_stat_counter_ref(st, "dram_bytes", "bytes", "estimated bytes transferred from/to main memory",
                              &w->dram_bytes);
    rc |= ks_stat_real_ref(st, "dram_bandwidth_gbs", "GB/s", "estimated mean main memory bandwidth", &w->dram_gbs);
    rc |= ks_stat_real_ref(st, "energy_mj", "mJ", "estimated energy of the frame", &w->energy_mj);
    rc |= ks_stat_counter_ref(st, "sched.primaries", "rays", "primary rays", &w->primaries);
    rc |= ks_stat_counter_ref(st, "sched.bounces", "rays", "bounce rays", &w->bounces);
    if (w->has_func) {
        rc |= ks_stat_counter_ref(st, "functional.visits", "nodes", "node visits of the frame", &w->visits);
        rc |= ks_stat_counter_ref(st, "functional.box_tests", "tests", "child slab tests", &w->box_tests);
        rc |= ks_stat_counter_ref(st, "functional.leaves", "leaves", "leaves sent to the IST", &w->leaves);
        rc |= ks_stat_counter_ref(st, "functional.tri_tests", "tests", "triangle tests", &w->tri_tests);
        rc |= ks_stat_real_ref(st, "functional.node_l1_hit_rate", "ratio", "node L1 hits / accesses", &w->l1_hit);
        rc |= ks_stat_real_ref(st, "functional.node_l2_hit_rate", "ratio", "node L2 hits / accesses", &w->l2_hit);
        rc |= ks_stat_real_ref(st, "functional.prim_hit_rate", "ratio", "primitive cache hits / accesses",
                               &w->prim_hit);
        rc |= ks_stat_real_ref(st, "functional.dram_row_hit_rate", "ratio",
                               "DRAM line reads that found their row open", &w->row_hit);
        rc |= ks_stat_real_ref(st, "functional.cycles_trv", "cycles", "busiest TRV's issue cycles", &w->cyc_trv);
        rc |= ks_stat_real_ref(st, "functional.cycles_ist", "cycles", "IST issue cycles", &w->cyc_ist);
        rc |= ks_stat_real_ref(st, "functional.cycles_dram", "cycles", "DRAM transfer cycles at peak bandwidth",
                               &w->cyc_dram);
        rc |= ks_stat_real_ref(st, "functional.cycles_latency", "cycles",
                               "latency bound: summed ray latencies / ray slots (Little's law)", &w->cyc_lat);
        rc |= ks_stat_real_ref(st, "functional.mem_latency", "cycles", "modelled memory latency at the utilisation",
                               &w->mem_latency);
        rc |= ks_stat_real_ref(st, "functional.runner_up", "ratio", "second largest bound / largest (1 = a tie)",
                               &w->runner_up);
        rc |= ks_stat_real_ref(st, "functional.phase_excess", "ratio",
                               "busiest issue unit's work summed phase by phase (func_phases runs of the "
                               "primaries) / over the frame, - 1",
                               &w->phase_excess);
    }
    if (w->is_sampled) {
        rc |= ks_stat_counter_ref(st, "sample.groups", "groups", "independent groups of pixel rows modelled",
                                  &w->samples);
        rc |= ks_stat_counter_ref(st, "sample.rays", "rays", "rays through the full model", &w->sample_rays);
        rc |= ks_stat_real_ref(st, "sample.rate", "fraction", "fraction of the pixels modelled", &w->sample_rate);
    }
    if (w->is_windowed) {
        rc |= ks_stat_counter_ref(st, "window.count", "windows", "windows of consecutive pixels modelled", &w->windows);
        rc |= ks_stat_counter_ref(st, "window.pixels", "pixels", "pixels measured per window", &w->window_pixels);
        rc |= ks_stat_counter_ref(st, "window.warm_pixels", "pixels", "pixels of the warm-up before each window",
                                  &w->warm_pixels);
        rc |= ks_stat_counter_ref(st, "window.model_pixels", "pixels",
                                  "pixels through the full model (warm-ups and windows)", &w->model_pixels);
        rc |= ks_stat_counter_ref(st, "window.lattice_pixels", "pixels",
                                  "pixels through the functional level for the frame's auxiliary figures",
                                  &w->lattice_pixels);
        rc |= ks_stat_real_ref(st, "window.cold_fill_share", "ratio",
                               "fills into never-used ways of node L2 and primitive cache / their fills, in the windows",
                               &w->cold_share);
        static const char *const fig[FID_WIN_HEADLINE] = {"mrps", "dram_mb", "energy_mj"};
        rc |= ks_stat_counter_ref(st, "window.paired_windows", "windows",
                                  "windows whose residuals follow (0: too many to list)", &w->paired_windows);
        rc |= ks_stat_real_ref(st, "window.t95", "ratio", "Student t of the windows' 95% interval", &w->t95);
        for (int k = 0; k < FID_WIN_HEADLINE; k++) {
            char key[96], desc[200];
            snprintf(key, sizeof key, "window.other_err.%s", fig[k]);
            snprintf(desc, sizeof desc, "%s: the lattice's and the start correction's 95%% errors in quadrature",
                     fig[k]);
            rc |= ks_stat_real_ref(st, key, "%", desc, &w->other_err[k]);
            snprintf(key, sizeof key, "window.bias_err.%s", fig[k]);
            snprintf(desc, sizeof desc, "%s: the bias bounds (cold fills + floor)", fig[k]);
            rc |= ks_stat_real_ref(st, key, "%", desc, &w->bias_err[k]);
            for (uint64_t q = 0; q < w->paired_windows; q++) {
                snprintf(key, sizeof key, "window.resid.%s.%llu", fig[k], (unsigned long long)q);
                snprintf(desc, sizeof desc,
                         "window %llu (image order): its residual of %s as it enters the interval, relative to "
                         "the frame's figure",
                         (unsigned long long)q, k == FID_WIN_CYCLES ? "the cycles" : fig[k]);
                rc |= ks_stat_real_ref(st, key, "ratio", desc, &w->resid[k][q]);
            }
        }
    }
    /* windowed's Table 1 figures, under the full model's names
     * (model/energy/energy.c), so Table 1 reads either */
    const struct {
        const char *key, *unit, *desc;
        double *v;
    } per_unit[] = {
        {"energy.%s_dynamic_mj", "mJ", "estimated dynamic energy of the %s units", w->unit_dyn_mj},
        {"energy.%s_static_mj", "mJ", "estimated static energy of the %s units", w->unit_static_mj},
        {"energy.%s_mj", "mJ", "estimated energy of the %s units", w->unit_mj},
        {"power.%s_mw", "mW", "estimated mean power of the %s units", w->unit_mw},
        {"area.%s_mm2", "mm2", "area of the %s units", w->unit_mm2},
        {"error_estimate.power_%s_mw", "%", "estimated error of power.%s_mw, relative", w->unit_mw_err},
    };
    for (int u = 0; u < EU_COUNT && w->has_units; u++)
        for (size_t i = 0; i < sizeof per_unit / sizeof per_unit[0]; i++) {
            char key[96], desc[160];
            snprintf(key, sizeof key, per_unit[i].key, energy_unit_name((energy_unit)u));
            snprintf(desc, sizeof desc, per_unit[i].desc, energy_unit_name((energy_unit)u));
            rc |= ks_stat_real_ref(st, key, per_unit[i].unit, desc, &per_unit[i].v[u]);
        }
    rc |= fid_register_stats(&o->res, st);
    return rc;
}

static void own_from_func(fid_own *w, const fid_func *f)
{
    w->has_func = true;
    w->visits = f->visits, w->box_tests = f->box_tests, w->leaves = f->leaves, w->tri_tests = f->tri_tests;
    w->primaries = f->primaries, w->bounces = f->bounces, w->rays = f->rays;
    w->l1_hit = f->l1.accesses ? (double)f->l1.hits / (double)f->l1.accesses : 0;
    w->l2_hit = f->l2.accesses ? (double)f->l2.hits / (double)f->l2.accesses : 0;
    w->prim_hit = f->prim.accesses ? (double)f->prim.hits / (double)f->prim.accesses : 0;
    w->row_hit = f->dram_lines ? (double)f->row_hits / (double)f->dram_lines : 0;
    w->cyc_trv = f->cyc_trv, w->cyc_ist = f->cyc_ist, w->cyc_dram = f->cyc_dram, w->cyc_lat = f->cyc_lat;
    w->mem_latency = f->mem_latency, w->runner_up = f->runner_up, w->bound = f->bound;
    w->phase_excess = f->phase_excess;
}

static void set_headline(fid_outcome *o, double clock_mhz)
{
    fid_own *w = o->own;
    double sec = (double)w->cycles / (clock_mhz * 1e6);
    w->mrps = sec > 0 ? (double)w->rays / sec / 1e6 : 0;
    w->dram_gbs = sec > 0 ? (double)w->dram_bytes / sec / 1e9 : 0;
    o->cycles = (double)w->cycles, o->rays = (double)w->rays, o->mrps = w->mrps;
    o->dram_bytes = (double)w->dram_bytes, o->energy_mj = w->energy_mj;
}

/* ---- the levels ---------------------------------------------------------- */

static void set_unreliable(fid_result *r, const char *why)
{
    if (!r->unreliable)
        snprintf(r->reason, sizeof r->reason, "%s", why);
    else {
        size_t n = strlen(r->reason);
        snprintf(r->reason + n, sizeof r->reason - n, "; %s", why);
    }
    r->unreliable = 1;
}

/* Saves and restores the memory keys fixed-mem changes. */
typedef struct mem_keys {
    char model[32], latency[32], bw[64], pj[64];
} mem_keys;

static void save_keys(const rtcfg *cfg, mem_keys *k)
{
    snprintf(k->model, sizeof k->model, "memory.model=%s", rtcfg_str(cfg, "memory.model"));
    snprintf(k->latency, sizeof k->latency, "memory.fixed_latency=%lld", (long long)rtcfg_int(cfg, "memory.fixed_latency"));
    snprintf(k->bw, sizeof k->bw, "memory.fixed_bandwidth_gbs=%.17g", rtcfg_real(cfg, "memory.fixed_bandwidth_gbs"));
    snprintf(k->pj, sizeof k->pj, "energy.fixed_mem_pj_per_byte=%.17g", rtcfg_real(cfg, "energy.fixed_mem_pj_per_byte"));
}

static int restore_keys(rtcfg *cfg, const mem_keys *k, char *err, size_t errlen)
{
    return rtcfg_set(cfg, k->model, err, errlen) || rtcfg_set(cfg, k->latency, err, errlen) ||
                   rtcfg_set(cfg, k->bw, err, errlen) || rtcfg_set(cfg, k->pj, err, errlen)
               ? 2
               : 0;
}

static int set_fixed(rtcfg *cfg, double latency, double pj, char *err, size_t errlen)
{
    char a[64], b[64];
    snprintf(a, sizeof a, "memory.fixed_latency=%lld", (long long)llround(latency < 1 ? 1 : latency));
    snprintf(b, sizeof b, "energy.fixed_mem_pj_per_byte=%.6g", pj);
    return rtcfg_set(cfg, "memory.model=fixed", err, errlen) || rtcfg_set(cfg, a, err, errlen) ||
                   rtcfg_set(cfg, b, err, errlen)
               ? 2
               : 0;
}

static uint32_t pilot_period(const fid_job *job, double fraction)
{
    const fid_params *fp = fid_params_get();
    double pixels = (double)job->width * job->height;
    if (pixels * fraction < fp->pilot_min_pixels)
        fraction = fp->pilot_min_pixels / pixels;
    if (fraction >= 0.5)
        return 1;
    return (uint32_t)llround(1.0 / fraction);
}

/* fixed-mem: a full pilot on interleaved row bands measures the memory (mean
 * latency, achieved bandwidth, DRAM energy per byte); the fixed model's
 * latency is fitted so that the pilot's cycles match (two fixed pilots and
 * a secant step); then the whole frame runs on the fitted fixed memory. */
static int run_fixed_mem(const fid_job *job, fid_outcome *o, char *err, size_t errlen)
{
    const fid_params *fp = fid_params_get();
    rtcfg *cfg = job->cfg;
    fid_result *r = &o->res;
    r->level = FID_FIXED_MEM;
    if (rtcfg_enum(cfg, "memory.model") != MEMSYS_LPDDR3) {
        model_fig f;
        snprintf(r->detail, sizeof r->detail, "memory.model is already fixed: the full model of this machine");
        return run_model_series(job, cfg, NULL, 0, &f, &o->top, "frame", 0, err, errlen);
    }
    mem_keys saved;
    save_keys(cfg, &saved);
    uint32_t period = pilot_period(job, fp->pilot_fraction), n = 0;
    uint32_t *px = NULL;
    if (period > 1 && !(px = band_subset(job, period, 0, 1, &n))) {
        snprintf(err, errlen, "out of memory");
        return 2;
    }
    model_fig full, f0, f1, fin;
    double L = 0, util = 0, resid = 0, dram_static_share = 0, pilot_latency = 0, pilot_row_hit = 1;
    int rc = run_model(job, cfg, px, n, &full, NULL, err, errlen);
    if (rc == 0) {
        double gbs = rtcfg_real(cfg, "memory.fixed_bandwidth_gbs");
        double bpc = gbs * 1000.0 / rtcfg_real(cfg, "machine.clock_mhz");
        util = gbs > 0 ? full.dram_gbs / gbs : 0;
        double line = full.mem_requests > 0 ? full.dram_bytes / full.mem_requests : 64;
        /* the fixed model moves the line over its bus before the latency */
        double L0 = fmax(1.0, full.mem_latency - (bpc > 0 ? line / bpc : 0));
        double pj = full.dram_bytes > 0 ? full.dram_mj * 1e9 / full.dram_bytes : rtcfg_real(cfg, "energy.fixed_mem_pj_per_byte");
        L = L0;
        dram_static_share = full.energy_mj > 0 ? full.dram_static_mj / full.energy_mj : 0;
        pilot_latency = full.mem_latency, pilot_row_hit = full.row_hit;
        if (!(rc = set_fixed(cfg, L0, pj, err, errlen)))
            rc = run_model(job, cfg, px, n, &f0, NULL, err, errlen);
        if (rc == 0 && full.cycles > 0 && fabs(f0.cycles - full.cycles) > 0.005 * full.cycles) {
            double L1 = fmax(1.0, L0 * (f0.cycles > full.cycles ? 0.7 : 1.3));
            if (!(rc = set_fixed(cfg, L1, pj, err, errlen)))
                rc = run_model(job, cfg, px, n, &f1, NULL, err, errlen);
            if (rc == 0 && fabs(f1.cycles - f0.cycles) > 0.5)
                L = L0 + (full.cycles - f0.cycles) * (L1 - L0) / (f1.cycles - f0.cycles);
            else if (rc == 0)
                L = L1;
            L = fmin(fmax(L, 1.0), 20.0 * L0 + 100.0);
            resid = fmin(fabs(f0.cycles - full.cycles), fabs(f1.cycles - full.cycles)) / full.cycles;
            if (fabs(f1.cycles - full.cycles) < fabs(f0.cycles - full.cycles) && fabs(f1.cycles - f0.cycles) <= 0.5)
                L = L1;
        }
        if (rc == 0 && !(rc = set_fixed(cfg, L, pj, err, errlen)))
            rc = run_model_series(job, cfg, NULL, 0, &fin, &o->top, "frame", 0, err, errlen);
        snprintf(r->detail, sizeof r->detail,
                 "full-fidelity pilot on %u of %u pixels (row bands): mean memory latency %.1f cycles, %.2f GB/s "
                 "(%.0f%% of peak), %.0f%% row hits; fixed memory calibrated to latency %.0f cycles, %.0f pJ/byte",
                 px ? n : job->width * job->height, job->width * job->height, full.mem_latency, full.dram_gbs,
                 100.0 * util, 100.0 * full.row_hit, L, pj);
    }
    if (restore_keys(cfg, &saved, err, errlen) && rc == 0)
        rc = 2;
    free(px);
    r->err_mrps = fp->fixed_err_base + fp->fixed_err_util * util * util + resid;
    r->err_dram_mb = fp->fixed_err_base;
    /* the DRAM's background energy follows time, not bytes: the pJ/byte of
     * the pilot carries it only at the pilot's bytes per second */
    r->err_energy_mj = r->err_mrps + dram_static_share;
    if (util > fp->fixed_max_util) {
        char why[200];
        snprintf(why, sizeof why,
                 "fixed-mem: the pilot's DRAM utilisation %.0f%% exceeds %.0f%%: queueing and row conflicts at "
                 "saturation are outside the range the calibration holds",
                 100.0 * util, 100.0 * fp->fixed_max_util);
        set_unreliable(r, why);
    }
    /* saturation shows in the latency as well: with few row hits the
     * LPDDR3 saturates far below its peak bandwidth (the furball stand-in:
     * 59% of peak, 37% row hits, 203 cycles mean latency) */
    double unloaded = fp->dram_latency + (1.0 - pilot_row_hit) * fp->row_miss_cycles;
    if (pilot_latency > fp->fixed_max_latency_ratio * unloaded) {
        char why[240];
        snprintf(why, sizeof why,
                 "fixed-mem: the pilot's mean memory latency %.0f cycles is %.1f times the unloaded %.0f: the "
                 "DRAM is saturated, where one fixed latency stands for a queue that changes with the load",
                 pilot_latency, pilot_latency / unloaded, unloaded);
        set_unreliable(r, why);
    }
    return rc;
}

/* The functional level's own error model (fidelity_params.h): a clear
 * bottleneck is predicted within func_err_base; as the runner-up bound
 * approaches a tie the units interfere and the estimate grows. */
static void functional_errors(const fid_func *f, fid_result *r)
{
    const fid_params *fp = fid_params_get();
    double tie = f->runner_up > 0.5 ? (f->runner_up - 0.5) / 0.5 : 0;
    double row_miss = f->dram_lines ? 1.0 - (double)f->row_hits / (double)f->dram_lines : 0;
    /* the DRAM queueing term is the crudest part: its share grows with the
     * utilisation and the row misses (hairball BVH2 diffuse: 143 cycles
     * measured against 88 modelled at 46% utilisation, 13% row hits) */
    r->err_mrps = fp->func_err_base + fp->func_err_tie * tie + fp->func_err_mem * f->dram_util * row_miss;
    r->err_dram_mb = fp->func_err_dram;
    r->err_energy_mj = fp->func_err_energy;
    if (f->runner_up >= fp->func_tie_flag) {
        char why[200];
        snprintf(why, sizeof why,
                 "functional: the %s bound and the next are within %.0f%% of a tie: units interfere, the "
                 "throughput model does not hold",
                 f->bound, 100.0 * (1.0 - f->runner_up));
        set_unreliable(r, why);
    }
    if (f->dram_util > fp->fixed_max_util) {
        char why[200];
        snprintf(why, sizeof why,
                 "functional: DRAM utilisation %.0f%% exceeds %.0f%%: the queueing model does not hold at saturation",
                 100.0 * f->dram_util, 100.0 * fp->fixed_max_util);
        set_unreliable(r, why);
    }
}

/* ---- independent pieces (kernel/fork_pool.h) ----------------------------
 * The frame's functional pass, each sample group and the functional level's
 * energy pilot depend on nothing but the job: they run as pieces, in worker
 * processes when job->jobs > 1, and hand back plain data (fid_func.bound
 * points to a string literal, shared after fork). The caller combines them
 * in piece order, so the figures do not depend on job->jobs. */

/* What one piece hands back. */
typedef struct fid_piece {
    model_fig m;                  /* the cycle model on the piece's pixels (not for the frame pass) */
    fid_func f;                   /* the functional pass on the same pixels (the frame's for the frame pass) */
    uint32_t pixels;              /* pixels of the piece; 0: an empty group, nothing run */
} fid_piece;

/* Which pieces: [the frame's functional pass], then `groups` disjoint sets
 * of row bands of the given period (period <= 1 with one group: the whole
 * frame). */
typedef struct piece_plan {
    const fid_job *job;
    bool frame_pass;
    uint32_t period, groups;
} piece_plan;

static int run_piece(void *user, int index, void *result, char *err, size_t errlen)
{
    const piece_plan *pl = user;
    const fid_job *job = pl->job;
    fid_piece *r = result;
    memset(r, 0, sizeof *r);
    if (pl->frame_pass && index == 0)
        return fid_functional_run(job, NULL, 0, &r->f, err, errlen) ? 2 : 0;
    uint32_t g = (uint32_t)index - (pl->frame_pass ? 1u : 0u), n = job->width * job->height;
    uint32_t *px = NULL;
    if ((pl->period > 1 || pl->groups > 1) && !(px = band_subset(job, pl->period, g, pl->groups, &n))) {
        snprintf(err, errlen, "out of memory");
        return 2;
    }
    r->pixels = n;
    int rc = 0;
    if (n > 0) {
        rc = run_model_series(job, job->cfg, px, px ? n : 0, &r->m, NULL, "group", g, err, errlen);
        if (rc == 0 && fid_functional_run(job, px, n, &r->f, err, errlen))
            rc = 2;
    }
    free(px);
    return rc;
}

/* Energy of a frame from a cycle-model sample and the functional counts of
 * sample and frame, unit by unit: static energy (DRAM's background power
 * included) scales with the time, DRAM's dynamic energy with DRAM bytes,
 * the TRVs' with box tests, the stacks' with pushes + pops. The IST's, the
 * caches' and the FIFOs' dynamic energy goes partly with the work (tests,
 * accesses) and partly with the misses (re-issue loops, fills, memory
 * traffic), and a sample run from cold caches has more misses per work
 * than the frame: with both parts >= 0, the frame's lies between the
 * sample's scaled by the work and scaled by the fills. The midpoint is
 * taken; *range_mj: half the gap, a bound on that error. (Scaling all
 * dynamic energy by the work put sampled's mJ/frame 14% high on interior
 * primary MBVH4 320x180, against a 9% estimate: its sample spent 67-97%
 * more IST, cache and FIFO energy per work than its frame. Before that,
 * DRAM's static energy was also in the DRAM term and taken off the
 * dynamic one, which hid part of it: 7% low on Fairy primary MBVH4.) */
static double energy_ratio(const model_fig *m, const fid_func *fs, const fid_func *ff, double frame_seconds,
                           double *range_mj)
{
    double work_s = (double)(fs->visits + fs->tri_tests), work_f = (double)(ff->visits + ff->tri_tests);
    double fills_s = (double)(fs->l1.fills + fs->l2.fills + fs->prim.fills);
    double fills_f = (double)(ff->l1.fills + ff->l2.fills + ff->prim.fills);
    double acc_s = (double)(fs->l1.accesses + fs->l2.accesses + fs->prim.accesses);
    double acc_f = (double)(ff->l1.accesses + ff->l2.accesses + ff->prim.accesses);
#define FID_RATIO(f, s) ((s) > 0 ? (f) / (s) : 0.0)
    double r_work = FID_RATIO(work_f, work_s), r_fill = fills_s > 0 ? FID_RATIO(fills_f, fills_s) : r_work;
    /* the units before DRAM (model_fig.unit_dyn_mj): the work-side ratio of each */
    const double r_unit[EU_DRAM] = {
        [EU_TRV] = FID_RATIO((double)ff->box_tests, (double)fs->box_tests),
        [EU_IST] = FID_RATIO((double)ff->tri_tests, (double)fs->tri_tests),
        [EU_STACK] = FID_RATIO((double)(ff->pushes + ff->pops), (double)(fs->pushes + fs->pops)),
        [EU_CACHE] = FID_RATIO(acc_f, acc_s),
        [EU_FIFO] = r_work,
    };
    const bool with_misses[EU_DRAM] = {[EU_IST] = true, [EU_CACHE] = true, [EU_FIFO] = true};
    double e = 0, range = 0;
    for (int u = 0; u < EU_DRAM; u++) {
        double r = r_unit[u] > 0 ? r_unit[u] : r_work;
        if (with_misses[u]) {
            e += m->unit_dyn_mj[u] * 0.5 * (r + r_fill);
            range += m->unit_dyn_mj[u] * 0.5 * fabs(r - r_fill);
        } else {
            e += m->unit_dyn_mj[u] * r;
        }
    }
    double dram_dyn = m->dram_mj - m->dram_static_mj;
    double sec_s = m->mrps > 0 ? m->rays / (m->mrps * 1e6) : 0;
    e += FID_RATIO((double)ff->dram_bytes, (double)fs->dram_bytes) * dram_dyn;
    e += sec_s > 0 ? m->static_mj * frame_seconds / sec_s : 0;
#undef FID_RATIO
    if (range_mj)
        *range_mj = range;
    return e;
}

int fid_lv_functional(const fid_job *job, fid_outcome *o, fid_func *ff, char *err, size_t errlen)
{
    const fid_params *fp = fid_params_get();
    fid_result *r = &o->res;
    r->level = FID_FUNCTIONAL;
    /* two independent pieces: the frame's functional pass and the energy
     * pilot (a small cycle-model run scaled by the functional counts) */
    piece_plan plan = {job, true, pilot_period(job, fp->pilot_fraction / 4), 1};
    fid_piece *pc = calloc(2, sizeof *pc);
    if (!pc) {
        snprintf(err, errlen, "out of memory");
        return 2;
    }
    int rc = ks_pool_run(2, job->jobs, sizeof *pc, run_piece, &plan, pc, err, errlen);
    if (rc) {
        free(pc);
        return rc;
    }
    *ff = pc[0].f;
    const model_fig m = pc[1].m;
    const fid_func fs = pc[1].f;
    const uint32_t pilot_pixels = pc[1].pixels;
    free(pc);
    fid_own *w = o->own;
    own_from_func(w, ff);
    w->cycles = (uint64_t)ff->cycles;
    w->dram_bytes = ff->dram_bytes;
    functional_errors(ff, r);
    /* the throughput model against the cycle model on the pilot's pixels:
     * how far it errs there is evidence of how far it errs on the frame,
     * which the terms above (fitted on the built-in scenes) cannot see
     * (hairball-real diffuse 320x180: the model's node L1 and primitive
     * cache hit 6% and 11% of the time, the functional order 25% and 42%;
     * MRPS 138% high against an estimate of 31%). Not a flag: a small
     * pilot starts cold, and its gap overstates the frame's (hairball
     * primary 96x54: 49% on the pilot, 1% on the frame). */
    double pilot_dev = m.mrps > 0 && fs.mrps > 0 ? fabs(fs.mrps / m.mrps - 1.0) : 0;
    r->err_mrps += pilot_dev;
    double sec = ff->cycles / (ff->clock_mhz * 1e6), erange = 0;
    w->energy_mj = energy_ratio(&m, &fs, ff, sec, &erange);
    /* the pilot's misses per work against the frame's (energy_ratio) */
    r->err_energy_mj += w->energy_mj > 0 ? erange / w->energy_mj : 0;
    /* the energy's static part follows the time: the MRPS error carries over */
    r->err_energy_mj += m.energy_mj > 0 ? r->err_mrps * m.static_mj / m.energy_mj : 0;
    set_headline(o, ff->clock_mhz);
    snprintf(r->detail, sizeof r->detail,
             "functional: %s-bound (TRV %.0f, IST %.0f, DRAM %.0f, latency %.0f cycles; runner-up %.0f%% of it); "
             "energy from a cycle-model pilot on %u pixels (MRPS there: functional %.3g, model %.3g)",
             ff->bound, ff->cyc_trv, ff->cyc_ist, ff->cyc_dram, ff->cyc_lat, 100.0 * ff->runner_up, pilot_pixels,
             fs.mrps, m.mrps);
    return 0;
}

/* The miss-wait scale at which the functional cycles of sample fs equal
 * target (bisection on a log scale; cycles grow with the scale). */
static double calibrate_miss_scale(const fid_job *job, fid_func *fs, double target)
{
    double lo = log(0.05), hi = log(20.0);
    for (int it = 0; it < 40; it++) {
        double mid = 0.5 * (lo + hi);
        fid_functional_retime(job, fs, exp(mid));
        if (fs->cycles < target)
            lo = mid;
        else
            hi = mid;
    }
    double k = exp(0.5 * (lo + hi));
    fid_functional_retime(job, fs, k);
    return k;
}

/* sampled: the cycle model on `groups` disjoint sets of row bands;
 * each group's figures scaled to the frame by the functional pass (ratio
 * estimator: model(sample) x functional(frame) / functional(sample)), the
 * groups' spread giving a Student-t 95% confidence interval. ff: the
 * functional pass of the frame (made here when ff->rays == 0). */
int fid_lv_sampled(const fid_job *job, double rate, fid_outcome *o, fid_func *ff, char *err, size_t errlen)
{
    const fid_params *fp = fid_params_get();
    fid_result *r = &o->res;
    r->level = FID_SAMPLED;
    int G = fp->sample_groups;
    uint32_t period = (uint32_t)llround((double)G / rate);
    if (period < (uint32_t)G)
        period = (uint32_t)G;
    double est[3][16] = {{0}}, sample_rays = 0, dev[2] = {0, 0}, energy_range = 0, raw_mrps_dev = 0;
    uint32_t min_pixels = UINT32_MAX;
    /* the pieces: [the frame's functional pass when not given], the groups */
    piece_plan plan = {job, ff->rays == 0, period, (uint32_t)G};
    int first = plan.frame_pass ? 1 : 0, npieces = first + G;
    fid_piece *pc = calloc((size_t)npieces, sizeof *pc);
    if (!pc) {
        snprintf(err, errlen, "out of memory");
        return 2;
    }
    int rc = ks_pool_run(npieces, job->jobs, sizeof *pc, run_piece, &plan, pc, err, errlen);
    if (rc) {
        free(pc);
        return rc;
    }
    if (plan.frame_pass)
        *ff = pc[0].f;
    for (int g = 0; g < G; g++) {
        const uint32_t n = pc[first + g].pixels;
        if (n < min_pixels)
            min_pixels = n;
        if (n == 0)
            continue;
        const model_fig m = pc[first + g].m;
        fid_func fs = pc[first + g].f;
        sample_rays += m.rays;
        /* MRPS: the misses' cost calibrated on the sample (the functional
         * model's miss wait scaled until its cycles for the sample equal
         * the cycle model's), then applied to the frame's counts. How far
         * that moves the frame's figure bounds how much the calibration's
         * extrapolation may err: all of it goes into the estimate (half
         * left 3 of 32 sampled points at 320x180 silently outside). */
        double raw_dev = fabs(fs.mrps / m.mrps - 1.0);
        double k = calibrate_miss_scale(job, &fs, m.cycles);
        fid_func fk = *ff;
        fid_functional_retime(job, &fk, k);
        est[0][g] = fk.mrps;
        dev[0] += (ff->mrps > 0 ? fabs(fk.mrps / ff->mrps - 1.0) : 0) / G;
        raw_mrps_dev += raw_dev / G;
        /* DRAM bytes and energy: ratio estimators (model on the sample x
         * functional frame / functional sample); the functional model's DRAM
         * error on the sample bounds the assumption that it errs alike */
        dev[1] += (m.dram_bytes > 0 ? fabs((double)fs.dram_bytes / m.dram_bytes - 1.0) : 0) / G;
        est[1][g] = fs.dram_bytes ? m.dram_bytes * (double)ff->dram_bytes / (double)fs.dram_bytes : 0;
        double sec = est[0][g] > 0 ? (double)ff->rays / (est[0][g] * 1e6) : 0;
        double erange = 0;
        est[2][g] = energy_ratio(&m, &fs, ff, sec, &erange);
        energy_range += erange / G;
    }
    free(pc);
    double mean[3], rel[3];
    for (int k = 0; k < 3; k++) {
        double s = 0, s2 = 0;
        for (int g = 0; g < G; g++)
            s += est[k][g];
        mean[k] = s / G;
        for (int g = 0; g < G; g++)
            s2 += (est[k][g] - mean[k]) * (est[k][g] - mean[k]);
        double sd = G > 1 ? sqrt(s2 / (G - 1)) : 0;
        /* half-width of the 95% CI of the mean, relative; a floor for the
         * ratio estimator's own bias (docs/fidelity.md) */
        rel[k] = mean[k] > 0 ? fp->sample_t95 * sd / sqrt((double)G) / mean[k] : 1.0;
    }
    double ci[3] = {rel[0], rel[1], rel[2]};
    /* plus the ratio estimator's bias bound, with a floor (fidelity_params.h),
     * and the frame's phase excess (functional.h): the frame's cycles are
     * the functional model's for the frame, which takes the busiest issue
     * unit over the whole frame; where the load moves between the TRVs and
     * the IST across the frame, in phases longer than the rays in flight
     * and the FIFOs smooth, each phase is bound by its own busiest unit and
     * the frame is slower. A sample's groups interleave rows from all over
     * the frame, so their calibration cannot see it. (Without it, 3 of the
     * 36 sampled points at 1280x720 were outside their estimates: hairball
     * primary BVH2 6.4% fast against 4.8%, Fairy primary MBVH4 3.1% against
     * 2.4%, forest primary MBVH4 2.0% against 1.5%.) */
    rel[0] += dev[0] + fp->sample_err_floor + ff->phase_excess;
    /* DRAM: the functional pass may err on the frame's capacity misses
     * more than on a sample's (mostly cold) ones, which the sample cannot
     * show: a fixed bias bound */
    rel[1] += dev[1] + fp->sample_err_floor + fp->sample_err_dram;
    /* energy: the static part follows the MRPS calibration, the DRAM part
     * the DRAM estimate; the units' dynamic part is bounded by the gap
     * between scaling it by the work and by the misses (energy_ratio) */
    rel[2] += dev[0] + ff->phase_excess + dev[1] + (mean[2] > 0 ? energy_range / mean[2] : 0) + fp->sample_err_floor;
    r->err_mrps = rel[0], r->err_dram_mb = rel[1], r->err_energy_mj = rel[2];
    fid_own *w = o->own;
    own_from_func(w, ff);
    w->is_sampled = true;
    w->samples = (uint64_t)G;
    w->sample_rays = (uint64_t)sample_rays;
    w->sample_rate = rate;
    w->rays = ff->rays;
    w->cycles = mean[0] > 0 ? (uint64_t)llround((double)ff->rays / (mean[0] * 1e6) * ff->clock_mhz * 1e6) : 0;
    w->dram_bytes = (uint64_t)llround(mean[1]);
    w->energy_mj = mean[2];
    set_headline(o, ff->clock_mhz);
    o->mrps = w->mrps = mean[0];
    snprintf(r->detail, sizeof r->detail,
             "sampled: the full model on %d groups of %.2f%% of the pixels (bands of %d rows, %.0f rays), scaled by "
             "the functional pass of the frame (ratio estimator)",
             G, 100.0 * rate / G, fp->band_rows, sample_rays);
    double bound = r->accuracy > 0 ? r->accuracy : fp->sample_max_err;
    if (min_pixels < 64 || r->err_mrps > bound || r->err_dram_mb > bound || r->err_energy_mj > bound) {
        char why[400];
        snprintf(why, sizeof why,
                 "sampled at %.2f%% of the pixels: error estimate (95%% CI MRPS %.1f%%, DRAM %.1f%%, mJ %.1f%%; "
                 "functional vs model on the sample before calibration %.1f%%, DRAM %.1f%%; the frame's phase "
                 "excess %.1f%%) exceeds the %.1f%% bound%s",
                 100.0 * rate, 100.0 * ci[0], 100.0 * ci[1], 100.0 * ci[2], 100.0 * raw_mrps_dev, 100.0 * dev[1],
                 100.0 * ff->phase_excess, 100.0 * bound, min_pixels < 64 ? "; a group has under 64 pixels" : "");
        set_unreliable(r, why);
    }
    return 0;
}

double fid_lv_worst(const fid_result *r)
{
    return fmax(r->err_mrps, fmax(r->err_dram_mb, r->err_energy_mj));
}

/* windowed: the full model on warmed-up windows only (windowed.h). The
 * error estimate of each figure has two parts. The random errors, each a
 * 95% half-width of an independent sample, add in quadrature: the windows'
 * interval (*sampling: the part more windows shrink), the start
 * correction's, and the lattice's (the frame's auxiliary figures; for MRPS
 * plus its ray count, added to it in full: both come from the same pixels).
 * The bias bounds add in full on top (*bias): the warm-up's (the windows'
 * fills into never-used cache ways: each may be a miss a warm cache would
 * not have made) and a floor. *other: the random part beside the interval. */
void fid_lv_windowed_errors(const fid_windowed *wd, double e[FID_WIN_FIGS], double sampling[FID_WIN_FIGS],
                            double other[FID_WIN_FIGS], double bias[FID_WIN_FIGS])
{
    const fid_params *fp = fid_params_get();
    for (int k = 0; k < FID_WIN_FIGS; k++) {
        double lattice = wd->lattice_err[k] + (k == FID_WIN_CYCLES ? wd->rays_err : 0);
        sampling[k] = wd->ci[k];
        other[k] = sqrt(wd->start_err[k] * wd->start_err[k] + lattice * lattice);
        bias[k] = wd->cold_share + fp->win_err_floor;
        e[k] = sqrt(sampling[k] * sampling[k] + other[k] * other[k]) + bias[k];
    }
}

/* The outcome of a windowed estimate: figures, errors, method, flag. */
void fid_lv_windowed_outcome(const fid_job *job, const fid_windowed *wd, fid_outcome *o)
{
    const fid_params *fp = fid_params_get();
    fid_result *r = &o->res;
    r->level = FID_WINDOWED;
    double e[FID_WIN_FIGS], ci[FID_WIN_FIGS], other[FID_WIN_FIGS], bias[FID_WIN_FIGS];
    fid_lv_windowed_errors(wd, e, ci, other, bias);
    r->err_mrps = e[FID_WIN_CYCLES];
    r->err_dram_mb = e[FID_WIN_DRAM];
    r->err_energy_mj = e[FID_WIN_ENERGY];
    fid_own *w = o->own;
    w->is_windowed = true;
    w->windows = wd->windows, w->window_pixels = wd->window_pixels, w->warm_pixels = wd->warm_pixels;
    w->model_pixels = (uint64_t)wd->model_pixels, w->lattice_pixels = (uint64_t)wd->lattice_pixels;
    w->cold_share = wd->cold_share;
    w->paired_windows = wd->resid && wd->windows <= FID_PAIRED_MAX_WINDOWS ? wd->windows : 0;
    w->t95 = wd->t95;
    for (int k = 0; k < FID_WIN_HEADLINE; k++) {
        /* the rays' lattice error is left out: the same pixels give every
         * machine the same rays, so it cancels in a change */
        double lat = wd->lattice_err[k];
        w->other_err[k] = 100.0 * sqrt(wd->start_err[k] * wd->start_err[k] + lat * lat);
        w->bias_err[k] = 100.0 * bias[k];
        for (uint64_t q = 0; q < w->paired_windows; q++)
            w->resid[k][q] = wd->resid[(size_t)k * wd->windows + q];
    }
    w->primaries = (uint64_t)wd->primaries;
    w->rays = (uint64_t)llround(wd->rays);
    w->bounces = w->rays - w->primaries;
    w->cycles = (uint64_t)llround(wd->cycles);
    w->dram_bytes = (uint64_t)llround(wd->dram_bytes);
    w->energy_mj = wd->energy_mj;
    set_headline(o, rtcfg_real(job->cfg, "machine.clock_mhz"));
    /* Table 1 per unit: each power is its dynamic energy over the frame's
     * time plus its leakage (exact: a property of the machine), DRAM's
     * background energy estimated like the dynamic; its error: the energy
     * estimate's plus the time's, on the part that is estimated */
    w->has_units = wd->has_units;
    double sec = wd->cycles / (rtcfg_real(job->cfg, "machine.clock_mhz") * 1e6);
    for (int u = 0; u < EU_COUNT && wd->has_units && sec > 0; u++) {
        double dyn = wd->unit_mj[u], stat = u == EU_DRAM ? wd->unit_mj[EU_COUNT] : wd->leak_mw[u] * sec;
        double est_mw = (dyn * (e[FID_WIN_UNIT0 + u] + e[FID_WIN_CYCLES]) +
                         (u == EU_DRAM ? stat * (e[FID_WIN_DRAM_STATIC] + e[FID_WIN_CYCLES]) : 0)) / sec;
        w->unit_dyn_mj[u] = dyn, w->unit_static_mj[u] = stat, w->unit_mj[u] = dyn + stat;
        w->unit_mw[u] = (dyn + stat) / sec;   /* mJ / s = mW */
        w->unit_mm2[u] = wd->area_mm2[u];
        w->unit_mw_err[u] = w->unit_mw[u] > 0 ? 100.0 * est_mw / w->unit_mw[u] : 0;
    }
    double npix = (double)job->width * job->height;
    snprintf(r->detail, sizeof r->detail,
             "windowed: the full model on %u windows of %u pixels, each after %u warm-up pixels (%.1f%% of the "
             "pixels through the model), scaled by the traversal work and functional DRAM lines of 1 pixel in %d; "
             "95%% interval of the "
             "windows MRPS %.1f%%, DRAM %.1f%%, mJ %.1f%%; cold fills %.1f%%",
             wd->windows, wd->window_pixels, wd->warm_pixels, 100.0 * wd->model_pixels / npix, fp->win_lattice,
             100.0 * ci[0], 100.0 * ci[1], 100.0 * ci[2], 100.0 * wd->cold_share);
    r->unreliable = 0, r->reason[0] = 0;
    double bound = r->accuracy > 0 ? r->accuracy : fp->sample_max_err;
    if (wd->too_small) {
        set_unreliable(r, "windowed: the frame is too small for the windows (they would overlap, or be shorter "
                          "than win_min_pixels)");
    } else if (wd->cold_share > fp->win_max_cold) {
        char why[400];
        snprintf(why, sizeof why,
                 "windowed: the warm-ups are too short for this frame: %.1f%% of the windows' node L2 and primitive "
                 "cache fills went into never-used ways (at most %.0f%%); each may be a miss a warm cache would not "
                 "have made",
                 100.0 * wd->cold_share, 100.0 * fp->win_max_cold);
        set_unreliable(r, why);
    } else if (r->err_mrps > bound || r->err_dram_mb > bound || r->err_energy_mj > bound) {
        char why[400];
        snprintf(why, sizeof why, "windowed: error estimate exceeds the %.1f%% bound (the windows' 95%% interval "
                                  "MRPS %.1f%%, DRAM %.1f%%, mJ %.1f%%)",
                 100.0 * bound, 100.0 * ci[0], 100.0 * ci[1], 100.0 * ci[2]);
        set_unreliable(r, why);
    }
}

static int run_windowed(const fid_job *job, double rate, uint32_t windows, fid_outcome *o, char *err, size_t errlen)
{
    fid_windowed wd = {0};
    int rc = fid_windowed_run(job, rate, windows, &wd, err, errlen);
    if (rc == 0)
        fid_lv_windowed_outcome(job, &wd, o);
    fid_windowed_free(&wd);
    return rc;
}

int fid_lv_full(const fid_job *job, fid_outcome *o, char *err, size_t errlen)
{
    model_fig f;
    o->res.level = FID_FULL;
    o->res.err_mrps = o->res.err_dram_mb = o->res.err_energy_mj = 0;
    int rc = run_model(job, job->cfg, NULL, 0, &f, &o->top, err, errlen);
    o->cycles = f.cycles, o->rays = f.rays, o->mrps = f.mrps, o->dram_bytes = f.dram_bytes, o->energy_mj = f.energy_mj;
    return rc;
}

/* An empty outcome with its own figures' storage (any storage it had freed
 * first): for one level's run, and for each of --accuracy's trials. 0, or
 * -1 with a message when out of memory. */
int fid_lv_fresh_trial(fid_outcome *t, double acc, char *err, size_t errlen)
{
    free(t->own);
    memset(t, 0, sizeof *t);
    if (!(t->own = calloc(1, sizeof *t->own))) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    t->res.accuracy = acc;
    return 0;
}

int fid_run(const fid_job *job, fid_level level, double accuracy, fid_outcome *o, char *err, size_t errlen)
{
    memset(o, 0, sizeof *o);
    int rc;
    if (accuracy > 0) {
        rc = fid_accuracy_run(job, accuracy, o, err, errlen);
        o->res.accuracy = accuracy;
    } else {
        if (fid_lv_fresh_trial(o, 0, err, errlen))
            return 2;
        fid_func ff;
        memset(&ff, 0, sizeof ff);
        switch (level) {
        case FID_FIXED_MEM: rc = run_fixed_mem(job, o, err, errlen); break;
        case FID_FUNCTIONAL: rc = fid_lv_functional(job, o, &ff, err, errlen); break;
        case FID_WINDOWED: rc = run_windowed(job, job->sample_rate, job->windows, o, err, errlen); break;
        case FID_SAMPLED:
            rc = fid_lv_sampled(job, job->sample_rate > 0 ? job->sample_rate : fid_params_get()->sample_rate, o, &ff,
                             err, errlen);
            break;
        default: rc = fid_lv_full(job, o, err, errlen); break;
        }
    }
    if (rc == 0 || o->top) {
        if (o->top) {
            ks_stats *st = accel_top_stats(o->top);
            model_fig f;
            if (get_fig(o->top, &f, err, errlen))
                return 2;
            o->cycles = f.cycles, o->rays = f.rays, o->mrps = f.mrps, o->dram_bytes = f.dram_bytes,
            o->energy_mj = f.energy_mj;
            if (fid_register_stats(&o->res, st)) {
                snprintf(err, errlen, "fidelity statistics: %s", ks_stats_error(st));
                return 2;
            }
        } else if (o->own && own_stats(o)) {
            snprintf(err, errlen, "fidelity statistics: %s", o->stats ? ks_stats_error(o->stats) : "out of memory");
            return 2;
        }
    }
    return rc;
}

ks_stats *fid_outcome_stats(fid_outcome *o) { return o->top ? accel_top_stats(o->top) : o->stats; }

void fid_outcome_print(fid_outcome *o, FILE *out)
{
    if (o->top) {
        accel_top_print_summary(o->top, out);
        return;
    }
    fid_own *w = o->own;
    if (!w)
        return;
    fprintf(out, "cycles      %llu (estimated)\n", (unsigned long long)w->cycles);
    fprintf(out, "rays        %llu (%llu primary, %llu bounce)\n", (unsigned long long)w->rays,
            (unsigned long long)w->primaries, (unsigned long long)w->bounces);
    fprintf(out, "MRPS        %.2f (estimated)\n", w->mrps);
    if (w->has_func) {
        fprintf(out, "bounds      trv %.0f, ist %.0f, dram %.0f, latency %.0f cycles: %s-bound\n", w->cyc_trv,
                w->cyc_ist, w->cyc_dram, w->cyc_lat, w->bound ? w->bound : "?");
        fprintf(out, "caches      node L1 %.2f%% hits, node L2 %.2f%%, prim %.2f%%; DRAM rows %.1f%% hits (functional)\n",
                100 * w->l1_hit, 100 * w->l2_hit, 100 * w->prim_hit, 100 * w->row_hit);
    }
    fprintf(out, "DRAM        %.2f MB, %.2f GB/s (estimated)\n", (double)w->dram_bytes / 1e6, w->dram_gbs);
    fprintf(out, "energy      %.4g mJ/frame (estimated)\n", w->energy_mj);
}

void fid_outcome_free(fid_outcome *o)
{
    accel_top_destroy(o->top);
    if (o->stats)
        ks_stats_destroy(o->stats);
    free(o->own);
    memset(o, 0, sizeof *o);
}
