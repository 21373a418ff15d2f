/* trv_slab.h — the TRV's slab tests of all children of a node at once.
 *
 * Contract: trv_slab_lanes(prep, node, n, tmin, tmax, tnear, &hit_bits) gives,
 * for every child slot i < n of the node (n = 1..8, slots of RT_SLOT_BYTES),
 * exactly what the reference per-child code gives: for a used slot, bit i of
 * hit_bits and tnear[i] from rt_slab_test(prep, lo, hi, tmin, tmax)
 * (tracer/bvh/bvh_layout.h, the same IEEE single operations in the same order, bit
 * for bit, NaN and signed zeros included); for an empty slot (RT_META_EMPTY)
 * no hit and tnear +0. tnear must have room for 8 floats (lanes past n may be
 * written). Returns the number of used slots (the box tests the TRV counts).
 *
 * Why: the slab tests are the largest single cost of a TRV pass; with SSE2
 * (every x86-64) four children are tested in one go: subps/mulps are the scalar
 * operations lane by lane, minps/maxps return the second operand when either is
 * NaN or both are equal, exactly rt_minf/rt_maxf (a < b ? a : b, a > b ? a : b),
 * cmpordps is "neither is NaN", and the selects are bitwise. Without SSE2
 * (arm64) the reference code runs per child. Only slot memory is read (lanes
 * past n repeat slot 0). Tested against rt_slab_test in tb_trv_slab. */
#ifndef RTSIM_MODEL_TRV_SLAB_H
#define RTSIM_MODEL_TRV_SLAB_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "tracer/bvh/bvh_layout.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

/* Set bits of an 8-bit mask (no popcnt instruction on baseline x86-64; the
 * builtin would be a library call): two nibble look-ups. */
static inline int trv_popcount8(uint32_t x)
{
    static const uint8_t nibble_bits[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};
    return nibble_bits[x & 15u] + nibble_bits[(x >> 4) & 15u];
}

#if defined(__SSE2__)
/* Lanes base..base+3 (those >= n repeat slot 0): hit bits of the used slots in
 * *hit_bits (bit k = lane base+k), tnear[base..base+4) written (4 floats: the
 * caller's array has room), returns the used slots among the lanes < n. */
static inline __attribute__((always_inline)) int trv_slab_group(const rt_ray_prep *r, const uint8_t *node, int n,
                                                                int base, float tmin, float tmax, float *tnear,
                                                                uint32_t *hit_bits)
{
    /* org and inv_dir are six consecutive floats: two loads, six shuffles */
    _Static_assert(offsetof(rt_ray_prep, inv_dir) == 3 * sizeof(float) && sizeof(rt_ray_prep) == 6 * sizeof(float),
                   "rt_ray_prep: org then inv_dir, six floats");
    const float *pf = (const float *)(const void *)r;
    const __m128 p0 = _mm_loadu_ps(pf);       /* org.x org.y org.z inv.x */
    const __m128 p1 = _mm_loadu_ps(pf + 2);   /* org.z inv.x inv.y inv.z */
    const __m128 ox = _mm_shuffle_ps(p0, p0, 0x00), oy = _mm_shuffle_ps(p0, p0, 0x55), oz = _mm_shuffle_ps(p0, p0, 0xAA);
    const __m128 ix = _mm_shuffle_ps(p0, p0, 0xFF), iy = _mm_shuffle_ps(p1, p1, 0xAA), iz = _mm_shuffle_ps(p1, p1, 0xFF);
    /* slot floats: lo.x lo.y lo.z hi.x | hi.y hi.z ref meta */
    __m128 a[4], b[4];
    for (int k = 0; k < 4; k++) {
        const float *s = (const float *)(const void *)(node + (size_t)(base + k < n ? base + k : 0) * RT_SLOT_BYTES);
        a[k] = _mm_loadu_ps(s);
        b[k] = _mm_loadu_ps(s + 4);
    }
    _MM_TRANSPOSE4_PS(a[0], a[1], a[2], a[3]);   /* lo.x, lo.y, lo.z, hi.x of the 4 lanes */
    _MM_TRANSPOSE4_PS(b[0], b[1], b[2], b[3]);   /* hi.y, hi.z, ref, meta */
    __m128 tn = _mm_set1_ps(tmin), tf = _mm_set1_ps(tmax);
#define TRV_SLAB_AXIS_(lo, hi, o, inv)                                                           \
    do {                                                                                         \
        const __m128 t0 = _mm_mul_ps(_mm_sub_ps(lo, o), inv);                                   \
        const __m128 t1 = _mm_mul_ps(_mm_sub_ps(hi, o), inv);                                   \
        const __m128 ord = _mm_cmpord_ps(t0, t1);                                                \
        const __m128 nn = _mm_max_ps(tn, _mm_min_ps(t0, t1));                                    \
        const __m128 ff = _mm_min_ps(tf, _mm_max_ps(t0, t1));                                    \
        tn = _mm_or_ps(_mm_and_ps(ord, nn), _mm_andnot_ps(ord, tn));                             \
        tf = _mm_or_ps(_mm_and_ps(ord, ff), _mm_andnot_ps(ord, tf));                             \
    } while (0)
    TRV_SLAB_AXIS_(a[0], a[3], ox, ix);
    TRV_SLAB_AXIS_(a[1], b[0], oy, iy);
    TRV_SLAB_AXIS_(a[2], b[1], oz, iz);
#undef TRV_SLAB_AXIS_
    /* RT_META_EMPTY is bit 31, the sign bit of the meta lane */
    const __m128 empty = _mm_castsi128_ps(_mm_srai_epi32(_mm_castps_si128(b[3]), 31));
    const int valid = n - base >= 4 ? 0xF : (1 << (n - base)) - 1;
    const int used = ~_mm_movemask_ps(empty) & valid;
    *hit_bits |= (uint32_t)(_mm_movemask_ps(_mm_cmple_ps(tn, tf)) & used) << base;
    _mm_storeu_ps(tnear + base, _mm_andnot_ps(empty, tn));   /* empty slots: +0 */
    return trv_popcount8((uint32_t)used);
}
#endif

/* hit bit i of *hit_bits: child i hit; tnear[0..8) written (room for 8 floats). */
static inline int trv_slab_lanes(const rt_ray_prep *r, const uint8_t *node, int n, float tmin, float tmax,
                                 float tnear[8], uint32_t *hit_bits)
{
    *hit_bits = 0;
#if defined(__SSE2__)
    if (n == 4)   /* MBVH4 */
        return trv_slab_group(r, node, 4, 0, tmin, tmax, tnear, hit_bits);
    if (n == 2)   /* BVH2 */
        return trv_slab_group(r, node, 2, 0, tmin, tmax, tnear, hit_bits);
    int used = 0;
    for (int base = 0; base < n; base += 4)
        used += trv_slab_group(r, node, n, base, tmin, tmax, tnear, hit_bits);
    return used;
#else
    int used = 0;
    for (int i = 0; i < n; i++) {
        const uint8_t *slot = node + (size_t)i * RT_SLOT_BYTES;
        uint32_t meta;
        memcpy(&meta, slot + 28, sizeof meta);
        float lohi[6], tn = 0.0f;
        memcpy(lohi, slot, sizeof lohi);
        if (!(meta & RT_META_EMPTY)) {
            used++;
            if (rt_slab_test(r, lohi, lohi + 3, tmin, tmax, &tn))
                *hit_bits |= 1u << i;
        }
        tnear[i] = tn;
    }
    return used;
#endif
}

#endif
