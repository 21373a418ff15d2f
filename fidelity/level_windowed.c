/* level_windowed.c — windowed's outcome (docs/fidelity.md): from the windows
 * windowed.c ran, the frame's figures, their error estimates (random parts
 * in quadrature, bias bounds on top), the residuals a paired estimate needs,
 * Table 1 per unit, and the flags. */
#include "fidelity/levels.h"

#include <math.h>
#include <stdio.h>

#include "fidelity/fidelity_params.h"
#include "fidelity/windowed.h"

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
    w->lattice_groups = wd->lat_resid && w->paired_windows ? FID_LAT_GROUPS : 0;
    w->start_windows = wd->start_windows;
    for (int k = 0; k < FID_WIN_HEADLINE; k++) {
        /* the rays' lattice error is left out: the same pixels give every
         * machine the same rays, so it cancels in a change */
        double lat = wd->lattice_err[k];
        w->other_err[k] = 100.0 * sqrt(wd->start_err[k] * wd->start_err[k] + lat * lat);
        w->bias_err[k] = 100.0 * bias[k];
        for (uint64_t q = 0; q < w->paired_windows; q++) {
            w->resid[k][q] = wd->resid[(size_t)k * wd->windows + q];
            w->start_resid[k][q] = wd->start_resid ? wd->start_resid[(size_t)k * wd->windows + q] : 0;
        }
        for (int g = 0; g < FID_LAT_GROUPS; g++)
            w->lat_resid[k][g] = wd->lat_resid ? wd->lat_resid[(size_t)k * FID_LAT_GROUPS + g] : 0;
    }
    w->primaries = (uint64_t)wd->primaries;
    w->rays = (uint64_t)llround(wd->rays);
    w->bounces = w->rays - w->primaries;
    w->cycles = (uint64_t)llround(wd->cycles);
    w->dram_bytes = (uint64_t)llround(wd->dram_bytes);
    w->energy_mj = wd->energy_mj;
    fid_set_headline(o, rtcfg_real(job->cfg, "machine.clock_mhz"));
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
        fid_set_unreliable(r, "windowed: the frame is too small for the windows (they would overlap, or be shorter "
                              "than win_min_pixels)");
    } else if (wd->cold_share > fp->win_max_cold) {
        char why[400];
        snprintf(why, sizeof why,
                 "windowed: the warm-ups are too short for this frame: %.1f%% of the windows' node L2 and primitive "
                 "cache fills went into never-used ways (at most %.0f%%); each may be a miss a warm cache would not "
                 "have made",
                 100.0 * wd->cold_share, 100.0 * fp->win_max_cold);
        fid_set_unreliable(r, why);
    } else if (r->err_mrps > bound || r->err_dram_mb > bound || r->err_energy_mj > bound) {
        char why[400];
        snprintf(why, sizeof why, "windowed: error estimate exceeds the %.1f%% bound (the windows' 95%% interval "
                                  "MRPS %.1f%%, DRAM %.1f%%, mJ %.1f%%)",
                 100.0 * bound, 100.0 * ci[0], 100.0 * ci[1], 100.0 * ci[2]);
        fid_set_unreliable(r, why);
    }
}

int fid_lv_windowed(const fid_job *job, double rate, uint32_t windows, fid_outcome *o, char *err, size_t errlen)
{
    fid_windowed wd = {0};
    int rc = fid_windowed_run(job, rate, windows, &wd, err, errlen);
    if (rc == 0)
        fid_lv_windowed_outcome(job, &wd, o);
    fid_windowed_free(&wd);
    return rc;
}
