/* bvh_layout.h — the bytes the hardware fetches: node and triangle formats of
 * the simulated memory image, and the exact arithmetic of a box and a
 * triangle test on them. Shared by the reference traversal (tracer/) and the
 * hardware model (model/ may include this header and nothing else of tracer/).
 *
 * Node of an N-wide BVH (N = 2..8): N child slots of 32 bytes, so a node is
 * N x 32 bytes (64 B for BVH2, 128 B for MBVH4; paper Fig. 1 and sec. 3.1).
 * Slot c (little-endian):
 *   float lo[3], hi[3]   child AABB                               bytes 0..23
 *   uint32 ref           inner child: node index (address = node_base + ref * node_bytes)
 *                        leaf child:  first triangle index (address = tri_base + ref * 48)
 *   uint32 meta          bits 0..15: triangle count of a leaf child (1..RT_LEAF_MAX),
 *                        0 for an inner child; bit 31 (RT_META_EMPTY): slot unused
 *                        (then the box is lo = +inf, hi = -inf and ref = 0; an
 *                        empty slot is recognised by this bit and never tested:
 *                        the slab test of an inverted box does not reliably miss)
 * Used slots come first; the root is node 0 and always an inner node.
 *
 * Triangle: 48 bytes in Wald's (2004, sec. 7.1) precomputed projection form:
 *   float n_u, n_v, n_d; uint32 k;        plane: n_k = 1 (implicit), k = dominant axis
 *   float b_nu, b_nv, b_d; uint32 prim;   edge 1 (barycentric beta); prim = mesh triangle index
 *   float c_nu, c_nv, c_d; uint32 flags;  edge 2 (barycentric gamma); flags bit 0: degenerate
 * Triangles are stored in leaf order (a leaf's triangles are contiguous).
 *
 * The arithmetic below is the definition of what a box-test and a triangle-test
 * unit compute: the reference traversal and the model both call these, so
 * their results agree bit for bit (C11 float ops, no contraction: -std=c11). */
#ifndef RTSIM_TRACER_BVH_LAYOUT_H
#define RTSIM_TRACER_BVH_LAYOUT_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#define RT_SLOT_BYTES 32u
#define RT_TRI_BYTES 48u
#define RT_WIDTH_MIN 2
#define RT_WIDTH_MAX 8
#define RT_LEAF_MAX 255u          /* upper bound of a leaf's triangle count */
#define RT_META_EMPTY 0x80000000u
#define RT_META_COUNT_MASK 0xFFFFu

static inline uint32_t rt_node_bytes(int width) { return (uint32_t)width * RT_SLOT_BYTES; }

typedef struct rt_child {
    float lo[3], hi[3];
    uint32_t ref, meta;
} rt_child;

typedef struct rt_tri48 {
    float n_u, n_v, n_d;
    uint32_t k;
    float b_nu, b_nv, b_d;
    uint32_t prim;
    float c_nu, c_nv, c_d;
    uint32_t flags;
} rt_tri48;

/* Decode slot c of a node from its bytes (little-endian host assumed; the
 * project targets x86-64/arm64 Linux). */
static inline void rt_node_child(const uint8_t *node, int c, rt_child *out)
{
    memcpy(out, node + (size_t)c * RT_SLOT_BYTES, sizeof *out);
}
static inline bool rt_child_empty(const rt_child *ch) { return (ch->meta & RT_META_EMPTY) != 0; }
static inline bool rt_child_is_leaf(const rt_child *ch) { return !rt_child_empty(ch) && (ch->meta & RT_META_COUNT_MASK) != 0; }
static inline uint32_t rt_child_count(const rt_child *ch) { return ch->meta & RT_META_COUNT_MASK; }

static inline void rt_tri_decode(const uint8_t *bytes, rt_tri48 *out) { memcpy(out, bytes, sizeof *out); }

/* Precomputed per-ray values a TRV holds in its ray state. */
typedef struct rt_ray_prep {
    float org[3], inv_dir[3];
} rt_ray_prep;

