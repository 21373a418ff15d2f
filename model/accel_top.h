/* accel_top.h — the one top-level assembly of the accelerator (paper Fig. 2):
 * creates the kernel simulation, the 500 MHz clock, the scheduler, trv.count
 * TRV units, the IST, the memory hierarchy (node L1 per TRV, shared node L2,
 * primitive cache, memory) and every FIFO between them; turns on the
 * deadlock detector; registers every statistic (with unit and description)
 * and, when asked, a VCD of all units (scopes per unit: FIFO occupancies,
 * unit states, ray ids at the issue/exit stages) with a time window and a
 * signal filter.
 *
 * Contract: accel_top_create() validates the configuration against the
 * image (width) and returns NULL with a message naming the key on error.
 * accel_top_run() runs the frame to completion: 0 when every ray completed,
 * 1 on a simulation failure (deadlock: the report names who waits on whom;
 * livelock: no node visit, triangle test or completed ray for
 * sched.watchdog_cycles + the machine's longest wait; a ray whose stack
 * overflowed: "stack too small", naming trv.stack_depth). Half-way to the
 * watchdog it engages the TRVs' livelock guard (trv_core.h) and says so in
 * the summary; a run that never starves is unaffected.
 * Results are deterministic (same inputs -> same cycles and statistics). */
#ifndef RTSIM_MODEL_ACCEL_TOP_H
#define RTSIM_MODEL_ACCEL_TOP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <stdio.h>

#include "kernel/module_desc.h"
#include "kernel/sim.h"
#include "kernel/stats.h"
#include "model/accel_config.h"
#include "model/energy/energy.h"
#include "model/mem/mem_arbiter.h"
#include "model/ray/accel_ray.h"
#include "config/config.h"
#include "model/ray/scheduler.h"
#include "model/series.h"

typedef struct accel_top accel_top;

typedef struct accel_top_opts {
    const char *vcd_path;          /* NULL: no VCD */
    uint64_t vcd_begin_cycle, vcd_end_cycle;   /* window [begin, end); end 0 = to the end */
    const char *vcd_filter;        /* comma-separated globs, NULL = all */
    accel_event_fn events;         /* per-ray event log (NULL: none) */
    void *events_user;
    uint64_t deadlock_cycles;      /* kernel detector margin; 0 = default (100000); the window is
                                      the margin + the machine's longest wait (docs/accel.md) */
    bool exhaustive;               /* step every unit every cycle on every clock (no idle
                                      skipping): the reference mode results must equal */
    accel_series *series;          /* interval statistics (model/series.h), NULL: none; the
                                      caller keeps it and destroys it after the top */
} accel_top_opts;

/* Called between run slices (every ~64K cycles) for progress bars. */
typedef void (*accel_progress_fn)(void *user, uint64_t cycle, uint64_t rays_done, uint64_t rays_admitted);

accel_top *accel_top_create(const rtcfg *cfg, const accel_image *img, const accel_source *src,
                            const accel_top_opts *opts, char *err, size_t errlen);
int accel_top_run(accel_top *t, accel_progress_fn progress, void *user, char *err, size_t errlen);
void accel_top_destroy(accel_top *t);

/* After a run. */
uint64_t accel_top_cycles(const accel_top *t);     /* cycles of the frame (to the last completion) */
uint64_t accel_top_rays(const accel_top *t);       /* rays completed */
double accel_top_mrps(const accel_top *t);         /* rays / simulated second / 1e6 at the machine clock */
ks_stats *accel_top_stats(accel_top *t);           /* every statistic */

/* The most TRVs a machine has (trv.count's range, model/ray/trv.c). */
enum { ACCEL_MAX_TRV = 64 };

/* Accesses, hits and line fills of a cache level (the cache's statistics
 * of those names). */
typedef struct accel_cache_figures {
    uint64_t accesses, hits, fills;
} accel_cache_figures;

