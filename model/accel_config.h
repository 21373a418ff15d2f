/* accel_config.h — the configuration keys of the ray side (TRV, IST,
 * scheduler, ray-side FIFOs) as rtcfg schemas (config/config.h), and their
 * conversion to the units' parameters. Needs no kernel.
 *
 * Sections: [trv] (count, slots, stack, pipeline stages, FLOPs), [ist],
 * [sched], and the ray-side keys of [fifo] (ray_*). Defaults are the paper's
 * (sec. 3, 3.1); the machine width comes from machine.branching. */
#ifndef RTSIM_MODEL_ACCEL_CONFIG_H
#define RTSIM_MODEL_ACCEL_CONFIG_H

#include <stddef.h>

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
    /* ray-side FIFO capacities and their latency (cycles) */
    uint32_t fifo_new, fifo_leaf, fifo_return, fifo_done, fifo_trv_loop, fifo_ist_loop, fifo_latency;
} accel_params;

extern const rtcfg_schema accel_schema_fifo;

/* Registers the schemas above. */
int accel_add_schemas(rtcfg *cfg, char *err, size_t errlen);
/* Reads the parameters (after rtcfg_finish). */
void accel_params_get(const rtcfg *cfg, accel_params *out);

/* Ray-side FIFO keys, for auto-sizing: key i ("fifo.ray_new" ...) and the
 * suffix of the FIFO names it sizes ("new" -> "trv0.new" ...). */
unsigned accel_fifo_key_count(void);
const char *accel_fifo_key(unsigned i);

/* Deadlock-free minima (the cross-key check of [fifo] refuses machines below
 * them; FIFO auto-sizing never writes less). accel_fifo_min: the smallest
 * safe capacity of key i on its own (ray_trv_loop: trv.slots - TRV stages +
 * 1; the others 1); accel_leaf_return_min: the smallest safe sum
 * fifo.ray_leaf + fifo.ray_return. accel_trv_depth_of: the TRV pipeline
 * stages of cfg (trv_pipeline_depth without building a TRV). The argument
 * is in accel_config.c and docs/accel.md. */
uint32_t accel_fifo_min(const rtcfg *cfg, unsigned i);
uint32_t accel_leaf_return_min(const rtcfg *cfg);
uint32_t accel_trv_depth_of(const rtcfg *cfg);

#endif
