/* trv_core.h — the work of one pass of a ray through a TRV pipeline, as a
 * pure function of the ray record, the node bytes and the stack (paper sec. 3,
 * Fig. 3; sec. 3.1 for MBVH). The TRV module (trv.h) adds the timing.
 *
 * One pass, by the ray's phase:
 *   VISIT: probe the node L1 for the target node's N*32 bytes. MISS/BLOCKED
 *     -> LOOP ("looping for next chance", Nah et al. 2014): nothing changes,
 *     the ray goes round again. HIT -> N slab tests (rt_slab_test against
 *     [tmin, closest]) -> sorting network (sort_net.h) -> the nearest hit
 *     child becomes the target (kept in the ray state), the others are pushed
 *     farthest first in one banked-stack operation; nothing hit -> pop as below.
 *   POP (back from the IST, or nothing hit): pop the top entry; with the
 *     distance stack, entries with tnear > closest are culled in the same
 *     operation (one read each); the stack empty -> DONE.
 * The new target is a leaf -> TO_IST, an inner node -> CONTINUE.
 * Occlusion rays (r->occlusion; paper sec. 3.1 "occlusion rays may bypass
 * the sort"): VISIT takes the hit children in slot order instead of through
 * the sorting network (sort_passes and sort_swaps do not count them); a POP
 * pass of a ray that came back from the IST with a hit resets the slot's
 * stack and ends the ray (DONE) without reading an entry.
 * Events (accel_ray.h) are emitted only for committed work, in the
 * reference traversal's order. */
#ifndef RTSIM_MODEL_TRV_CORE_H
#define RTSIM_MODEL_TRV_CORE_H

#include <stdbool.h>
#include <stdint.h>

#include "model/ray/accel_ray.h"
#include "model/ray/sort_net.h"
#include "model/ray/trv_stack.h"

typedef struct trv_core_params {
    int width;               /* N, 2..8 (must equal the image's) */
    bool distance_cull;      /* distance stack (paper 3.1: MBVH only by default) */
    uint32_t slots;          /* ray slots = stacks (paper: 32) */
    uint32_t stack_depth;    /* entries per stack (paper: 64) */
    uint32_t stack_banks;    /* banks of the stack memory (N-1 makes pushes conflict-free) */
} trv_core_params;

typedef enum trv_pass_result {
    TRV_LOOP_MISS,           /* node fetch missed: ray goes round again */
    TRV_LOOP_BLOCKED,        /* node L1 could not take the access this cycle */
    TRV_CONTINUE,            /* next target is an inner node */
    TRV_TO_IST,              /* next target is a leaf */
    TRV_DONE,                /* traversal finished */
    TRV_OVERFLOW             /* stack too small: ray failed */
} trv_pass_result;

typedef struct trv_core_stats {
    uint64_t passes, visits, pop_passes;
    uint64_t loops_miss, loops_blocked;
    uint64_t box_tests;      /* used child slots tested */
    uint64_t box_lanes;      /* lanes active (N per visit; the FPUs work on all) */
    uint64_t sort_passes, sort_swaps;
    uint64_t culls, to_ist, done, overflows;
} trv_core_stats;

typedef struct trv_core {
    trv_core_params p;
    const accel_image *img;
    const sort_net *net;
    trv_stack stack;
    accel_probe_fn probe;
    void *probe_ctx;
    accel_event_fn ev;
    void *ev_user;
    trv_core_stats st;
    uint32_t fetch_cycles;  /* cycles the last node fetch occupied the L1 port (bank conflict > 1) */
    /* Forward-progress guard (docs/accel.md "Livelock guard"; off unless
     * the top level engages it on a starving run): one ray at a time holds
     * the token; the others may use the node L1 only for nodes already
     * present, so no fill of theirs evicts the token ray's lines. */
    bool (*present)(void *ctx, uint64_t addr, uint32_t bytes);   /* side-effect-free probe */
    bool guard;
    int64_t guard_slot;     /* slot of the ray holding the token, -1: free */
} trv_core;

/* False with a message on bad parameters (width mismatch, sizes). */
bool trv_core_init(trv_core *c, const trv_core_params *p, const accel_image *img, accel_probe_fn probe,
                   void *probe_ctx, char *err, unsigned errlen);
void trv_core_free(trv_core *c);

/* One pass of ray r (which owns stack slot r->slot) at cycle now; *stack_cycles
 * gets the cycles the stack operation occupies the stack stage (0 if none). */
trv_pass_result trv_core_pass(trv_core *c, accel_ray *r, uint64_t now, uint32_t *stack_cycles);

#endif
