/* trv.h — the TRV (traversal) unit as a kernel module (paper sec. 3, Fig. 3;
 * MBVH variant sec. 3.1): a clocked process around trv_core (the pass logic).
 *
 * Pipeline: issue stage (one ray per cycle) -> fetch (node L1 probe) -> slab
 * tests -> sorting network (one stage per layer: 1 for BVH2's compare-swap, 3
 * for MBVH4) -> stack -> next state. The pass is computed at issue (the unit
 * is execution-driven on the node bytes) and the ray travels the remaining
 * stages in the pipe (pipe_ring.h, exit depth - 1 cycles later). At the exit stage the ray
 * goes to: the loop FIFO (next node, or "looping for next chance" after a
 * node L1 miss), the IST (leaf), or the scheduler (done). A stack operation
 * needing k > 1 bank cycles stalls issue for k - 1 cycles.
 * Occlusion rays bypass the sorting network (paper sec. 3.1): every pass of
 * one leaves the pipe sort-layers cycles earlier (latency_bypass), in order
 * behind any slower ray ahead of it (pipe_ring.h). The VCD's per-stage ray
 * variables still show such a ray at issue + k (as if it went through the
 * sort stages); issue_ray and exit_ray show its real cycles.
 * Issue priority: rays back from the IST, then looping rays, then new rays.
 * Ports (FIFOs of trv_msg, created by the top level): in_new (scheduler),
 * in_ist (IST returns), out_ist (leaf work), out_done (to the scheduler);
 * pipe and loop are internal. Returns progress per step; sleeps otherwise. */
#ifndef RTSIM_MODEL_TRV_H
#define RTSIM_MODEL_TRV_H

#include <stdbool.h>
#include <stdint.h>

#include "config/config.h"
#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/module_desc.h"
#include "kernel/stats.h"
#include "kernel/vcd.h"
#include "model/ray/pipe_ring.h"
#include "model/ray/pipe_trace.h"
#include "model/ray/trv_core.h"

/* What travels on ray FIFOs: the index of the ray's record (accel_ray table;
 * the record stands for the ray data the hardware moves) and, in the pipe,
 * the pass result. */
typedef struct trv_msg {
    uint32_t ray;
    uint32_t result;
} trv_msg;

typedef struct trv_params {
    trv_core_params core;
    uint32_t stages_fetch;   /* node L1 tag + data */
    uint32_t stages_box;     /* slab test FP pipeline */
    uint32_t stages_stack;
    uint32_t stages_next;    /* next-state decision */
    uint32_t box_flops;      /* FLOPs per slab test lane */
} trv_params;

typedef struct trv_unit {
    trv_params p;
    uint32_t id;
    uint32_t depth;          /* total pipeline stages */
    uint32_t latency_bypass; /* issue to exit of an occlusion ray: depth - 1 - sort layers */
    trv_core core;
    accel_ray *rays;         /* the top level's ray table */
    ks_clocked *proc;
    ks_clock *clk;
    ks_fifo *in_new, *in_ist, *out_ist, *out_done;
    pipe_ring pipe;          /* stages after issue */
    pipe_ring loop;          /* exit -> issue loop FIFO (fifo.ray_trv_loop entries) */
    uint64_t busy_until;     /* issue stalled by a multi-cycle stack operation */
    /* statistics */
    uint64_t busy_cycles, issue_new, issue_ist, issue_loop, exit_stall_cycles, stack_stall_cycles;
    uint64_t flops, rays_in_unit;
    bool failed;             /* a ray overflowed its stack */
    /* VCD (NULL when off) */
    bool vcd;                /* a VCD is open (else every variable below is NULL) */
    ks_vcd_var *v_issue_ray, *v_exit_ray, *v_state, *v_rays;
    pipe_trace stage_rays;   /* the ray in each stage after issue */
} trv_unit;

/* The unit's configuration section [trv] (rtcfg schema; registered by
 * accel_add_schemas). */
extern const rtcfg_schema trv_schema;
extern const ks_module_desc trv_module_desc;

/* Pipeline depth for params: fetch + box + sort layers + stack + next. */
uint32_t trv_pipeline_depth(const trv_params *p);

/* Lifecycle (every unit's verbs, docs/design.md "Adding a unit"): create,
 * connect its port FIFOs, register its statistics, destroy.
 * trv_create makes the unit's process on clk, its pipeline and its loop
 * FIFO; NULL with a message on bad parameters. The port FIFOs must be
 * connected before the run. */
trv_unit *trv_create(uint32_t id, const char *name, const trv_params *p, const accel_image *img, accel_ray *rays,
                     ks_sim *sim, ks_clock *clk, uint32_t loop_capacity, char *err, unsigned errlen);
void trv_connect(trv_unit *t, ks_fifo *in_new, ks_fifo *in_ist, ks_fifo *out_ist, ks_fifo *out_done);
void trv_set_probe(trv_unit *t, accel_probe_fn probe, void *ctx);
void trv_set_events(trv_unit *t, accel_event_fn fn, void *user);
/* Registers statistics under "<name>." and, when a VCD is open, the unit's
 * variables (state, ray ids at issue, in each pipeline stage and at exit,
 * rays held). */
/* 0, or -1 when a statistic is not declared in the unit's description
 * (message in ks_stats_error). */
int trv_register(trv_unit *t, const char *name, ks_stats *st, ks_vcd *vcd);
void trv_destroy(trv_unit *t);   /* NULL is a no-op */

#endif
