/* traverse.h — reference traversal: exactly the hardware's algorithm, in
 * software, on the bytes of a memory image (tracer/bvh/bvh.h). The hardware model
 * must reproduce its hits and its event sequence per ray exactly.
 *
 * Algorithm (paper sec. 3 and 3.1), width N, ray [tmin, tmax):
 *   cur = root (node 0); stack empty; closest = tmax
 *   VISIT(cur): slab-test every used slot with [tmin, closest] (rt_slab_test);
 *     order the hit children by (tnear, slot index) ascending (the sorting
 *     network; for N = 2 the compare-swap: slot 1 first only if its tnear is
 *     strictly smaller);
 *     none hit -> POP;
 *     else the nearest becomes the next target and the others are PUSHed
 *     farthest first (so the second nearest is on top), each with its tnear;
 *     the next target is a leaf -> LEAF, else VISIT it.
 *   LEAF(first, count): rt_wald_test each triangle in order with
 *     [tmin, closest]; a hit sets closest = t (strictly closer only, so the
 *     first of equal distances wins); then POP.
 *   POP: stack empty -> DONE. Else take the top entry; with the distance stack
 *     (params.distance_cull, on for N > 2 by default, paper 3.1) an entry whose
 *     tnear > closest is discarded (CULL) and POP repeats; otherwise the entry
 *     is the next target (LEAF or VISIT).
 * Occlusion rays (ray->occlusion, any-hit; the paper's sec. 3.1: "occlusion
 * rays may bypass the sort"): the same algorithm with two changes, which the
 * hardware model makes too (docs/accel.md "Occlusion rays"):
 *   VISIT: no sorting network: the hit children are taken in slot order
 *     (the lowest hit slot is the next target, the others are PUSHed highest
 *     slot first, so the next lowest is on top);
 *   LEAF: the first triangle that hits ends the ray: its TRI (b = 1), then
 *     DONE with that primitive and distance; the rest of the leaf and the
 *     stack are dropped.
 *   closest stays tmax until that hit, so the distance stack never culls.
 * Stack depth is bounded (default 64, the paper's); an overflow is an error
 * for the ray ("stack too small for the scene"), never silent: rt_trace_ray
 * returns false and the event stream ends without DONE.
 * Each step is reported through an optional event callback (trace logs, tests):
 * VISIT, then that node's PUSHes (farthest first), then the nearest child as
 * VISIT or LEAF (or POP/CULL/DONE when no child was hit); LEAF is followed by
 * one TRI per triangle; DONE is last. Events and counts never change a result.
 * Implementation and measured figures: tracer/trace/traverse.c, docs/tracer-bvh.md. */
#ifndef RTSIM_TRACER_TRAVERSE_H
#define RTSIM_TRACER_TRAVERSE_H

#include <stdbool.h>
#include <stdint.h>

#include "tracer/bvh/bvh.h"
#include "tracer/trace/ray.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RT_STACK_DEPTH_DEFAULT 64

typedef enum rt_trv_event_kind {
    RT_EV_VISIT,   /* a = node index */
    RT_EV_PUSH,    /* a = ref, b = meta (count for a leaf, 0 inner), t = tnear */
    RT_EV_POP,     /* a, b, t of the popped entry that will be processed */
    RT_EV_CULL,    /* a, b, t of a popped entry discarded by the distance stack */
    RT_EV_LEAF,    /* a = first triangle index, b = count */
    RT_EV_TRI,     /* a = triangle index (in leaf order), b = 1 if it became the closest hit, t = closest after */
    RT_EV_DONE     /* a = mesh primitive hit or RT_NO_HIT, t = closest */
} rt_trv_event_kind;

typedef struct rt_trv_event {
    uint8_t kind;      /* rt_trv_event_kind */
    uint32_t a, b;
    float t;
} rt_trv_event;

typedef void (*rt_trv_event_fn)(void *user, const rt_trv_event *ev);

typedef struct rt_trv_params {
    int stack_depth;     /* 1..4096; default RT_STACK_DEPTH_DEFAULT */
    bool distance_cull;  /* distance stack; default: width > 2 */
} rt_trv_params;

void rt_trv_params_default(rt_trv_params *p, int width);

/* Per-ray counts (summed by callers for frame statistics): box_tests = used
 * slots slab-tested; pops = popped entries processed, culls = popped entries
 * discarded (pushes = pops + culls on a completed ray); max_stack = deepest
 * stack after a visit's pushes. */
typedef struct rt_trv_counts {
    uint32_t visits, box_tests, leaves, tri_tests, pushes, pops, culls, max_stack;
} rt_trv_counts;

/* Traces one ray. Returns false only on stack overflow (hit then holds the
 * closest found so far). counts and fn may be NULL. */
bool rt_trace_ray(const rt_bvh_image *img, const rt_trv_params *p, const rt_ray *ray, rt_hit *hit,
                  rt_trv_counts *counts, rt_trv_event_fn fn, void *user);

#ifdef __cplusplus
}
#endif

#endif
