/* levels.h — inside fidelity/: each level's run as the automatic choice
 * (accuracy.c) calls it. Each fills an outcome made by
 * fid_lv_fresh_trial() and returns 0, or non-zero with err set, as fid_run
 * (fidelity.h). Not for use outside fidelity/. */
#ifndef RTSIM_FIDELITY_LEVELS_H
#define RTSIM_FIDELITY_LEVELS_H

#include "fidelity/fidelity.h"
#include "fidelity/functional.h"
#include "fidelity/windowed.h"

/* functional: the frame's functional pass into *ff (kept for sampled) */
int fid_lv_functional(const fid_job *job, fid_outcome *o, fid_func *ff, char *err, size_t errlen);
/* sampled at `rate`; reuses *ff when it holds the frame's pass */
int fid_lv_sampled(const fid_job *job, double rate, fid_outcome *o, fid_func *ff, char *err, size_t errlen);
/* the full model */
int fid_lv_full(const fid_job *job, fid_outcome *o, char *err, size_t errlen);
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

#endif