/* The figures of a run, typed: each is read from the field of the unit
 * that counts it, the field its statistic in the registry references (the
 * statistic's name in brackets), so a renamed field fails to compile
 * instead of reading as 0. The units' counts are live (so far into the
 * run); the frame's figures (top level) are set when the run ends, the
 * energy figures when it was last computed. The energy adapter, the
 * summary and the fidelity levels (fidelity/model_run.c) read these. */
typedef struct accel_figures {
    /* top level (accel_top.c), the frame */
    uint64_t cycles;               /* [cycles] cycles of the frame */
    uint64_t rays;                 /* [rays] rays completed */
    double mrps;                   /* [mrps] million rays per second at the machine clock */
    uint64_t dram_bytes;           /* [dram_bytes] main memory bytes of the frame */
    double dram_gbs;               /* [dram_bandwidth_gbs] mean main memory bandwidth, GB/s */
    double in_flight_mean;         /* [rays_in_flight_mean] time-averaged rays in flight */
    uint64_t dram_node_bytes, dram_triangle_bytes;   /* [dram_node_bytes, dram_triangle_bytes] by kind */
    uint64_t dram_footprint_bytes, dram_refetch_bytes; /* [dram_footprint_bytes, dram_refetch_bytes] by cause */
    uint64_t dram_compulsory_misses, dram_refetch_misses; /* [dram_compulsory_misses, dram_refetch_misses] fills */
    double dram_pj_per_byte;       /* [dram_pj_per_byte] DRAM energy per byte, pJ */
    /* scheduler (model/ray/scheduler.h) */
    uint64_t primaries, bounces;   /* [sched.primaries, sched.bounces] rays taken of each kind */
    uint64_t failed;               /* [sched.failed] rays whose traversal stack overflowed */
    bool occlusion;                /* an occlusion run: the two figures below are registered */
    uint64_t occlusion_rays, occluded; /* [sched.occlusion_rays, sched.occluded] */
    uint64_t max_in_flight;        /* [sched.max_in_flight] most rays in flight at once */
    double latency_mean;           /* [sched.latency_mean] mean ray latency, cycles */
    /* TRVs (model/ray/trv.h): per unit, then summed over the units */
    uint32_t trv_count;
    uint64_t trv_busy_cycles[ACCEL_MAX_TRV]; /* [trvI.busy_cycles] cycles TRV I issued */
    uint64_t trv_flops;            /* [trvI.flops] slab-test FLOPs */
    uint64_t trv_sort_passes;      /* [trvI.sort_passes] passes through the sorting network */
    uint64_t trv_stack_pops, trv_stack_pushes; /* [trvI.stack_pops, trvI.stack_pushes] stack accesses */
    uint64_t trv_issue_loop;       /* [trvI.issue_loop] rays issued from the loop ring (its writes) */
    /* IST (model/ray/ist.h) */
    uint64_t ist_busy_cycles;      /* [ist.busy_cycles] cycles the IST issued */
    uint64_t ist_flops;            /* [ist.flops] triangle-test FLOPs */
    uint64_t ist_loops_miss, ist_loops_blocked; /* [ist.loops_miss, ist.loops_blocked] rays sent round its ring */
    /* caches (model/mem/cache_core.h): the node L1s summed, node L2, primitive cache */
    accel_cache_figures node_l1, node_l2, prim; /* [node_l1_I.*, node_l2.*, prim.*] */
    /* the memory arbiter (model/mem/mem_arbiter.h), input 0 the node L2, 1 the primitive cache */
    mem_arbiter_input_stats mem_arbiter[2]; /* [mem_arbiter.bytes_I, footprint_bytes_I, first_touch_I, refetches_I] */
    /* the memory (model/mem/fixed_mem.h or mem_dram_adapter.h) */
    uint64_t mem_requests;         /* [memory.requests] requests that reached the memory */
    uint64_t mem_latency_sum;      /* [memory.latency_sum] their summed latencies, cycles */
    bool lpddr3;                   /* the LPDDR3 model: row_hit_rate is registered */
    double row_hit_rate;           /* [dram.row_hit_rate] row hits / row accesses (model/dram/dram_port.h) */
    bool dram_energy;              /* the energy model prices the LPDDR3 power: the two below are set */
    double dram_energy_uJ, dram_background_uJ; /* [dram.energy_uJ, dram.background_energy_uJ] */
    /* energy (model/energy/energy.h), with an energy model */
    bool energy;
    double energy_mj;              /* [energy_mj] energy of the frame, mJ */
    double unit_mj[EU_COUNT];      /* [energy.U_mj] per unit (energy.h order), mJ */
    double unit_dynamic_mj[EU_COUNT], unit_static_mj[EU_COUNT]; /* [energy.U_dynamic_mj, energy.U_static_mj] */
} accel_figures;

