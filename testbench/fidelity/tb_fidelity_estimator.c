/* tb_fidelity_estimator.c — the windowed level's estimator maths
 * (fidelity/estimator.h) on made-up windows with a known answer:
 *   - the Student t table at a few degrees of freedom;
 *   - the collapsed strata's pair sums, even and odd counts by hand;
 *   - the non-negative fit: exact data recovers its coefficients; data
 *     whose unconstrained fit has a negative coefficient gets that
 *     coefficient 0 and the one-figure weighted fit by hand;
 *   - calibration: windows drawn from a known population (a trend down the
 *     image plus independent noise), the frame's total by the fit, its 95%
 *     interval by the pairs; over 4000 draws the interval covers the true
 *     total 93-97% of the time, and the paired interval of the change
 *     between two correlated "machines" covers the true change likewise and
 *     is narrower than the unpaired one (scripts/paired.py's method). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "fidelity/estimator.h"
#include "testbench/tb.h"

/* a deterministic generator: 64-bit LCG (Knuth MMIX constants) and Box-Muller */
static uint64_t rng = 88172645463325252ull;
static double uniform(void)
{
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return ((double)(rng >> 11) + 0.5) / 9007199254740992.0;
}
static double normal(void) { return sqrt(-2.0 * log(uniform())) * cos(6.283185307179586 * uniform()); }

enum { STRATA = 16, PER = 400, DRAWS = 4000 };

