/* scheduler.h — the ray scheduler (paper sec. 3): gives rays free ray slots
 * (trv.count x trv.slots, 128 by default) and feeds each pixel's next bounce
 * only when its previous ray has completed (paper sec. 3.2: "Secondary rays
 * are fed to the processor when the preceding ray is complete"); the shading
 * that makes the bounce ray happens outside the accelerator and takes
 * sched.shade_latency cycles. Rays come from a source (the tracer, outside
 * the model) through callbacks. Admission: up to sched.admit_per_cycle rays
 * per cycle, ready bounce rays before new primary rays, TRVs round-robin.
 * Per-ray latency (admission to completion) is recorded; a watchdog stops the
 * run with a report when rays are in flight but none completes for
 * sched.watchdog_cycles (e.g. a memory that never answers). */
#ifndef RTSIM_MODEL_SCHEDULER_H
#define RTSIM_MODEL_SCHEDULER_H

#include <stdbool.h>
#include <stdint.h>

#include "config/config.h"
#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/module_desc.h"
#include "kernel/stats.h"
#include "kernel/vcd.h"
#include "model/ray/accel_ray.h"
#include "model/ray/trv.h"

/* The ray source: primary rays by index; the bounce after a completed ray. */
typedef struct accel_source {
    void *user;
    uint64_t primary_count;
    /* The workload has occlusion rays: the scheduler then registers their
     * statistics (occlusion_rays, occluded); other runs' outputs are unchanged. */
    bool occlusion;
    /* Writes primary ray i (i < primary_count). */
    void (*primary)(void *user, uint64_t i, accel_ray_in *out);
    /* The next ray of the same pixel after `in` completed with `hit`, or
     * false when the path ends (may be NULL: primary rays only). */
    bool (*bounce)(void *user, const accel_ray_in *in, const accel_hit *hit, accel_ray_in *out);
    /* Called for every completed ray with its admission and completion cycle
     * (may be NULL); failed = stack overflow. */
    void (*complete)(void *user, uint32_t uid, const accel_ray_in *in, const accel_hit *hit, uint64_t admit,
                     uint64_t done, uint32_t visits, uint32_t tri_tests, bool failed);
} accel_source;

typedef struct sched_params {
    uint32_t admit_per_cycle;     /* rays admitted per cycle */
    uint32_t shade_latency;       /* cycles from completion to the bounce ray being ready */
    uint64_t watchdog_cycles;     /* 0 = off */
} sched_params;

typedef struct sched_pending {
    accel_ray_in ray;
    uint64_t ready;
} sched_pending;

typedef struct sched_unit {
    sched_params p;
    accel_source src;
    accel_ray *rays;              /* ntrv * slots records; record = trv * slots + slot */
    accel_ray_in *ray_in;         /* the ray as handed in, per record (for the bounce) */
    uint32_t ntrv, slots;
    uint32_t *free_slots;         /* per TRV stack of free slot numbers */
    uint32_t *nfree;
    uint32_t rr;
    sched_pending *pend;          /* ring of bounce rays waiting (<= ntrv * slots) */
    uint32_t pend_head, pend_count;
    uint64_t next_primary, next_uid;
    ks_clocked *proc;
    ks_clock *clk;
    ks_fifo *to_trv[64];
    ks_fifo *from_trv[64];
    uint64_t last_complete_cycle;
    bool watchdog_fired, any_failed;
    /* statistics */
    uint64_t admitted, primaries, bounces, completed, failed, in_flight, max_in_flight;
    uint64_t occlusion_rays, occluded;   /* completed occlusion rays, and those that hit */
    uint64_t latency_sum, latency_max, admit_stall_cycles;
    uint64_t in_flight_area, last_area_cycle; /* for mean rays in flight */
    ks_histogram *lat_hist;
    ks_vcd_var *v_in_flight, *v_admit_ray, *v_done_ray;
} sched_unit;

/* The unit's configuration section [sched] (rtcfg schema; registered by
 * accel_add_schemas). */
extern const rtcfg_schema sched_schema;
extern const ks_module_desc sched_module_desc;

/* Lifecycle: create, connect, register, destroy (docs/design.md). NULL
 * with a message on bad parameters. */
sched_unit *sched_create(const char *name, const sched_params *p, const accel_source *src, accel_ray *rays,
                         uint32_t ntrv, uint32_t slots, ks_clock *clk, char *err, unsigned errlen);
void sched_connect(sched_unit *s, ks_fifo **to_trv, ks_fifo **from_trv);
/* 0, or -1 when a statistic is not declared (message in ks_stats_error). */
int sched_register(sched_unit *s, const char *name, ks_stats *st, ks_vcd *vcd);
/* True when every ray has been admitted and completed. */
bool sched_finished(const sched_unit *s);
/* Mean rays in flight up to cycle `now`. */
double sched_mean_in_flight(const sched_unit *s, uint64_t now);
/* Mean latency of the rays completed so far, cycles (0 before the first). */
double sched_latency_mean(const sched_unit *s);
void sched_destroy(sched_unit *s);   /* NULL is a no-op */

#endif
