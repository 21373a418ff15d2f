/* ist.h — the IST (intersection) unit as a kernel module (paper sec. 3):
 * Wald's ray-triangle test, fully pipelined, fed by the TRVs' leaf FIFOs
 * (round-robin arbiter) and its own loop FIFO; one triangle test issues per
 * cycle. A ray holds the issue stage for its leaf's triangles (one per cycle)
 * and, after the last, travels the pipe (latency ist.latency) back to its
 * TRV for the stack pop. A primitive cache miss invalidates the test: the
 * ray travels the pipe and re-enters through the loop FIFO, resuming at the
 * missed triangle (looping for next chance). FLOPs per test are a parameter
 * (the division counts as 11 FLOPs, paper sec. 3.2). */
#ifndef RTSIM_MODEL_IST_H
#define RTSIM_MODEL_IST_H

#include <stdbool.h>
#include <stdint.h>

#include "config/config.h"
#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/module_desc.h"
#include "kernel/stats.h"
#include "kernel/vcd.h"
#include "model/ray/ist_core.h"
#include "model/ray/pipe_ring.h"
#include "model/ray/pipe_trace.h"
#include "model/ray/trv.h"

#define IST_MAX_TRV 64

typedef struct ist_params {
    uint32_t latency;        /* pipeline stages of a triangle test */
    uint32_t flops_per_test; /* FLOPs of one Wald test, division = 11 */
} ist_params;

typedef struct ist_unit {
    ist_params p;
    ist_core core;
    accel_ray *rays;
    ks_clocked *proc;
    ks_clock *clk;
    uint32_t ntrv, rr;                 /* arbiter: next TRV input to look at first */
    ks_fifo *in[IST_MAX_TRV], *out[IST_MAX_TRV];
    pipe_ring pipe;                    /* test pipeline after issue */
    pipe_ring loop;                    /* exit -> issue loop FIFO (fifo.ray_ist_loop entries) */
    int64_t cur;                       /* ray holding the issue stage, -1 none */
    uint64_t busy_until, bank_stall_cycles;
    uint64_t busy_cycles, flops, rays_in_unit, exit_stall_cycles, issue_stall_cycles;
    bool vcd;                          /* a VCD is open (else every VCD variable is NULL) */
    ks_vcd_var *v_issue_ray, *v_tri, *v_exit_ray;
    pipe_trace stage_rays;             /* the ray of the test in each stage */
} ist_unit;

/* The unit's configuration section [ist] (rtcfg schema; registered by
 * accel_add_schemas). */
extern const rtcfg_schema ist_schema;
extern const ks_module_desc ist_module_desc;

/* Lifecycle: create, connect, register, destroy (docs/design.md). NULL
 * with a message on bad parameters. */
ist_unit *ist_create(const char *name, const ist_params *p, const accel_image *img, accel_ray *rays, ks_sim *sim,
                     ks_clock *clk, uint32_t loop_capacity, uint32_t pipe_capacity, char *err, unsigned errlen);
void ist_destroy(ist_unit *u);   /* NULL is a no-op */
/* in[i]: leaf work from TRV i; out[i]: rays back to TRV i. */
void ist_connect(ist_unit *u, uint32_t ntrv, ks_fifo **in, ks_fifo **out);
void ist_set_probe(ist_unit *u, accel_probe_fn probe, void *ctx);
void ist_set_events(ist_unit *u, accel_event_fn fn, void *user);
/* 0, or -1 when a statistic is not declared in the unit's description
 * (message in ks_stats_error). */
int ist_register(ist_unit *u, const char *name, ks_stats *st, ks_vcd *vcd);

#endif
