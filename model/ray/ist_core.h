/* ist_core.h — the work of one IST issue slot: one ray-triangle test of
 * Wald's projection method (rt_wald_test, tracer/bvh/bvh_layout.h) on a 48-byte
 * triangle fetched through the primitive cache (paper sec. 3). The IST
 * module (ist.h) adds the pipeline timing.
 *
 * The unit is fully pipelined: a leaf's triangles issue on consecutive
 * cycles, each tested against the closest hit known at issue. Results are
 * written back in order and a hit only replaces a strictly closer one, so the
 * outcome equals the reference's sequential loop (a stale, larger tmax can
 * only let through a t that the in-order write-back then rejects).
 * A triangle fetch that misses invalidates that test: the ray loops and
 * resumes at that triangle later (looping for next chance).
 * An occlusion ray's first hit ends its leaf: the test returns IST_LAST and
 * the ray goes back to its TRV, which ends it (trv_core.h). The model knows
 * the hit at issue (as it knows every result at issue); a hardware IST would
 * learn it at the comparator stage and squash the leaf's later tests, so the
 * model is optimistic by at most leaf size - 1 issue cycles per occluded
 * ray (docs/accel.md "Occlusion rays"). */
#ifndef RTSIM_MODEL_IST_CORE_H
#define RTSIM_MODEL_IST_CORE_H

#include <stdint.h>

#include "model/ray/accel_ray.h"

typedef enum ist_result {
    IST_MORE,          /* tested; the leaf has more triangles */
    IST_LAST,          /* tested the leaf's last triangle: ray returns to its TRV to pop */
    IST_LOOP_MISS,     /* primitive cache miss: test invalidated */
    IST_LOOP_BLOCKED   /* primitive cache could not take the access */
} ist_result;

typedef struct ist_core_stats {
    uint64_t tests, hits, closer, loops_miss, loops_blocked, leaves;
} ist_core_stats;

typedef struct ist_core {
    const accel_image *img;
    accel_probe_fn probe;
    void *probe_ctx;
    accel_event_fn ev;
    void *ev_user;
    ist_core_stats st;
    uint32_t port_cycles;   /* cycles the last hit occupied the cache port (bank conflict > 1) */
} ist_core;

/* Tests triangle r->tri_next of the ray's leaf (phase RAY_LEAF). */
ist_result ist_core_test(ist_core *c, accel_ray *r, uint64_t now);

#endif