/* Fills *out with the run's figures so far (every field; those a machine
 * does not have are 0 and their flags false). */
void accel_top_figures(const accel_top *t, accel_figures *out);

/* A point of a run, for interval sampling (fidelity/windowed.c): counts from
 * the start of the run to `cycle`. */
typedef struct accel_point {
    bool finished;                 /* the frame ended before the mark */
    uint64_t cycle;                /* where the run stopped */
    uint64_t primaries;            /* primary rays the scheduler has taken */
    uint64_t completed, latency_sum; /* rays completed, their summed latencies (cycles) */
    double dram_bytes;
    /* line fills of the caches backed by memory (node L2, primitive cache),
     * and those into an invalid way: a cache started empty whose set was
     * not yet full, where a warm cache would have had an older line */
    uint64_t backed_fills, backed_cold_fills;
    energy_activity act;           /* energy activity so far (model/energy/energy.h) */
} accel_point;

/* Runs on until the scheduler has taken `primaries` primary rays (it checks
 * every few hundred cycles, so *p says where it really stopped) or the
 * frame ends (p->finished), and fills *p. The run may go on with another
 * call; accel_top_run() is not called after it. 0, or 1 on a simulation
 * failure (as accel_top_run). */
int accel_top_run_until(accel_top *t, uint64_t primaries, accel_point *p, char *err, size_t errlen);
/* Energy of the interval between two points of one run, unit by unit (the
 * run's energy model's result: mJ, mW over the interval, mm2), or NULL
 * without an energy model. Overwrites the run's energy figures, so only for
 * runs that are not reported themselves; valid until the next call. */
const energy_result *accel_top_interval_energy(accel_top *t, const accel_point *a, const accel_point *b);
const accel_params *accel_top_params(const accel_top *t);
/* Functional warming (fidelity/windowed.c): before the run starts, the
 * machine's caches take the contents (tags and LRU order) of the given
 * cores of the same geometry: l1[0..nl1) the TRVs' node L1s, then the node
 * L2 and the primitive cache (NULL: left empty). Statistics are not
 * touched. 0, or -1 when a geometry differs or nl1 is not the TRV count. */
struct cache_core;
int accel_top_warm_caches(accel_top *t, const struct cache_core *const *l1, int nl1, const struct cache_core *l2,
                          const struct cache_core *prim);
/* Samples no more into opts->series (which may then be destroyed). */
void accel_top_detach_series(accel_top *t);
uint64_t accel_top_guard_cycle(const accel_top *t); /* where the livelock guard engaged, 0: never */
/* Writes the human-readable summary: cycles, MRPS, per-unit utilization,
 * cache hit rates, DRAM traffic and bandwidth, rays in flight. */
void accel_top_print_summary(accel_top *t, FILE *out);

/* FIFO auto-sizing (paper sec. 3): sets every FIFO key of cfg to the first
 * power of two above the largest occupancy seen by the FIFOs it sizes, but
 * never below its deadlock-free minimum (accel_config.h).
 * Returns 0, or -1 with a message. */
int accel_top_autosize(const accel_top *t, rtcfg *cfg, char *err, size_t errlen);

/* The top level's own statistics (cycles, rays, mrps, ...). */
extern const ks_module_desc accel_top_module_desc;

/* Module description tables of every unit (for --help-module NAME). */
const ks_module_desc *accel_module_desc(const char *name);
void accel_module_list(FILE *out);

#endif
