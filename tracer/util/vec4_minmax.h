/* vec4_minmax.h — four-lane float min/max/add/sub/mul for the BVH builder's
 * box arithmetic (bvh2_sah.c): SSE on x86-64, plain C elsewhere. Bounds hold
 * no NaNs, so both paths give the same bits (min/max/add/sub/mul are exact
 * IEEE operations lane by lane) and trees are identical across machines.
 * Internal to tracer/. */
#ifndef RTSIM_TRACER_VEC4_MINMAX_H
#define RTSIM_TRACER_VEC4_MINMAX_H

#if defined(__SSE2__)
#include <emmintrin.h>
typedef __m128 v4;
static inline v4 v4_load(const float *p) { return _mm_load_ps(p); }     /* p 16-byte aligned */
static inline void v4_store(float *p, v4 a) { _mm_store_ps(p, a); }
static inline v4 v4_set1(float x) { return _mm_set1_ps(x); }
static inline v4 v4_min(v4 a, v4 b) { return _mm_min_ps(a, b); }
static inline v4 v4_max(v4 a, v4 b) { return _mm_max_ps(a, b); }
static inline v4 v4_add(v4 a, v4 b) { return _mm_add_ps(a, b); }
static inline v4 v4_sub(v4 a, v4 b) { return _mm_sub_ps(a, b); }
static inline v4 v4_mul(v4 a, v4 b) { return _mm_mul_ps(a, b); }
/* truncating float -> int of lanes 0..2 */
static inline void v4_to_int3(v4 a, int out[4]) { _mm_storeu_si128((__m128i *)out, _mm_cvttps_epi32(a)); }
#else
typedef struct v4 {
    float f[4];
} v4;
static inline v4 v4_load(const float *p) { return (v4){{p[0], p[1], p[2], p[3]}}; }
static inline void v4_store(float *p, v4 a)
{
    for (int i = 0; i < 4; i++)
        p[i] = a.f[i];
}
static inline v4 v4_set1(float x) { return (v4){{x, x, x, x}}; }
#define V4_LANES(expr) \
    v4 r;              \
    for (int i = 0; i < 4; i++) \
        r.f[i] = (expr);        \
    return r
static inline v4 v4_min(v4 a, v4 b) { V4_LANES(a.f[i] < b.f[i] ? a.f[i] : b.f[i]); }
static inline v4 v4_max(v4 a, v4 b) { V4_LANES(a.f[i] > b.f[i] ? a.f[i] : b.f[i]); }
static inline v4 v4_add(v4 a, v4 b) { V4_LANES(a.f[i] + b.f[i]); }
static inline v4 v4_sub(v4 a, v4 b) { V4_LANES(a.f[i] - b.f[i]); }
static inline v4 v4_mul(v4 a, v4 b) { V4_LANES(a.f[i] * b.f[i]); }
#undef V4_LANES
static inline void v4_to_int3(v4 a, int out[4])
{
    for (int i = 0; i < 3; i++)
        out[i] = (int)a.f[i];
    out[3] = 0;
}
#endif

#endif
