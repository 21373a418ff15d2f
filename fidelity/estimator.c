/* estimator.c — the windowed level's estimator maths (see estimator.h). */
#include "fidelity/estimator.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

double fid_t95(int dof)
{
    /* two-sided 95% quantiles of Student's t (any statistics table) */
    static const double t[] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
                               2.201,  2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
                               2.080,  2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
    if (dof < 1)
        return t[0];
    if (dof <= 30)
        return t[dof - 1];
    return dof <= 60 ? 2.000 : 1.960;
}

double fid_spread_low95(int dof)
{
    /* upper 5% points of chi-square (any statistics table): the spread s of
     * dof degrees of freedom is at least s sqrt(dof / chi2) with 95%
     * confidence; beyond the table, Wilson and Hilferty's approximation */
    static const double c[] = {3.841,  5.991,  7.815,  9.488,  11.070, 12.592, 14.067, 15.507, 16.919, 18.307,
                               19.675, 21.026, 22.362, 23.685, 24.996, 26.296, 27.587, 28.869, 30.144, 31.410,
                               32.671, 33.924, 35.172, 36.415, 37.652, 38.885, 40.113, 41.337, 42.557, 43.773};
    if (dof < 1)
        dof = 1;
    double k = dof, q;
    if (dof <= 30)
        q = c[dof - 1];
    else {
        double a = 2.0 / (9.0 * k), b = 1.0 - a + 1.6449 * sqrt(a);
        q = k * b * b * b;
    }
    return sqrt(k / q);
}

double fid_dot(const double beta[FID_EST_AUX], const double x[FID_EST_AUX])
{
    double v = 0;
    for (int a = 0; a < FID_EST_AUX; a++)
        v += beta[a] * x[a];
    return v;
}

/* see estimator.h: non-negative weighted least squares over the subsets of the figures */
int fid_fit_nonneg(const double (*x)[FID_EST_AUX], const double *y, uint32_t M, double beta[FID_EST_AUX])
{
    double A[FID_EST_AUX][FID_EST_AUX] = {{0}}, v[FID_EST_AUX] = {0}, sy = 0, sx = 0;
    for (uint32_t i = 0; i < M; i++) {
        double w = x[i][0] + x[i][1], wt = w > 0 ? 1.0 / w : 0;
        for (int a = 0; a < FID_EST_AUX; a++) {
            v[a] += wt * x[i][a] * y[i];
            for (int b = 0; b < FID_EST_AUX; b++)
                A[a][b] += wt * x[i][a] * x[i][b];
        }
        sy += y[i], sx += w;
    }
    double best = INFINITY;
    int used = 0;
    for (unsigned set = 1; set < 1u << FID_EST_AUX; set++) {
        /* the normal equations on the subset, Gauss-Jordan with partial pivoting */
        int idx[FID_EST_AUX], m = 0;
        for (int a = 0; a < FID_EST_AUX; a++)
            if (set >> a & 1)
                idx[m++] = a;
        double S[FID_EST_AUX][FID_EST_AUX + 1];
        for (int i = 0; i < m; i++) {
            for (int j = 0; j < m; j++)
                S[i][j] = A[idx[i]][idx[j]];
            S[i][m] = v[idx[i]];
        }
        bool ok = true;
        for (int c = 0; c < m && ok; c++) {
            int piv = c;
            for (int i = c + 1; i < m; i++)
                if (fabs(S[i][c]) > fabs(S[piv][c]))
                    piv = i;
            if (!(fabs(S[piv][c]) > 1e-12 * A[idx[c]][idx[c]]) || A[idx[c]][idx[c]] <= 0) {
                ok = false;   /* singular: a figure absent (primary rays have no bounce work) or collinear */
                break;
            }
            for (int j = 0; j <= m; j++) {
                double t = S[c][j];
                S[c][j] = S[piv][j], S[piv][j] = t;
            }
            for (int i = 0; i < m; i++)
                if (i != c) {
                    double f = S[i][c] / S[c][c];
                    for (int j = c; j <= m; j++)
                        S[i][j] -= f * S[c][j];
                }
        }
        double b[FID_EST_AUX] = {0};
        for (int i = 0; ok && i < m; i++)
            if ((b[idx[i]] = S[i][m] / S[i][i]) < 0)
                ok = false;
        if (!ok)
            continue;
        double sse = 0;
        for (uint32_t i = 0; i < M; i++) {
            double w = x[i][0] + x[i][1], e = y[i] - fid_dot(b, x[i]);
            sse += (w > 0 ? 1.0 / w : 0) * e * e;
        }
        if (sse < best * (1.0 - 1e-12)) {
            best = sse, used = m;
            memcpy(beta, b, sizeof b);
        }
    }
    if (used == 0) {
        for (int a = 0; a < FID_EST_AUX; a++)
            beta[a] = a == 2 ? 0 : sx > 0 ? sy / sx : 0;
        used = 1;
    }
    return used;
}

double fid_pairs_sumsq(const double *r, uint32_t M, uint32_t *pairs)
{
    uint32_t np = M < 2 ? 0 : M / 2 + M % 2;
    double s = 0;
    for (uint32_t q = 0; q < np; q++) {
        /* an odd window out is paired with its neighbour once more */
        uint32_t a = 2 * q < M - 1 ? 2 * q : M - 2, b = a + 1;
        s += (r[a] - r[b]) * (r[a] - r[b]);
    }
    if (pairs)
        *pairs = np;
    return s;
}