int main(void)
{
    tb_begin("estimator_t95");
    TB_CHECK(fabs(fid_t95(1) - 12.706) < 1e-9 && fabs(fid_t95(8) - 2.306) < 1e-9 && fabs(fid_t95(30) - 2.042) < 1e-9,
             "t table");
    TB_CHECK(fabs(fid_t95(0) - 12.706) < 1e-9 && fabs(fid_t95(45) - 2.000) < 1e-9 && fabs(fid_t95(500) - 1.960) < 1e-9,
             "t beyond the table");
    tb_end();

    tb_begin("estimator_spread_low95");
    TB_CHECK(fabs(fid_spread_low95(4) - sqrt(4 / 9.488)) < 1e-12 && fabs(fid_spread_low95(0) - sqrt(1 / 3.841)) < 1e-12,
             "chi-square table");
    TB_CHECK(fabs(fid_spread_low95(30) - fid_spread_low95(31)) < 0.01 && fid_spread_low95(31) > fid_spread_low95(30),
             "Wilson-Hilferty beyond the table joins it");
    /* coverage: a spread of dof normal draws (known mean 0) times the factor
     * stays under the true spread (1) in 95% of the draws (the stream of
     * draws is put back after: the tests below keep theirs) */
    const uint64_t rng_saved = rng;
    for (int dof = 4; dof <= 40; dof += 36) {
        int below = 0;
        for (int d = 0; d < DRAWS * 5; d++) {
            double ss = 0;
            for (int i = 0; i < dof; i++) {
                double z = normal();
                ss += z * z;
            }
            below += sqrt(ss / dof) * fid_spread_low95(dof) <= 1.0;
        }
        double cover = (double)below / (DRAWS * 5);
        TB_CHECK(cover > 0.94 && cover < 0.96, "dof %d: coverage %.3f, expected 0.95", dof, cover);
    }
    rng = rng_saved;
    tb_end();

    tb_begin("estimator_pairs");
    {
        const double r[] = {1, 3, 2, 2, 5};
        uint32_t np = 99;
        TB_CHECK(fabs(fid_pairs_sumsq(r, 4, &np) - 4.0) < 1e-12 && np == 2, "4 windows: (1-3)^2 + (2-2)^2, 2 pairs");
        TB_CHECK(fabs(fid_pairs_sumsq(r, 5, &np) - 13.0) < 1e-12 && np == 3,
                 "5 windows: the odd one paired with its neighbour once more: 4 + 0 + 9, 3 pairs");
        TB_CHECK(fid_pairs_sumsq(r, 1, &np) == 0.0 && np == 0, "1 window: no pair");
    }
    tb_end();

    tb_begin("estimator_fit_exact");
    {
        /* every auxiliary figure with a coefficient of its own */
        _Static_assert(FID_EST_AUX == 4, "the made-up windows below have four auxiliary figures");
        double x[8][FID_EST_AUX], y[8], beta[FID_EST_AUX];
        for (int i = 0; i < 8; i++) {
            x[i][0] = 100 + 17 * i, x[i][1] = 300 - 11 * i + (i % 3) * 40, x[i][2] = 5 + (i * 7) % 4;
            x[i][3] = 40 + (i * i) % 7;
            y[i] = 2.0 * x[i][0] + 3.0 * x[i][1] + 0.5 * x[i][2] + 1.5 * x[i][3];
        }
        int used = fid_fit_nonneg((const double(*)[FID_EST_AUX])x, y, 8, beta);
        TB_CHECK(fabs(beta[0] - 2.0) < 1e-9 && fabs(beta[1] - 3.0) < 1e-9 && fabs(beta[2] - 0.5) < 1e-9 &&
                     fabs(beta[3] - 1.5) < 1e-9,
                 "beta %g %g %g %g, expected 2 3 0.5 1.5", beta[0], beta[1], beta[2], beta[3]);
        TB_EQ_INT(used, 4);
    }
    tb_end();

    tb_begin("estimator_fit_nonneg");
    {
        /* y = 5 x0 - x1: the unconstrained fit needs a negative x1 */
        double x[6][FID_EST_AUX] = {{0}}, y[6], beta[FID_EST_AUX], num = 0, den = 0;
        for (int i = 0; i < 6; i++) {
            x[i][0] = 50 + 10 * i, x[i][1] = 20 + 9 * (i % 2);
            y[i] = 5 * x[i][0] - x[i][1];
            double wt = 1.0 / (x[i][0] + x[i][1]);
            num += wt * x[i][0] * y[i], den += wt * x[i][0] * x[i][0];
        }
        int used = fid_fit_nonneg((const double(*)[FID_EST_AUX])x, y, 6, beta);
        TB_CHECK(beta[1] == 0.0 && beta[2] == 0.0 && beta[3] == 0.0 && fabs(beta[0] - num / den) < 1e-9 * (num / den),
                 "beta %g %g %g %g, expected %g 0 0 0", beta[0], beta[1], beta[2], beta[3], num / den);
        TB_EQ_INT(used, 1);
    }
    tb_end();

    tb_begin("estimator_calibration");
    {
        /* A frame of STRATA bands of PER units; a unit's work x follows a
         * trend down the image, its figure y = 2 x (1 + noise), a second
         * machine's 2.2 x (1 + the same noise + a little of its own). The
         * window of a band: an eighth of its units. The frame's total is
         * beta . X with X known (the lattice's role). */
        int cover = 0, cover_change = 0, narrower = 0;
        for (int d = 0; d < DRAWS; d++) {
            double X = 0, Y = 0, YB = 0, xs[STRATA][FID_EST_AUX], ys[STRATA], yb[STRATA];
            for (int s = 0; s < STRATA; s++) {
                for (int a = 0; a < FID_EST_AUX; a++)
                    xs[s][a] = 0;
                ys[s] = yb[s] = 0;
                for (int u = 0; u < PER; u++) {
                    double x = 1000 + 600 * sin(0.4 * s) + 50 * normal(), e = normal();
                    double y = 2 * x * (1 + 0.1 * e), b = 2.2 * x * (1 + 0.1 * e + 0.02 * normal());
                    X += x, Y += y, YB += b;
                    if (u < PER / 8) {   /* the window: the first eighth of the band's units */
                        xs[s][0] += x, ys[s] += y, yb[s] += b;
                    }
                }
            }
            double Xa[FID_EST_AUX] = {X}, rel[2][STRATA], est[2];
            const double *yy[2] = {ys, yb};
            for (int m = 0; m < 2; m++) {
                double beta[FID_EST_AUX], fitted = 0;
                int used = fid_fit_nonneg((const double(*)[FID_EST_AUX])xs, yy[m], STRATA, beta);
                for (int s = 0; s < STRATA; s++)
                    fitted += fid_dot(beta, xs[s]);
                est[m] = fid_dot(beta, Xa);
                double scale = est[m] / fitted, dof = (double)STRATA / (STRATA - used), f = 1.0 / 8;
                for (int s = 0; s < STRATA; s++)
                    rel[m][s] = (yy[m][s] - fid_dot(beta, xs[s])) * scale * sqrt(dof * (1 - f)) / est[m];
            }
            uint32_t np;
            double ci = fid_t95(STRATA / 2) * sqrt(fid_pairs_sumsq(rel[0], STRATA, &np));
            cover += fabs(est[0] / Y - 1) <= ci;
            double diff[STRATA];
            for (int s = 0; s < STRATA; s++)
                diff[s] = rel[1][s] - rel[0][s];
            double ci_b = fid_t95(STRATA / 2) * sqrt(fid_pairs_sumsq(rel[1], STRATA, &np));
            double ci_change = fid_t95((int)np) * sqrt(fid_pairs_sumsq(diff, STRATA, &np));
            double change = est[1] / est[0], truth = YB / Y;
            cover_change += fabs(change / truth - 1) <= ci_change;
            narrower += ci_change < 0.5 * (ci + ci_b);
        }
        double c = (double)cover / DRAWS, cc = (double)cover_change / DRAWS;
        printf("coverage: figure %.3f, paired change %.3f; paired narrower in %d of %d draws\n", c, cc, narrower,
               DRAWS);
        TB_CHECK(c >= 0.93 && c <= 0.97, "the figure's 95%% interval covers the truth %.3f of the time", c);
        TB_CHECK(cc >= 0.93 && cc <= 0.99, "the change's paired interval covers the true change %.3f of the time", cc);
        TB_CHECK(narrower > DRAWS * 9 / 10, "the paired interval narrower than the figures' in %d of %d draws",
                 narrower, DRAWS);
    }
    tb_end();
    return tb_finish();
}
