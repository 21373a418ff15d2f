/* subset.h — the cycle model (model/accel_top.h) on a subset of a frame's
 * pixels: the primary rays of map[0..n) in that order (map NULL: every
 * pixel in scanline order), their bounces as in a frame run (frame/frame.h).
 * Used by every level that runs the full model on part of a frame (pilots,
 * sample groups, windows).
 *
 * Contract: fid_subset_open() builds the source and the top (0, or 2 with a
 * message: bad configuration or out of memory); the caller runs the top
 * (accel_top_run or accel_top_run_until) and reads it, then
 * fid_subset_close() frees both. The struct must stay where it was opened
 * (the source points into it). */
#ifndef RTSIM_FIDELITY_SUBSET_H
#define RTSIM_FIDELITY_SUBSET_H

#include "fidelity/fidelity.h"
#include "frame/frame.h"

typedef struct fid_subset {
    rtsim_frame frame;
    accel_source src;
    const uint32_t *map;
    accel_top *top;
    FILE *series_f;               /* the run's series rows, NULL: none */
    accel_series *series;
} fid_subset;

int fid_subset_open(fid_subset *s, const fid_job *job, const rtcfg *cfg, const uint32_t *map, uint32_t n, char *err,
                    size_t errlen);
/* The same with job->series_dir set: the run writes its series rows,
 * labelled (piece, phase), to series_dir/<tag>-<piece, 6 digits>.csv
 * (rows only: the caller of fid_run joins the files in name order under one
 * header). Without job->series_dir, fid_subset_open. */
int fid_subset_open_series(fid_subset *s, const fid_job *job, const rtcfg *cfg, const uint32_t *map, uint32_t n,
                           const char *tag, uint32_t piece, const char *phase, char *err, size_t errlen);
/* 0, or -1 when the series rows could not be written. */
int fid_subset_close(fid_subset *s);

#endif