static inline void rt_ray_prepare(const float org[3], const float dir[3], rt_ray_prep *p)
{
    for (int a = 0; a < 3; a++) {
        p->org[a] = org[a];
        /* 1/0 = +-inf is intended: the slab then spans everything or nothing */
        p->inv_dir[a] = 1.0f / dir[a];
    }
}

static inline float rt_minf(float a, float b) { return a < b ? a : b; }   /* b when either is NaN */
static inline float rt_maxf(float a, float b) { return a > b ? a : b; }

/* One axis of the slab test: narrows [*tn, *tf] by the axis' entry/exit
 * distances t0, t1. A NaN (0 * inf) means the origin lies on a slab plane of
 * an axis the ray is parallel to: the ray is then inside that (closed) slab
 * and the axis is ignored. (Fixed from the first draft, where a NaN entry
 * replaced tn and dropped tmin and the axes before it.) */
static inline void rt_slab_axis(float t0, float t1, float *tn, float *tf)
{
    const bool ordered = (t0 == t0) & (t1 == t1);   /* neither is NaN; & keeps it branch-free */
    const float n = rt_maxf(*tn, rt_minf(t0, t1)), f = rt_minf(*tf, rt_maxf(t0, t1));
    *tn = ordered ? n : *tn;
    *tf = ordered ? f : *tf;
}

/* Slab test of one child box against [tmin, tmax]; on a hit *tnear is the
 * entry distance (>= tmin). 6 subtractions, 6 multiplications, 12 compares:
 * the FLOP count the model charges comes from its config, not from here.
 * Axes x, y, z in that order. Not for empty slots (see RT_META_EMPTY). */
static inline bool rt_slab_test(const rt_ray_prep *r, const float lo[3], const float hi[3], float tmin, float tmax,
                                float *tnear)
{
    float tn = tmin, tf = tmax;
    rt_slab_axis((lo[0] - r->org[0]) * r->inv_dir[0], (hi[0] - r->org[0]) * r->inv_dir[0], &tn, &tf);
    rt_slab_axis((lo[1] - r->org[1]) * r->inv_dir[1], (hi[1] - r->org[1]) * r->inv_dir[1], &tn, &tf);
    rt_slab_axis((lo[2] - r->org[2]) * r->inv_dir[2], (hi[2] - r->org[2]) * r->inv_dir[2], &tn, &tf);
    *tnear = tn;
    return tn <= tf;
}

/* Wald's projection test (Wald 2004, sec. 7.1). Accepts a hit when
 * tmin < t < tmax and u, v >= 0, u + v <= 1; *t, *u, *v set on a hit.
 * The division is one op here; the model counts it as 11 FLOPs (paper 3.2). */
static inline bool rt_wald_test(const rt_tri48 *tri, const float org[3], const float dir[3], float tmin, float tmax,
                                float *t_out, float *u_out, float *v_out)
{
    if (tri->flags & 1u)
        return false;
    static const int mod3[5] = {0, 1, 2, 0, 1};
    const int k = (int)tri->k, ku = mod3[k + 1], kv = mod3[k + 2];
    const float nd = 1.0f / (dir[k] + tri->n_u * dir[ku] + tri->n_v * dir[kv]);
    const float t = (tri->n_d - org[k] - tri->n_u * org[ku] - tri->n_v * org[kv]) * nd;
    if (!(tmin < t && t < tmax))
        return false;
    const float hu = org[ku] + t * dir[ku];
    const float hv = org[kv] + t * dir[kv];
    const float beta = hv * tri->b_nu + hu * tri->b_nv + tri->b_d;
    if (beta < 0.0f)
        return false;
    const float gamma = hu * tri->c_nu + hv * tri->c_nv + tri->c_d;
    if (gamma < 0.0f)
        return false;
    if (beta + gamma > 1.0f)
        return false;
    *t_out = t;
    *u_out = beta;
    *v_out = gamma;
    return true;
}

#endif
