/* levels.h — inside fidelity/: what the files of the levels share. Not for
 * use outside fidelity/.
 *
 * Each level's run, as fid_run (fidelity.c) and the automatic choice
 * (accuracy.c) call it: each fills an outcome made by fid_lv_fresh_trial()
 * and returns 0, or non-zero with err set, as fid_run (fidelity.h). Then
 * the parts the level files (level_*.c) share: the cycle model on a pixel
 * subset and its figures (model_run.c: from the model's typed figures,
 * accel_top_figures in model/accel_top.h, not from statistics looked up by
 * name), the registry of estimated figures
 * (own_stats.c), the independent pieces and the energy ratio estimator
 * (level_functional.c). */
#ifndef RTSIM_FIDELITY_LEVELS_H
#define RTSIM_FIDELITY_LEVELS_H

#include <stdbool.h>
#include <stdint.h>

#include "fidelity/fidelity.h"
#include "fidelity/functional.h"
#include "fidelity/windowed.h"
#include "model/energy/energy.h"

/* fixed-mem (level_fixed_mem.c) */
int fid_lv_fixed_mem(const fid_job *job, fid_outcome *o, char *err, size_t errlen);
/* functional: the frame's functional pass into *ff (kept for sampled) */
int fid_lv_functional(const fid_job *job, fid_outcome *o, fid_func *ff, char *err, size_t errlen);
/* sampled at `rate`; reuses *ff when it holds the frame's pass */
int fid_lv_sampled(const fid_job *job, double rate, fid_outcome *o, fid_func *ff, char *err, size_t errlen);
/* the same for --accuracy: without *ff, the groups first; when they predict
 * an error over give_up, the frame's pass is not run, *gave_up is set and
 * the result is that prediction, flagged (level_sampled.c) */
int fid_lv_sampled_or_give_up(const fid_job *job, double rate, double give_up, fid_outcome *o, fid_func *ff,
                              bool *gave_up, char *err, size_t errlen);
/* the full model (model_run.c) */
int fid_lv_full(const fid_job *job, fid_outcome *o, char *err, size_t errlen);
/* windowed at `rate` with `windows` windows (0: the defaults) */
int fid_lv_windowed(const fid_job *job, double rate, uint32_t windows, fid_outcome *o, char *err, size_t errlen);
/* windowed's figures, estimates and flag from windows run so far */
void fid_lv_windowed_outcome(const fid_job *job, const fid_windowed *wd, fid_outcome *o);
/* windowed's estimate e per figure, and its parts: the windows' interval
 * (the part more windows shrink), the other random errors, the bias bounds */
void fid_lv_windowed_errors(const fid_windowed *wd, double e[FID_WIN_FIGS], double sampling[FID_WIN_FIGS],
                            double other[FID_WIN_FIGS], double bias[FID_WIN_FIGS]);
/* the largest of a result's three estimates */
double fid_lv_worst(const fid_result *r);
/* an empty outcome with its own figures' storage (any it had freed first);
 * 0, or -1 when out of memory */
int fid_lv_fresh_trial(fid_outcome *t, double acc, char *err, size_t errlen);

/* --accuracy acc (accuracy.c) */
int fid_accuracy_run(const fid_job *job, double acc, fid_outcome *o, char *err, size_t errlen);

/* flags r unreliable for `why`, after any reason it has (fidelity.c) */
void fid_set_unreliable(fid_result *r, const char *why);

/* ---- the cycle model on part of a frame (model_run.c) ------------------ */

/* Figures of a cycle-model run. */
typedef struct model_fig {
    double cycles, rays, mrps, dram_bytes, energy_mj, static_mj, dram_mj, dram_static_mj;
    double mem_latency, dram_gbs, row_hit, mem_requests;
    double unit_dyn_mj[EU_DRAM];  /* dynamic energy of the units before DRAM (energy.h order: trv .. fifo) */
} model_fig;

/* the pixels of group `group` of `groups` interleaved sets of row bands, one
 * band in `period` each, *n of them; NULL when out of memory */
uint32_t *fid_band_subset(const fid_job *job, uint32_t period, uint32_t group, uint32_t groups, uint32_t *n);
/* the band period of a pilot on about `fraction` of the pixels */
uint32_t fid_pilot_period(const fid_job *job, double fraction);
/* a run's figures, from the model's typed figures (accel_top_figures) */
void fid_get_fig(const accel_top *t, model_fig *f);
/* the model with cfg on map[0..n) (NULL: the frame) into *fig; *keep: the
 * top handed back; tag: --series rows written. 0, 1 on a simulation
 * failure, 2 on bad input */
int fid_run_model_series(const fid_job *job, const rtcfg *cfg, const uint32_t *map, uint32_t n, model_fig *fig,
                         accel_top **keep, const char *tag, uint32_t piece, char *err, size_t errlen);
/* the same without --series rows (pilots) */
int fid_run_model(const fid_job *job, const rtcfg *cfg, const uint32_t *map, uint32_t n, model_fig *fig,
                  accel_top **keep, char *err, size_t errlen);

/* ---- the registry of estimated figures (own_stats.c) ------------------- */

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
    /* the random errors beside the windows' as residuals that pair too
     * (windowed.h lat_resid, start_resid): the lattice's groups, and each
     * window's start excess (image order); start_windows: the windows
     * with a warm-up */
    double lat_resid[FID_WIN_HEADLINE][FID_LAT_GROUPS], start_resid[FID_WIN_HEADLINE][FID_PAIRED_MAX_WINDOWS];
    uint64_t lattice_groups, start_windows;
    const char *bound;
    bool has_func, is_sampled, is_windowed, has_units;
} fid_own;

/* o->stats: a new registry of *o->own's figures and o->res; 0, or non-zero
 * (o->stats NULL when out of memory) */
int fid_own_stats(fid_outcome *o);
/* the functional pass's counts, hit rates and bounds into w */
void fid_own_from_func(fid_own *w, const fid_func *f);
/* w's MRPS and GB/s from its cycles at clock_mhz; o's headline figures */
void fid_set_headline(fid_outcome *o, double clock_mhz);

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

/* a piece of *user (a piece_plan) into *result (a fid_piece), for
 * ks_pool_run; 0, or 2 with err set */
int fid_run_piece(void *user, int index, void *result, char *err, size_t errlen);
/* a frame's energy from a cycle-model sample m and the functional counts of
 * sample fs and frame ff; *range_mj: the bound on its error */
double fid_energy_ratio(const model_fig *m, const fid_func *fs, const fid_func *ff, double frame_seconds,
                        double *range_mj);

#endif
