/* windowed.h — the windowed level: the full model on a few windows of
 * consecutive pixels spread over the frame, each after a warm-up stretch of
 * the pixels just before it, and nothing else of the frame through the
 * model (docs/fidelity.md "windowed").
 *
 * SMARTS-style interval sampling with bounded warming: a window's run starts
 * cold warm_pixels before it, runs the cycle model through the warm-up (the
 * caches, DRAM rows and the ray pipeline reach the state the frame has
 * there: the caches hold 1-2K lines, the pipeline 128 rays) and measures
 * the window as the difference of two points of the run (accel_top.h
 * accel_top_run_until): cycles, rays, DRAM bytes and energy.
 *
 * Scaling to the frame: each figure fitted on the windows against four
 * auxiliary figures of their pixels, applied to the frame's, estimated from
 * a lattice of 1 pixel in win_lattice run through the functional level
 * (functional.h, no timing): the node visits and the triangle tests of each
 * pixel's rays, its bounces' traversal work, and the DRAM lines
 * the lattice's caches fetched for it (a window's: its lattice pixels',
 * scaled; where in the scene the misses are, which work alone does not
 * say: hairball diffuse MRPS was 3.1-3.5% off without it, 1.2-1.4% with,
 * docs/fidelity.md "windowed"); plus the
 * frame's start (the warm-up's excess over its fit, averaged over the
 * windows: every warm-up starts as cold as the frame does) and its drain
 * (the path latency). Each figure's 95% interval comes from the windows'
 * residuals paired with their neighbours in the image (collapsed strata,
 * Student t), the lattice's standard error and the start correction's
 * spread; a warm-up bias bound from the fills into never-used cache ways
 * inside the windows (a warm cache would have had a line there).
 *
 * Contract: fid_windowed_run() fills *out; deterministic whatever job->jobs
 * (the windows are independent pieces, kernel/fork_pool.h; the lattice runs
 * in the calling process first, the windows' figures need its pixels').
 * Returns 0, 1 on a simulation failure, 2 on bad input or no memory, or the
 * pool's 128 + signal; err set. */
#ifndef RTSIM_FIDELITY_WINDOWED_H
#define RTSIM_FIDELITY_WINDOWED_H

#include <stdbool.h>
#include <stdint.h>

#include "fidelity/fidelity.h"
#include "model/energy/energy.h"

/* The figures estimated: the three figures of merit (FID_WIN_HEADLINE of
 * them), then each unit's dynamic energy (model/energy/energy.h order) and
 * DRAM's static (background) energy, for Table 1's power per unit. */
enum {
    FID_WIN_CYCLES,
    FID_WIN_DRAM,
    FID_WIN_ENERGY,
    FID_WIN_HEADLINE,
    FID_WIN_UNIT0 = FID_WIN_HEADLINE,
    FID_WIN_DRAM_STATIC = FID_WIN_UNIT0 + EU_COUNT,
    FID_WIN_FIGS
};
/* the auxiliary figures of a pixel's path: its rays' node visits (the
 * TRVs' work) and triangle tests (the IST's), its bounce rays' traversal
 * work (visits + tests), and the DRAM lines its misses bring in when the
 * lattice's pixels run through the functional level's caches (a window's:
 * from the lattice's pixels inside it) */
enum { FID_AUX_VISITS, FID_AUX_TRI_TESTS, FID_AUX_BOUNCE_WORK, FID_AUX_DRAM_LINES, FID_AUX_COUNT };
/* the lattice's pixels in interleaved groups (pixel k of the lattice in
 * group k % FID_LAT_GROUPS), each a sparser lattice of its own: the spread
 * of the groups' estimates is what a paired estimate pairs */
enum { FID_LAT_GROUPS = 16 };

