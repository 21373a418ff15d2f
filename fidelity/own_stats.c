/* own_stats.c — the statistics registry of a level whose figures are
 * estimated, not run (functional, sampled, windowed; fid_own in levels.h):
 * the frame's figures under the full model's names, so readers of a full
 * run's JSON read them too, and each level's own figures beside them. */
#include "fidelity/levels.h"

#include <stdio.h>

#include "model/energy/energy.h"

/* n statistics PREFIX.FIG.I (ratio), I = 0..n-1, over v[I]; desc_fmt takes
 * I and what (the figure in words). */
static int residual_list(ks_stats *st, const char *prefix, const char *fig, uint64_t n, double *v,
                         const char *desc_fmt, const char *what)
{
    int rc = 0;
    for (uint64_t i = 0; i < n; i++) {
        char key[96], desc[240];
        snprintf(key, sizeof key, "%s.%s.%llu", prefix, fig, (unsigned long long)i);
        snprintf(desc, sizeof desc, desc_fmt, (unsigned long long)i, what);
        rc |= ks_stat_real_ref(st, key, "ratio", desc, &v[i]);
    }
    return rc;
}

int fid_own_stats(fid_outcome *o)
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
        rc |= ks_stat_counter_ref(st, "window.lattice_groups", "groups",
                                  "interleaved groups of the lattice's pixels whose residuals follow (0: none)",
                                  &w->lattice_groups);
        rc |= ks_stat_counter_ref(st, "window.start_windows", "windows",
                                  "windows with a warm-up: their start excesses make the start correction",
                                  &w->start_windows);
        for (int k = 0; k < FID_WIN_HEADLINE; k++) {
            char key[96], desc[200];
            snprintf(key, sizeof key, "window.other_err.%s", fig[k]);
            snprintf(desc, sizeof desc, "%s: the lattice's and the start correction's 95%% errors in quadrature",
                     fig[k]);
            rc |= ks_stat_real_ref(st, key, "%", desc, &w->other_err[k]);
            snprintf(key, sizeof key, "window.bias_err.%s", fig[k]);
            snprintf(desc, sizeof desc, "%s: the bias bounds (cold fills + floor)", fig[k]);
            rc |= ks_stat_real_ref(st, key, "%", desc, &w->bias_err[k]);
            const char *what = k == FID_WIN_CYCLES ? "the cycles" : fig[k];
            rc |= residual_list(st, "window.resid", fig[k], w->paired_windows, w->resid[k],
                                "window %llu (image order): its residual of %s as it enters the interval, "
                                "relative to the frame's figure", what);
            rc |= residual_list(st, "window.start_resid", fig[k], w->paired_windows, w->start_resid[k],
                                "window %llu (image order): its start excess of %s less the mean, relative to the "
                                "frame's figure, scaled so the squares sum to the start correction's variance", what);
            rc |= residual_list(st, "window.lat_resid", fig[k], w->lattice_groups, w->lat_resid[k],
                                "lattice group %llu: its estimate of %s less the groups' mean, relative to the "
                                "frame's figure, scaled so the squares sum to the lattice's variance", what);
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

void fid_own_from_func(fid_own *w, const fid_func *f)
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

void fid_set_headline(fid_outcome *o, double clock_mhz)
{
    fid_own *w = o->own;
    double sec = (double)w->cycles / (clock_mhz * 1e6);
    w->mrps = sec > 0 ? (double)w->rays / sec / 1e6 : 0;
    w->dram_gbs = sec > 0 ? (double)w->dram_bytes / sec / 1e9 : 0;
    o->cycles = (double)w->cycles, o->rays = (double)w->rays, o->mrps = w->mrps;
    o->dram_bytes = (double)w->dram_bytes, o->energy_mj = w->energy_mj;
}
