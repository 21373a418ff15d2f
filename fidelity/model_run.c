/* model_run.c — the cycle model on part or all of a frame, as the levels run
 * it (levels.h): interleaved row bands as pixel subsets, a run on a subset
 * (subset.h) with its --series rows, the figures the levels read from it
 * (the model's typed figures, accel_top.h), and the full level itself. */
#include "fidelity/levels.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fidelity/fidelity_params.h"
#include "fidelity/subset.h"
#include "model/energy/energy.h"

/* ---- pixel subsets: interleaved row bands ------------------------------- */

/* Pixels of group g of `groups` interleaved sets of bands (fp->band_rows rows
 * each, the full width), each set taking one band in `period`, in scanline
 * order. Whole rows keep the frame's order of rays within a row, and so its
 * cache locality (tiles spread over a row lose it: docs/fidelity.md). */
uint32_t *fid_band_subset(const fid_job *job, uint32_t period, uint32_t group, uint32_t groups, uint32_t *n)
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

/* Bands of a pilot on about `fraction` of the pixels, and no fewer than
 * pilot_min_pixels of them: the period, 1 for the whole frame. */
uint32_t fid_pilot_period(const fid_job *job, double fraction)
{
    const fid_params *fp = fid_params_get();
    double pixels = (double)job->width * job->height;
    if (pixels * fraction < fp->pilot_min_pixels)
        fraction = fp->pilot_min_pixels / pixels;
    if (fraction >= 0.5)
        return 1;
    return (uint32_t)llround(1.0 / fraction);
}

/* ---- running the cycle model on a pixel subset (subset.h) -------------- */

/* The figures of a cycle-model run, from the model's typed figures
 * (accel_top_figures). The energy figures are set when the run has an
 * energy model, the row-hit rate when it has the LPDDR3 model; the rest
 * are 0 without them. */
void fid_get_fig(const accel_top *t, model_fig *f)
{
    accel_figures a;
    accel_top_figures(t, &a);
    memset(f, 0, sizeof *f);
    f->cycles = (double)a.cycles;
    f->rays = (double)a.rays;
    f->mrps = a.mrps;
    f->dram_bytes = (double)a.dram_bytes;
    f->dram_gbs = a.dram_gbs;
    if (a.energy) {
        f->energy_mj = a.energy_mj;
        for (int u = 0; u < EU_COUNT; u++)   /* in energy.h's order, as the sum always was */
            f->static_mj += a.unit_static_mj[u];
        for (int u = 0; u < EU_DRAM; u++)
            f->unit_dyn_mj[u] = a.unit_dynamic_mj[u];
        f->dram_mj = a.unit_mj[EU_DRAM];
        f->dram_static_mj = a.unit_static_mj[EU_DRAM];
    }
    /* both memories count requests and their latencies */
    f->mem_requests = (double)a.mem_requests;
    f->mem_latency = f->mem_requests > 0 ? (double)a.mem_latency_sum / f->mem_requests : 0;
    if (a.lpddr3)
        f->row_hit = a.row_hit_rate;
}

/* Runs the cycle model with cfg on the pixels map[0..n) (map NULL: the
 * whole frame). *keep: the top is handed back (else destroyed). tag: the
 * run's figures make the result, so with --series it writes its rows
 * (fid_subset_open_series; NULL: it does not). */
int fid_run_model_series(const fid_job *job, const rtcfg *cfg, const uint32_t *map, uint32_t n, model_fig *fig,
                         accel_top **keep, const char *tag, uint32_t piece, char *err, size_t errlen)
{
    fid_subset sub;
    if (fid_subset_open_series(&sub, job, cfg, map, n, tag, piece, tag, err, errlen))
        return 2;
    int rc = accel_top_run(sub.top, map ? NULL : job->progress, job->progress_user, err, errlen) ? 1 : 0;
    fid_get_fig(sub.top, fig);
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

int fid_run_model(const fid_job *job, const rtcfg *cfg, const uint32_t *map, uint32_t n, model_fig *fig,
                  accel_top **keep, char *err, size_t errlen)
{
    return fid_run_model_series(job, cfg, map, n, fig, keep, NULL, 0, err, errlen);
}

int fid_lv_full(const fid_job *job, fid_outcome *o, char *err, size_t errlen)
{
    model_fig f;
    o->res.level = FID_FULL;
    o->res.err_mrps = o->res.err_dram_mb = o->res.err_energy_mj = 0;
    int rc = fid_run_model(job, job->cfg, NULL, 0, &f, &o->top, err, errlen);
    o->cycles = f.cycles, o->rays = f.rays, o->mrps = f.mrps, o->dram_bytes = f.dram_bytes, o->energy_mj = f.energy_mj;
    return rc;
}