typedef struct fid_windowed {
    /* the plan and what ran */
    uint32_t windows, warm_pixels, window_pixels;  /* windows run (the plan's after fid_windowed_run); pixels per window */
    uint32_t planned;             /* fid_windowed_probe: the plan's windows */
    double model_pixels;          /* pixels through the cycle model (warm-ups and windows) */
    double measured_pixels;       /* of them, inside the windows */
    double lattice_pixels;        /* pixels through the functional level for the frame's auxiliary figures */
    double lattice_cpu_s;         /* CPU seconds the lattice took (ks_pool_process_cpu_s) */
    bool too_small;               /* the frame cannot hold the plan: windows shrank or overlap */
    /* the frame */
    double primaries, rays, cycles, dram_bytes, energy_mj, static_mj;
    /* per unit: the frame's dynamic energy (mJ; DRAM's static at EU_COUNT),
     * leakage (mW; DRAM's 0: its static energy is estimated) and area (mm2) */
    double unit_mj[EU_COUNT + 1], leak_mw[EU_COUNT], area_mm2[EU_COUNT];
    bool has_units;               /* an energy model: the three arrays hold */
    double mean_latency;          /* cycles per ray in the windows */
    /* relative errors (fractions), each a 95% half-width or a bound */
    double ci[FID_WIN_FIGS];      /* the windows' spread about the ratio */
    double start_err[FID_WIN_FIGS]; /* the start correction's spread */
    double lattice_err[FID_WIN_FIGS]; /* the frame's auxiliary figure from the lattice */
    double rays_err;              /* the frame's ray count from the lattice (0 for primary rays) */
    double cold_share;            /* fills into never-used ways / fills, in the windows */
    /* resid[k * windows + q]: window q's (image order) residual of headline
     * figure k as it enters ci[k], relative to the frame's figure:
     * ci[k] = t95 . sqrt(fid_pairs_sumsq(resid + k * windows)) (estimator.h);
     * a sweep's paired estimates pair them across machines (owned) */
    double *resid, t95;
    uint32_t npairs;
    /* the random errors beside the windows' interval, as residuals that pair
     * across machines too (relative to the frame's figure; their sums of
     * squares are the variances): lat_resid[k * FID_LAT_GROUPS + g], group
     * g's estimate of the lattice's part less the groups' mean;
     * start_resid[k * windows + q], window q's (image order) start excess
     * less the mean (0 for a window without a warm-up); start_windows: the
     * windows with one (owned) */
    double *lat_resid, *start_resid;
    uint32_t start_windows;
    struct fid_win_runs *runs;    /* the windows run so far (owned) */
} fid_windowed;

/* Plans and runs the windows and the lattice, and estimates. rate: fraction
 * of the frame's pixels through the cycle model (warm-ups included; 0 = the
 * default win_rate); windows: 0 = the default. fid_windowed_free() frees
 * what out->runs holds (after any return). */
int fid_windowed_run(const fid_job *job, double rate, uint32_t windows, fid_windowed *out, char *err, size_t errlen);
/* Plans the same way but runs only the first `count` windows (and the
 * lattice): a pilot whose estimate says whether the rest is worth its
 * cost; out->planned: the plan's windows. */
int fid_windowed_probe(const fid_job *job, double rate, uint32_t windows, uint32_t count, fid_windowed *out,
                       char *err, size_t errlen);
/* --accuracy's first look, before the lattice: one window of
 * win_probe_pixels after a win_warm_pixels warm-up from empty caches, in
 * this process; *cold_share: its fills into never-used ways / its fills;
 * *turnover: the frame's node L2 and primitive cache fills at the
 * window's rate over those caches' lines. Where most fills are cold, or
 * the frame refills its caches only a few times (primary rays: the caches
 * keep their lines for most of a frame), no window stands for the frame.
 * 0, 1 or 2 as fid_windowed_run. */
int fid_windowed_cold_probe(const fid_job *job, double *cold_share, double *turnover, char *err, size_t errlen);
/* Runs windows up to `windows` in all (beyond the plan too: the positions
 * are a sequence, the earlier windows are kept) and the lattice if not yet
 * run, and estimates. */
int fid_windowed_more(const fid_job *job, uint32_t windows, fid_windowed *out, char *err, size_t errlen);
void fid_windowed_free(fid_windowed *w);
/* Whether the frame holds the plan without flagging it as too small; why
 * (when not): what is too small. */
bool fid_windowed_fits(const fid_job *job, double rate, uint32_t windows, char *why, size_t whylen);

#endif
