/* memsys.h — the memory hierarchy of the accelerator, built from the
 * configuration in one call (paper sec. 3, Fig. 2):
 *
 *   TRV i --probe--> node_l1_<i> --miss/fill--> l2_arbiter --> node_l2 --+
 *   IST   --probe--> prim ------------------------------------------------+--> mem_arbiter --> memory
 *
 * Contract:
 *  - memsys_build creates (on the given sim and accelerator clock) one node L1
 *    per TRV ([node_l1]), the shared node L2 ([node_l2]), the primitive cache
 *    ([prim], two banks interleaved by line), the round-robin arbiters, the
 *    memory (memory.model: fixed = fixed_mem, a latency and a bandwidth;
 *    lpddr3 = mem_dram_adapter + dram_port, the command-level LPDDR3-1600
 *    model on its own 800 MHz clock) and every FIFO between them (depths from [fifo] mem_* keys,
 *    latency fifo.mem_latency). cfg must have the memsys schemas registered
 *    (memsys_add_schemas) and be finished. Statistics are registered in
 *    `stats` when not NULL.
 *  - The TRVs and the IST call cache_core_access(memsys_node_l1(ms, i), addr,
 *    bytes, cycle) and cache_core_access(memsys_prim(ms), ...) on the accelerator
 *    clock's cycle: CACHE_HIT = data usable (add memsys hit latency),
 *    CACHE_MISS = retry later (the line is on its way), CACHE_BLOCKED = retry.
 *    The *_filled events fire after each fill of that cache (to wake sleepers).
 *  - memsys_fifo_at lists every FIFO with its configuration key (FIFO
 *    auto-sizing: set the key to ks_fifo_suggested_capacity and rewrite)
 *    and the line bytes its items carry (a fill or response: the line of
 *    the cache it fills; 0 for a request), for the energy model.
 *  - Destroy the memsys before the sim (the sim owns the FIFOs/processes). */
#ifndef RTSIM_MODEL_MEMSYS_H
#define RTSIM_MODEL_MEMSYS_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/module_desc.h"
#include "kernel/sim.h"
#include "kernel/stats.h"
#include "model/mem/cache_core.h"
#include "model/mem/cache.h"
#include "config/config.h"
#include "model/mem/memsys_config.h"

typedef struct memsys memsys;

memsys *memsys_build(ks_sim *sim, ks_clock *clk, const rtcfg *cfg, int ntrv, ks_stats *stats, char *err,
                     size_t errlen);
void memsys_destroy(memsys *ms);

int memsys_trv_count(const memsys *ms);
cache_core *memsys_node_l1(memsys *ms, int trv);
cache_core *memsys_prim(memsys *ms);
cache_core *memsys_node_l2(memsys *ms);
/* Hit latency of the L1 / primitive cache in cycles (from the configuration). */
uint32_t memsys_node_l1_latency(const memsys *ms);
uint32_t memsys_prim_latency(const memsys *ms);
ks_event *memsys_node_l1_filled(memsys *ms, int trv);
ks_event *memsys_prim_filled(memsys *ms);
cache_unit *memsys_unit(memsys *ms, const char *name);   /* "node_l1_0", "node_l2", "prim" */

memsys_model memsys_memory_model(const memsys *ms);
/* Bytes read from / written to main memory so far. */
uint64_t memsys_memory_bytes(const memsys *ms);
uint64_t memsys_memory_requests(const memsys *ms);
/* Sum over requests of the cycles from reaching the memory to the response. */
uint64_t memsys_memory_latency_sum(const memsys *ms);
/* The arbiter in front of the memory (statistics "mem_arbiter.*"): input 0
 * the node L2, input 1 the primitive cache. */
struct mem_arbiter;
const struct mem_arbiter *memsys_mem_arbiter(const memsys *ms);
/* The LPDDR3 port (statistics "dram.*", its own 800 MHz clock), NULL when fixed. */
struct dram_port *memsys_dram_port(memsys *ms);
/* The LPDDR3 spec in use (NULL with the fixed memory). */
struct dram_spec;
const struct dram_spec *memsys_dram_spec(const memsys *ms);

int memsys_fifo_count(const memsys *ms);
ks_fifo *memsys_fifo_at(const memsys *ms, int i, const char **config_key, uint32_t *line_bytes);

/* Description tables of the memory-side modules for --help-module: by module
 * name ("cache", "arbiter", "fixed_mem", "dram_adapter", "dram") or by
 * instance name ("node_l1", "node_l2", "prim" -> cache; "l2_arbiter",
 * "mem_arbiter" -> arbiter; "memory" -> dram_adapter; "fixed" -> fixed_mem;
 * "lpddr3" -> dram); NULL if unknown. */
const ks_module_desc *memsys_module_desc(const char *name);
/* The memory side's own totals (node_l1.hit_rate, memory.bytes_total). */
extern const ks_module_desc memsys_totals_module_desc;
/* Comma-separated module names, for messages. */
void memsys_module_list(FILE *out);

/* Work still held anywhere in the memory side (MSHRs, in-flight requests). */
int memsys_busy(const memsys *ms);

#endif
