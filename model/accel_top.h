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
