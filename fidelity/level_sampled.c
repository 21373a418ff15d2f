/* level_sampled.c — sampled (docs/fidelity.md): the cycle model on
 * interleaved groups of row bands, each scaled to the frame by the
 * functional pass (ratio estimators; the misses' cost calibrated on each
 * group), the groups' spread giving the interval; its error estimate, flag;
 * for --accuracy, the groups first and the frame's pass only when their own
 * prediction says it may pay. */
#include "fidelity/levels.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "fidelity/fidelity_params.h"
#include "fidelity/functional.h"
#include "kernel/fork_pool.h"

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

/* What the groups say once scaled to the frame by a functional pass. */
typedef struct sampled_est {
    double mean[3], rel[3];       /* MRPS, DRAM bytes, mJ: the groups' mean, its 95% half-width (relative) */
    double dev[2];                /* how far the MRPS calibration moves the frame; functional vs model DRAM */
    double energy_range, raw_mrps_dev, sample_rays;
    uint32_t min_pixels;
} sampled_est;

/* Each group's figures scaled to the frame by ff (ratio estimators: model(sample)
 * x functional(frame) / functional(sample)), their mean and spread. */
static void sampled_estimate(const fid_job *job, int G, const fid_piece *groups, const fid_func *ff, sampled_est *e)
{
    const fid_params *fp = fid_params_get();
    double est[3][16] = {{0}};
    memset(e, 0, sizeof *e);
    e->min_pixels = UINT32_MAX;
    for (int g = 0; g < G; g++) {
        const uint32_t n = groups[g].pixels;
        if (n < e->min_pixels)
            e->min_pixels = n;
        if (n == 0)
            continue;
        const model_fig m = groups[g].m;
        fid_func fs = groups[g].f;
        e->sample_rays += m.rays;
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
        e->dev[0] += (ff->mrps > 0 ? fabs(fk.mrps / ff->mrps - 1.0) : 0) / G;
        e->raw_mrps_dev += raw_dev / G;
        /* DRAM bytes and energy: ratio estimators (model on the sample x
         * functional frame / functional sample); the functional model's DRAM
         * error on the sample bounds the assumption that it errs alike */
        e->dev[1] += (m.dram_bytes > 0 ? fabs((double)fs.dram_bytes / m.dram_bytes - 1.0) : 0) / G;
        est[1][g] = fs.dram_bytes ? m.dram_bytes * (double)ff->dram_bytes / (double)fs.dram_bytes : 0;
        double sec = est[0][g] > 0 ? (double)ff->rays / (est[0][g] * 1e6) : 0;
        double erange = 0;
        est[2][g] = fid_energy_ratio(&m, &fs, ff, sec, &erange);
        e->energy_range += erange / G;
    }
    for (int k = 0; k < 3; k++) {
        double s = 0, s2 = 0;
        for (int g = 0; g < G; g++)
            s += est[k][g];
        e->mean[k] = s / G;
        for (int g = 0; g < G; g++)
            s2 += (est[k][g] - e->mean[k]) * (est[k][g] - e->mean[k]);
        double sd = G > 1 ? sqrt(s2 / (G - 1)) : 0;
        /* half-width of the 95% CI of the mean, relative; a floor for the
         * ratio estimator's own bias (docs/fidelity.md) */
        e->rel[k] = e->mean[k] > 0 ? fp->sample_t95 * sd / sqrt((double)G) / e->mean[k] : 1.0;
    }
}

/* The error estimate of each figure (MRPS, DRAM bytes, mJ) from e: its
 * interval plus the ratio estimator's bias bound, with a floor
 * (fidelity_params.h), and the frame's phase excess (functional.h): the
 * frame's cycles are the functional model's for the frame, which takes the
 * busiest issue unit over the whole frame; where the load moves between the
 * TRVs and the IST across the frame, in phases longer than the rays in
 * flight and the FIFOs smooth, each phase is bound by its own busiest unit
 * and the frame is slower. A sample's groups interleave rows from all over
 * the frame, so their calibration cannot see it. (Without it, 3 of the 36
 * sampled points at 1280x720 were outside their estimates: hairball primary
 * BVH2 6.4% fast against 4.8%, Fairy primary MBVH4 3.1% against 2.4%,
 * forest primary MBVH4 2.0% against 1.5%.) */
static void sampled_errors(const sampled_est *e, double phase_excess, double err[3])
{
    /* (the sums grouped as they always were: the same bits) */
    const fid_params *fp = fid_params_get();
    err[0] = e->rel[0] + (e->dev[0] + fp->sample_err_floor + phase_excess);
    /* DRAM: the functional pass may err on the frame's capacity misses
     * more than on a sample's (mostly cold) ones, which the sample cannot
     * show: a fixed bias bound */
    err[1] = e->rel[1] + (e->dev[1] + fp->sample_err_floor + fp->sample_err_dram);
    /* energy: the static part follows the MRPS calibration, the DRAM part
     * the DRAM estimate; the units' dynamic part is bounded by the gap
     * between scaling it by the work and by the misses (fid_energy_ratio) */
    err[2] = e->rel[2] + (e->dev[0] + phase_excess + e->dev[1] + (e->mean[2] > 0 ? e->energy_range / e->mean[2] : 0) +
                          fp->sample_err_floor);
}

/* sampled: the cycle model on `groups` disjoint sets of row bands;
 * each group's figures scaled to the frame by the functional pass, the
 * groups' spread giving a Student-t 95% confidence interval. ff: the
 * functional pass of the frame (made here when ff->rays == 0). give_up
 * (> 0, --accuracy): when ff is not given, the groups run first, and when
 * their estimate with their own functional passes standing in for the
 * frame's is over give_up, the frame's pass is not run: the result keeps
 * that estimate, flagged. */
