/* fidelity.h — cheaper fidelity levels of the same machine, each result with
 * its own error estimate and an "unreliable" flag (docs/fidelity.md).
 *
 * Levels (rtsim --fidelity LEVEL):
 *   full        today's cycle-level model with command-level LPDDR3;
 *   fixed-mem   the same units, memory as latency + bandwidth limit
 *               (memory.model=fixed) calibrated per run from a short
 *               full-fidelity pilot on interleaved pixel rows;
 *   functional  no timing: rays through the caches in a plausible order
 *               (real counts), cycles from a throughput model;
 *   sampled     the full model on interleaved bands of pixel rows, scaled to the
 *               frame by a ratio estimator against the functional pass of
 *               the whole frame, with a confidence interval over groups;
 *   windowed    the full model on a few warmed-up windows of consecutive
 *               pixels only, scaled to the frame by the traversal work of a
 *               pixel lattice (fidelity/windowed.h).
 * --accuracy P% picks the cheapest level whose estimated errors stay within
 * P, from a pilot, and falls back to full when unsure.
 *
 * Contract: fid_run() runs a non-full level (or the automatic choice) for a
 * loaded scene and built BVH and fills a fid_outcome: either the accel_top
 * of the run that gives the figures (fixed-mem) or a statistics registry of
 * its own (functional, sampled), plus the fid_result (level, relative error
 * estimate per figure of merit, flag and reason). Deterministic: same inputs,
 * same numbers, whatever job->jobs (independent pieces run in forked worker
 * processes and are combined in a fixed order). Library folder: uses model/, tracer/ and frame/frame.h
 * (the tracer->model bridge); model/ never includes it. */
#ifndef RTSIM_FIDELITY_FIDELITY_H
#define RTSIM_FIDELITY_FIDELITY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "kernel/stats.h"
#include "model/accel_top.h"
#include "config/config.h"
#include "tracer/bvh/bvh.h"
#include "tracer/io/scene.h"

typedef enum fid_level { FID_FULL, FID_FIXED_MEM, FID_FUNCTIONAL, FID_SAMPLED, FID_WINDOWED, FID_LEVEL_COUNT } fid_level;

const char *fid_level_name(fid_level l);
/* "full", "fixed-mem", "functional", "sampled", "windowed"; false when unknown. */
bool fid_level_parse(const char *s, fid_level *out);
/* "2%", "2", "0.5%": percent in (0, 100]; false otherwise. */
bool fid_accuracy_parse(const char *s, double *fraction);

/* --accuracy's steps (a probe, a pilot, a level tried), each with the CPU
 * seconds it took in this process and its worker processes
 * (kernel/fork_pool.h ks_pool_process_cpu_s) */
#define FID_MAX_STEPS 8
typedef struct fid_step {
    const char *name;             /* a string literal: "windowed's lattice", "full", ... */
    double cpu_s;
} fid_step;

/* What a result claims about itself. The error estimates are relative
 * (0.02 = 2%) bounds on |estimate - full model| / full model. */
typedef struct fid_result {
    fid_level level;
    double err_mrps, err_dram_mb, err_energy_mj;
    uint64_t unreliable;          /* 1: a figure may lie outside its estimate */
    char reason[1024];           /* why unreliable ("" when reliable) */
    char detail[512];             /* how the figures were obtained (pilot, sample...) */
    char choice[768];             /* --accuracy: what was picked and why ("" otherwise) */
    double accuracy;              /* --accuracy target (fraction), 0 when not asked */
    fid_step steps[FID_MAX_STEPS]; /* --accuracy: what it ran, in order, the last the level picked */
    int nsteps;
} fid_result;

/* full: exact by definition. */
void fid_result_full(fid_result *r);
/* Registers fidelity_level (0..4), unreliable, error_estimate.mrps,
 * error_estimate.dram_mb, error_estimate.energy_mj (percent) in st; r must
 * outlive st's use. */
/* The statistics fid_register_stats adds, declared (--help-module fidelity). */
extern const ks_module_desc fid_module_desc;
int fid_register_stats(fid_result *r, ks_stats *st);
/* Summary lines: "fidelity    LEVEL ..." with estimates and flag. */
void fid_print_summary(const fid_result *r, FILE *out);
/* "host" line of --accuracy's steps and their CPU (nothing without steps):
 *   host        --accuracy's steps: windowed's probe 0.136 s, ..., full 20.159 s CPU
 *               (before full: 1.337 s, 6.6% of it)
 * the part in parentheses only on a fallback to full. */
void fid_print_steps(const fid_result *r, FILE *out);
/* JSON members for the string fields, without braces, each line starting
 * with two spaces and ending with ",\n":
 *   "fidelity": "LEVEL", "unreliable_reason": "...", "fidelity_choice": "..." */
void fid_json_strings(const fid_result *r, char *buf, size_t len);

/* One frame to model. */
typedef struct fid_job {
    rtcfg *cfg;                   /* fixed-mem changes memory keys for its runs and restores them */
    const rt_mesh *mesh;
    const rt_view *view;
    const rt_bvh_image *img;
    uint32_t width, height;
    bool diffuse;
    uint32_t bounces;
    uint64_t seed;
    double sample_rate;           /* sampled, windowed: fraction of pixels, 0 = default */
    accel_progress_fn progress;
    void *progress_user;
    int jobs;                     /* independent pieces (the frame's functional pass, sample
                                     groups, pilots) run in up to this many worker processes
                                     at once (kernel/fork_pool.h); <= 1: one after the other
                                     in this process. The figures are the same either way. */
    uint32_t windows;             /* windowed: windows, 0 = default */
    const char *series_dir;       /* interval statistics (model/series.h): each cycle-model run
                                     whose figures make the result writes its rows to a file
                                     of this folder (fid_subset_open_series); NULL: none */
    uint64_t series_interval;     /* cycles per row */
} fid_job;

typedef struct fid_outcome {
    fid_result res;
    accel_top *top;               /* the run the figures come from (fixed-mem, or full under --accuracy) */
    ks_stats *stats;              /* functional / sampled: figures of the frame (owned) */
    /* headline figures of the frame (whatever level) */
    double cycles, rays, mrps, dram_bytes, energy_mj;
    struct fid_own *own;          /* storage behind stats */
} fid_outcome;

/* Runs level (not FID_FULL) or, with accuracy > 0, the automatic choice.
 * Returns 0, 1 on a simulation failure (or a worker process that died), 2
 * on bad input, 128 + the signal when interrupted while worker processes
 * ran (kernel/interrupt.h: they are stopped); err set. */
int fid_run(const fid_job *job, fid_level level, double accuracy, fid_outcome *out, char *err, size_t errlen);
/* The figures' registry (top's or own). */
ks_stats *fid_outcome_stats(fid_outcome *o);
/* Summary of the figures (accel_top's, or the functional/sampled lines). */
void fid_outcome_print(fid_outcome *o, FILE *out);
void fid_outcome_free(fid_outcome *o);

#endif
