/* det_math.c — see det_math.h. */
#include "tracer/util/det_math.h"

/* Reduces x to [-pi, pi] with a two-part 2*pi (Cody & Waite style) so the
 * reduction itself stays accurate for moderate |x|. */
static double reduce(double x)
{
    const double two_pi_hi = 6.28318530717958623200, two_pi_lo = 2.4492935982947064e-16;
    double k = x / two_pi_hi;
    k = (double)(long long)(k + (k >= 0 ? 0.5 : -0.5));
    return (x - k * two_pi_hi) - k * two_pi_lo;
}

double rt_det_sin(double x)
{
    x = reduce(x);
    /* Taylor series to x^23: remainder < pi^25/25! < 1e-12. */
    double x2 = x * x, term = x, sum = x;
    for (int n = 1; n <= 11; n++) {
        term *= -x2 / ((2 * n) * (2 * n + 1));
        sum += term;
    }
    return sum;
}

double rt_det_cos(double x)
{
    x = reduce(x);
    double x2 = x * x, term = 1, sum = 1;
    for (int n = 1; n <= 12; n++) {
        term *= -x2 / ((2 * n - 1) * (2 * n));
        sum += term;
    }
    return sum;
}

double rt_det_sqrt(double x)
{
    /* IEEE-754 requires sqrt to be correctly rounded, so this is already
     * deterministic; named so callers use only documented functions. */
    if (!(x > 0))
        return 0;
    return __builtin_sqrt(x);
}

double rt_det_tan(double x) { return rt_det_sin(x) / rt_det_cos(x); }
