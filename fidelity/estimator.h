/* estimator.h — the windowed level's estimator maths as pure functions (no
 * model, no I/O), so each can be tested on made-up windows with a known
 * answer (testbench/tb_fidelity_estimator.c) and reused by the paired
 * estimates of a sweep (scripts/paired.py repeats fid_pairs_sumsq on the
 * residuals rtsim writes, docs/fidelity.md "Paired estimates").
 *
 * Windows come as M rows of FID_EST_AUX auxiliary figures x and one figure
 * y. Everything here is deterministic: sums run in index order. */
#ifndef RTSIM_FIDELITY_ESTIMATOR_H
#define RTSIM_FIDELITY_ESTIMATOR_H

#include <stdint.h>

enum { FID_EST_AUX = 4 };   /* auxiliary figures per window (windowed.h FID_AUX_COUNT) */

/* Student t, two-sided 95%, for dof degrees of freedom (>= 1; < 1 reads as 1). */
double fid_t95(int dof);

/* The lower one-sided 95% bound of a spread (standard deviation) measured
 * with dof degrees of freedom, as a factor of the measured spread:
 * sqrt(dof / chi2_0.95(dof)) (< 1; dof < 1 reads as 1). */
double fid_spread_low95(int dof);

/* beta . x over FID_EST_AUX figures. */
double fid_dot(const double beta[FID_EST_AUX], const double x[FID_EST_AUX]);

/* Coefficients beta of y ~ beta . x over M windows: least squares weighted
 * by 1 / (x[0] + x[1]) (a window's spread grows with its work, as a ratio
 * estimator assumes), no coefficient negative (of the fits on each subset
 * of the figures whose coefficients are all >= 0, the one with the least
 * weighted residual sum). Falls back to one ratio sum(y) / sum(x[0] + x[1])
 * on x[0] and x[1] when no subset fits. Returns how many coefficients are
 * not 0 (the fit's degrees of freedom). */
int fid_fit_nonneg(const double (*x)[FID_EST_AUX], const double *y, uint32_t M, double beta[FID_EST_AUX]);

/* Collapsed strata (Cochran, Sampling Techniques, 3rd ed., 5A.12): r[0..M-1]
 * are the residuals of M windows, one per stratum, in image order; pairs
 * (0,1), (2,3), ... and, for odd M, (M-2, M-1) once more. Returns the sum
 * over the pairs of (r_a - r_b)^2, an estimate of the variance of sum(r)
 * (each pair's squared difference is twice the variance within its two
 * strata, and a pair covers two of them); *pairs: the number of pairs, the
 * t's degrees of freedom. M < 2: returns 0 and *pairs = 0. */
double fid_pairs_sumsq(const double *r, uint32_t M, uint32_t *pairs);

#endif
