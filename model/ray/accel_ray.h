/* accel_ray.h — what travels through the accelerator: the memory image the
 * units fetch from, the rays handed in by the tracer (which lives outside the
 * model), the per-ray record a TRV keeps in its ray slot (and which rides
 * along to the IST and back), hits, and the per-ray event callback.
 *
 * Contract: the event kinds and their a/b/t fields are those of the
 * reference traversal (tracer/trace/traverse.h, rt_trv_event_kind, same numbering),
 * emitted in the same per-ray order, only for work that commits (a pass whose
 * memory access missed emits nothing). model/ cannot include traverse.h, so
 * the numbering is repeated here; the system testbench checks it matches. */
#ifndef RTSIM_MODEL_ACCEL_RAY_H
#define RTSIM_MODEL_ACCEL_RAY_H

#include <stdbool.h>
#include <stdint.h>

#include "model/mem/cache_core.h"
#include "tracer/bvh/bvh_layout.h"

#define ACCEL_NO_HIT UINT32_MAX

/* The bytes in simulated memory (same fields as tracer/bvh/bvh.h's image). */
typedef struct accel_image {
    const uint8_t *bytes;
    uint64_t size;
    uint64_t node_base, tri_base;
    int width;               /* N: children per node */
    uint32_t node_bytes;     /* N * 32 */
    uint32_t nnodes, ntris;
} accel_image;

/* One ray as the tracer made it (tracer/trace/ray.h's rt_ray, field for field). */
typedef struct accel_ray_in {
    float org[3], dir[3];
    float tmin, tmax;
    uint32_t pixel;
    uint8_t bounce;
    uint8_t occlusion;       /* 1: occlusion ray (any hit ends it, no sort; docs/accel.md) */
} accel_ray_in;

typedef struct accel_hit {
    float t, u, v;
    uint32_t prim;           /* mesh triangle, or ACCEL_NO_HIT */
} accel_hit;

enum accel_event_kind {
    ACCEL_EV_VISIT, ACCEL_EV_PUSH, ACCEL_EV_POP, ACCEL_EV_CULL, ACCEL_EV_LEAF, ACCEL_EV_TRI, ACCEL_EV_DONE
};
/* uid: the ray's admission number (0, 1, ... in admission order). */
typedef void (*accel_event_fn)(void *user, uint32_t uid, int kind, uint32_t a, uint32_t b, float t);

/* A synchronous cache probe (model/mem/cache_core.h protocol: HIT, MISS, BLOCKED). */
/* *cycles (set on a hit): cycles the access occupies the port (bank
 * conflicts: > 1 stalls the requester). */
typedef cache_result (*accel_probe_fn)(void *ctx, uint64_t addr, uint32_t bytes, uint64_t now, uint32_t *cycles);

typedef enum accel_ray_phase {
    RAY_VISIT,     /* target is an inner node to fetch and test */
    RAY_LEAF,      /* target is a leaf: triangles tri_next..tri_end to test in the IST */
    RAY_POP,       /* leaf done (or nothing hit): next target comes from the stack */
    RAY_DONE,
    RAY_FAILED     /* stack overflow: the stack is too small for the scene */
} accel_ray_phase;

typedef struct accel_ray {
    rt_ray_prep prep;        /* origin and 1/dir for the slab tests */
    float dir[3];
    float tmin, closest;     /* closest = tmax until a hit shrinks it */
    float u, v;
    uint32_t prim;           /* ACCEL_NO_HIT until a hit */
    uint32_t target_ref, target_meta;
    uint32_t tri_next, tri_end;
    uint8_t phase;           /* accel_ray_phase */
    uint8_t bounce;
    uint8_t occlusion;       /* 1: occlusion ray: the TRV bypasses the sort, the IST's first hit ends it */
    uint16_t trv;            /* owning TRV and its stack slot */
    uint32_t slot;
    uint32_t uid, pixel;
    uint64_t admit_cycle;
    uint32_t visits, tri_tests, loops;   /* per-ray activity (heatmaps) */
} accel_ray;

/* Fills a ray record for a new traversal from the root (node 0). */
static inline void accel_ray_start(accel_ray *r, const accel_ray_in *in, uint32_t uid)
{
    rt_ray_prepare(in->org, in->dir, &r->prep);
    for (int a = 0; a < 3; a++)
        r->dir[a] = in->dir[a];
    r->tmin = in->tmin;
    r->closest = in->tmax;
    r->u = r->v = 0;
    r->prim = ACCEL_NO_HIT;
    r->target_ref = 0;
    r->target_meta = 0;
    r->tri_next = r->tri_end = 0;
    r->phase = RAY_VISIT;
    r->bounce = in->bounce;
    r->occlusion = in->occlusion;
    r->uid = uid;
    r->pixel = in->pixel;
    r->visits = r->tri_tests = r->loops = 0;
}

#endif
