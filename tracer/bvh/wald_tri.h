/* wald_tri.h — Wald's precomputed projection triangle (Wald 2004, "Realtime
 * Ray Tracing and Interactive Global Illumination", PhD thesis, sec. 7.1):
 * the 48-byte record of tracer/bvh/bvh_layout.h computed from three vertices.
 *
 * Contract: with N = (B-A) x (C-A), k = the axis of largest |N_k| (first on a
 * tie), u = (k+1) mod 3, v = (k+2) mod 3 and det = N_k:
 *   n_u = N_u/N_k, n_v = N_v/N_k, n_d = (N.A)/N_k            (plane, n_k = 1)
 *   b_nu = -(C-A)_u/det, b_nv = (C-A)_v/det, b_d = (A_v(C-A)_u - A_u(C-A)_v)/det
 *   c_nu = -(B-A)_v/det, c_nv = (B-A)_u/det, c_d = (A_u(B-A)_v - A_v(B-A)_u)/det
 * so that rt_wald_test's beta/gamma are the barycentric weights of B and C
 * (Embree's u and v). Computed in double and rounded once to float. A triangle
 * with N = 0 or any non-finite coefficient is flagged degenerate (flags bit 0,
 * all coefficients 0) and never hit. */
#ifndef RTSIM_TRACER_WALD_TRI_H
#define RTSIM_TRACER_WALD_TRI_H

#include <stdint.h>

#include "tracer/bvh/bvh_layout.h"
#include "tracer/io/mesh.h"

#define RT_TRI_FLAG_DEGENERATE 1u

void rt_wald_precompute(rt_vec3 a, rt_vec3 b, rt_vec3 c, uint32_t prim, rt_tri48 *out);

/* The record of mesh triangle prim. */
void rt_wald_precompute_prim(const rt_mesh *m, uint32_t prim, rt_tri48 *out);

#endif