static int sampled_run(const fid_job *job, double rate, double give_up, fid_outcome *o, fid_func *ff, bool *gave_up,
                       char *err, size_t errlen)
{
    const fid_params *fp = fid_params_get();
    fid_result *r = &o->res;
    r->level = FID_SAMPLED;
    int G = fp->sample_groups;
    uint32_t period = (uint32_t)llround((double)G / rate);
    if (period < (uint32_t)G)
        period = (uint32_t)G;
    const bool groups_first = ff->rays == 0 && give_up > 0;
    /* the pieces: [the frame's functional pass when not given], the groups */
    piece_plan plan = {job, ff->rays == 0 && !groups_first, period, (uint32_t)G};
    int first = plan.frame_pass ? 1 : 0, npieces = first + G;
    fid_piece *pc = calloc((size_t)npieces, sizeof *pc);
    if (!pc) {
        snprintf(err, errlen, "out of memory");
        return 2;
    }
    int rc = ks_pool_run(npieces, job->jobs, sizeof *pc, fid_run_piece, &plan, pc, err, errlen);
    if (rc) {
        free(pc);
        return rc;
    }
    if (plan.frame_pass)
        *ff = pc[0].f;
    const fid_piece *groups = pc + first;
    sampled_est e;
    if (groups_first) {
        /* the groups' functional passes together, a sample of the frame's
         * rows, stand in for the frame's: every term of the estimate but
         * the frame's phase excess (>= 0), which needs the frame's pass */
        fid_func stand;
        memset(&stand, 0, sizeof stand);
        for (int g = 0; g < G; g++)
            fid_functional_add(&stand, &groups[g].f);
        fid_functional_retime(job, &stand, 1.0);
        sampled_estimate(job, G, groups, &stand, &e);
        double pred[3];
        sampled_errors(&e, 0, pred);
        double worst = fmax(pred[0], fmax(pred[1], pred[2]));
        if (worst > give_up) {
            r->err_mrps = pred[0], r->err_dram_mb = pred[1], r->err_energy_mj = pred[2];
            char why[300];
            snprintf(why, sizeof why,
                     "sampled at %.2f%% of the pixels: its groups predict an error of %.1f%% (their own functional "
                     "passes standing in for the frame's), over %.1f%%: the frame's functional pass was not run",
                     100.0 * rate, 100.0 * worst, 100.0 * give_up);
            fid_set_unreliable(r, why);
            *gave_up = true;
            free(pc);
            return 0;
        }
        if (fid_functional_run(job, NULL, 0, ff, err, errlen)) {
            free(pc);
            return 2;
        }
    }
    sampled_estimate(job, G, groups, ff, &e);
    const double sample_rays = e.sample_rays, *mean = e.mean;
    free(pc);
    double rel[3];
    sampled_errors(&e, ff->phase_excess, rel);
    r->err_mrps = rel[0], r->err_dram_mb = rel[1], r->err_energy_mj = rel[2];
    fid_own *w = o->own;
    fid_own_from_func(w, ff);
    w->is_sampled = true;
    w->samples = (uint64_t)G;
    w->sample_rays = (uint64_t)sample_rays;
    w->sample_rate = rate;
    w->rays = ff->rays;
    w->cycles = mean[0] > 0 ? (uint64_t)llround((double)ff->rays / (mean[0] * 1e6) * ff->clock_mhz * 1e6) : 0;
    w->dram_bytes = (uint64_t)llround(mean[1]);
    w->energy_mj = mean[2];
    fid_set_headline(o, ff->clock_mhz);
    o->mrps = w->mrps = mean[0];
    snprintf(r->detail, sizeof r->detail,
             "sampled: the full model on %d groups of %.2f%% of the pixels (bands of %d rows, %.0f rays), scaled by "
             "the functional pass of the frame (ratio estimator)",
             G, 100.0 * rate / G, fp->band_rows, sample_rays);
    double bound = r->accuracy > 0 ? r->accuracy : fp->sample_max_err;
    if (e.min_pixels < 64 || r->err_mrps > bound || r->err_dram_mb > bound || r->err_energy_mj > bound) {
        char why[400];
        snprintf(why, sizeof why,
                 "sampled at %.2f%% of the pixels: error estimate (95%% CI MRPS %.1f%%, DRAM %.1f%%, mJ %.1f%%; "
                 "functional vs model on the sample before calibration %.1f%%, DRAM %.1f%%; the frame's phase "
                 "excess %.1f%%) exceeds the %.1f%% bound%s",
                 100.0 * rate, 100.0 * e.rel[0], 100.0 * e.rel[1], 100.0 * e.rel[2], 100.0 * e.raw_mrps_dev, 100.0 * e.dev[1],
                 100.0 * ff->phase_excess, 100.0 * bound, e.min_pixels < 64 ? "; a group has under 64 pixels" : "");
        fid_set_unreliable(r, why);
    }
    return 0;
}

int fid_lv_sampled(const fid_job *job, double rate, fid_outcome *o, fid_func *ff, char *err, size_t errlen)
{
    bool gave_up = false;
    return sampled_run(job, rate, 0, o, ff, &gave_up, err, errlen);
}

int fid_lv_sampled_or_give_up(const fid_job *job, double rate, double give_up, fid_outcome *o, fid_func *ff,
                              bool *gave_up, char *err, size_t errlen)
{
    *gave_up = false;
    return sampled_run(job, rate, give_up, o, ff, gave_up, err, errlen);
}
