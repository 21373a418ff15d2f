/* det_math.h — trigonometry that gives the same bits on every machine.
 *
 * libm's sin/cos/tan may differ in the last bit between C libraries and
 * versions; these use only + - * / on doubles (argument reduction by a
 * two-part 2*pi, then Taylor series to x^23 / x^24), so the built-in scenes,
 * camera rays and bounce directions are bit-for-bit reproducible across
 * IEEE-754 platforms (compiled without FP contraction, the C11 default of
 * GCC in ISO mode). Absolute error below 1e-12 for |x| <= 100 (argument
 * reduction adds about 1e-16 * |x| beyond): ample for geometry, not a
 * general libm replacement. sqrt is IEEE correctly rounded already. */
#ifndef RTSIM_TRACER_DET_MATH_H
#define RTSIM_TRACER_DET_MATH_H

#ifdef __cplusplus
extern "C" {
#endif

double rt_det_sin(double x);
double rt_det_cos(double x);
double rt_det_tan(double x);    /* sin/cos; x away from odd multiples of pi/2 */
double rt_det_sqrt(double x);   /* 0 for x <= 0 or NaN */

#ifdef __cplusplus
}
#endif

#endif
