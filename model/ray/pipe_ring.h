/* pipe_ring.h — the stages of a unit's pipeline after its issue stage, as a
 * ring of in-flight items each leaving at a fixed exit cycle (issue + depth).
 * A pipeline is not a channel between units, so it needs no kernel FIFO and
 * no kernel events: the owning process stays awake while items are inside
 * (or sleeps until the head's exit cycle). In order; one entry per stage. */
#ifndef RTSIM_MODEL_PIPE_RING_H
#define RTSIM_MODEL_PIPE_RING_H

#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>

#include "kernel/vcd.h"

typedef struct pipe_item {
    uint32_t ray, result;
    uint64_t exit_cycle;
} pipe_item;

typedef struct pipe_ring {
    pipe_item *items;
    uint32_t cap, head, count, max_count;
    uint32_t mask;           /* storage is a power of two >= cap: index by mask, no wrap test */
    uint32_t latency;        /* cycles from issue to exit */
    ks_vcd_var *v_occ;       /* occupancy in the VCD (NULL: off) */
} pipe_ring;

static inline bool pipe_ring_init(pipe_ring *p, uint32_t cap, uint32_t latency)
{
    p->cap = cap ? cap : 1;
    uint32_t size = 1;
    while (size < p->cap)
        size <<= 1;
    p->mask = size - 1;
    p->items = calloc(size, sizeof *p->items);
    p->head = p->count = p->max_count = 0;
    p->latency = latency;
    p->v_occ = NULL;
    return p->items != NULL;
}
static inline void pipe_ring_free(pipe_ring *p)
{
    free(p->items);
    p->items = NULL;
}
static inline bool pipe_ring_full(const pipe_ring *p) { return p->count == p->cap; }
/* The head item if it has reached its exit cycle, else NULL. */
static inline const pipe_item *pipe_ring_ready(const pipe_ring *p, uint64_t cycle)
{
    return p->count && p->items[p->head].exit_cycle <= cycle ? &p->items[p->head] : NULL;
}
/* Exit cycle of the head (UINT64_MAX when empty). */
static inline uint64_t pipe_ring_next_exit(const pipe_ring *p)
{
    return p->count ? p->items[p->head].exit_cycle : UINT64_MAX;
}
/* An item with a latency of its own (a ray that skips stages, e.g. the
 * TRV's sort bypass): the ring stays in order, so an item whose exit cycle
 * comes before that of the one ahead of it leaves right after that one.
 * vcd false: the caller knows no VCD variable is set (a unit without a VCD). */
static inline __attribute__((always_inline)) void pipe_ring_push_lat_v(pipe_ring *p, uint32_t ray, uint32_t result,
                                                                       uint64_t cycle, uint32_t latency, bool vcd)
{
    pipe_item *it = &p->items[(p->head + p->count) & p->mask];   /* no division: this runs every cycle */
    it->ray = ray;
    it->result = result;
    it->exit_cycle = cycle + latency;
    if (++p->count > p->max_count)
        p->max_count = p->count;
    if (vcd && p->v_occ)
        ks_vcd_set(p->v_occ, p->count);
}
/* An item with the ring's latency. */
static inline __attribute__((always_inline)) void pipe_ring_push_v(pipe_ring *p, uint32_t ray, uint32_t result,
                                                                   uint64_t cycle, bool vcd)
{
    pipe_ring_push_lat_v(p, ray, result, cycle, p->latency, vcd);
}
static inline __attribute__((always_inline)) pipe_item pipe_ring_pop_v(pipe_ring *p, bool vcd)
{
    pipe_item it = p->items[p->head];
    p->head = (p->head + 1) & p->mask;
    p->count--;
    if (vcd && p->v_occ)
        ks_vcd_set(p->v_occ, p->count);
    return it;
}

#endif
