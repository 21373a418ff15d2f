/* accel_config.h — the configuration keys of the ray side (TRV, IST,
 * scheduler, ray-side FIFOs) as rtcfg schemas (config/config.h), and their
 * conversion to the units' parameters. Needs no kernel.
 *
 * Sections: [trv] (count, slots, stack, pipeline stages, FLOPs), [ist],
 * [sched], the ray-side keys of [fifo] (ray_*), and [bvh] (the host-side
 * builder's parameters). Defaults are the paper's
 * (sec. 3, 3.1); the machine width comes from machine.branching. The table
 * of the ray-side FIFOs (accel_ray_fifos) and their deadlock-free minima. */
#ifndef RTSIM_MODEL_ACCEL_CONFIG_H
#define RTSIM_MODEL_ACCEL_CONFIG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "config/config.h"
#include "model/ray/ist.h"
#include "model/ray/scheduler.h"
#include "model/ray/trv.h"

typedef struct accel_params {
    int width;                 /* machine.branching */
    double clock_mhz;          /* machine.clock_mhz */
    uint32_t trv_count;
    trv_params trv;
    ist_params ist;
    sched_params sched;
    uint32_t fifo_latency;     /* latency of the ray-side FIFOs, cycles (their capacities: accel_ray_fifos) */
} accel_params;

extern const rtcfg_schema accel_schema_fifo;
extern const rtcfg_schema accel_schema_bvh;   /* [bvh]: the host-side BVH builder's keys */

/* Registers the schemas above. */
int accel_add_schemas(rtcfg *cfg, char *err, size_t errlen);
/* Reads the parameters (after rtcfg_finish). */
void accel_params_get(const rtcfg *cfg, accel_params *out);

/* The ray side's FIFOs (paper Fig. 2; docs/accel.md "Timing model"), one
 * row per kind. A '#' in a name stands for a TRV's index: such a row is one
 * FIFO per TRV ("trv#.new": trv0.new, trv1.new, ...), another row is one
 * FIFO. key: the [fifo] key of its capacity. producer, consumer: the units
 * at its ends ('#' as in name). ring: the FIFO is a ring inside its consumer
 * (pipe_ring.h: the loop FIFOs) rather than a kernel FIFO (the energy
 * model counts its writes from the consumer's figures: accel_top.c,
 * ring_writes). min: its deadlock-free minimum on its own (below;
 * NULL: 1). accel_top.c builds, binds and auto-sizes the FIFOs from this
 * table and gives them to the energy model. */
typedef enum {
    ACCEL_FIFO_NEW,
    ACCEL_FIFO_LEAF,
    ACCEL_FIFO_RETURN,
    ACCEL_FIFO_DONE,
    ACCEL_FIFO_TRV_LOOP,
    ACCEL_FIFO_IST_LOOP,
    ACCEL_FIFO_COUNT
} accel_fifo_id;

typedef struct accel_fifo_desc {
    const char *name, *key, *producer, *consumer;
    bool ring;
    uint32_t (*min)(const rtcfg *cfg);
} accel_fifo_desc;

extern const accel_fifo_desc accel_ray_fifos[ACCEL_FIFO_COUNT];

/* True when the row is one FIFO per TRV. */
bool accel_fifo_per_trv(const accel_fifo_desc *d);
/* pattern ('#' = a TRV's index, as in the table) for TRV trv, in buf. */
const char *accel_fifo_expand(const char *pattern, uint32_t trv, char *buf, size_t len);

/* Deadlock-free minima (the cross-key check of [fifo] refuses machines below
 * them; FIFO auto-sizing never writes less). accel_fifo_min: the smallest
 * safe capacity of FIFO id on its own (the row's min: ray_trv_loop, trv.slots
 * - TRV stages + 1; the others 1); accel_leaf_return_min: the smallest safe
 * sum fifo.ray_leaf + fifo.ray_return. accel_trv_depth_of: the TRV pipeline
 * stages of cfg (trv_pipeline_depth without building a TRV). The argument
 * is in accel_config.c and docs/accel.md. */
uint32_t accel_fifo_min(const rtcfg *cfg, accel_fifo_id id);
uint32_t accel_leaf_return_min(const rtcfg *cfg);
uint32_t accel_trv_depth_of(const rtcfg *cfg);

#endif
