/* memsys_config.h — the configuration keys of the memory side (caches,
 * memory-side FIFOs, memory model) as rtcfg schemas, and their conversion to
 * the parameters of the units. Needs no kernel.
 *
 * Sections (defaults = the paper's MBVH4 machine; presets in
 * model/data/machines/ cite the paper for every number):
 *   [node_l1]  per-TRV node L1        [node_l2]  node L2 shared by the TRVs
 *   [prim]     primitive cache of the IST (two banks interleaved by line)
 *   [memory]   model = fixed | lpddr3, fixed-latency figures, DRAM file/clock
 *   [fifo]     depths of the memory-side FIFOs (mem_* keys) and their latency
 *   [dram]     every key of the DRAM standard file named by memory.dram_config,
 *              as "SECTION.KEY" (dram.timing.nCL, dram.organization.channels,
 *              dram.constraints.rank RD -> WR, ...); a deferred schema
 *              (config.h), registered by rtcfg_finish once memory.dram_config
 *              is final, defaults = the file's values (docs/dram.md).
 * Cross-key checks (rtcfg_finish): sets per bank = size/(line*ways*banks) >= 1,
 * node_l1.line <= node_l2.line (an L1 fill is one L2 request), node_l1 and
 * node_l2 .addressing equal (byte: power-of-two lines; index: a line is one
 * node, docs/energy.md "Branching factors 2..8"); the DRAM
 * standard with the [dram] values loads (dram_spec_load: ranges, the key
 * named). With memory.model = fixed an unreadable DRAM file is no error (the
 * [dram] section is then absent). */
#ifndef RTSIM_MODEL_MEMSYS_CONFIG_H
#define RTSIM_MODEL_MEMSYS_CONFIG_H

#include <stddef.h>
#include <stdint.h>

#include "model/mem/cache_core.h"
#include "config/config.h"

typedef enum memsys_model { MEMSYS_FIXED = 0, MEMSYS_LPDDR3 = 1 } memsys_model;
/* node_l1.addressing, node_l2.addressing (in this order in the enum text). */
typedef enum memsys_addressing { MEMSYS_BYTE = 0, MEMSYS_INDEX = 1 } memsys_addressing;

extern const rtcfg_schema memsys_schema_node_l1, memsys_schema_node_l2, memsys_schema_prim, memsys_schema_memory,
    memsys_schema_fifo;

/* Registers all the schemas above ([dram] deferred to rtcfg_finish). */
int memsys_add_schemas(rtcfg *cfg, char *err, size_t errlen);

struct dram_spec;
/* Path of memory.dram_config (a name without '/' is in rtcfg_data_dir()). */
int memsys_dram_path(const rtcfg *cfg, char *buf, size_t len);
/* Loads the DRAM standard of a finished cfg with its [dram] values: the
 * keys not at their default are the overrides, named by their origin in
 * messages ("--set dram.timing.nCL=99" or "FILE:LINE"). */
int memsys_dram_spec_load(const rtcfg *cfg, struct dram_spec *spec, char *err, size_t errlen);

/* Cache parameters of a section ("node_l1", "node_l2", "prim"). With
 * SECTION.addressing = index the line is the node (memsys_node_bytes) and
 * SECTION.line is not used. */
void memsys_cache_params(const rtcfg *cfg, const char *section, cache_params *out);
/* The line (index-addressed: word) size a cache section really has. */
int64_t memsys_line_bytes(const rtcfg *cfg, const char *section);
/* Bytes of one BVH node: machine.branching x 32 (tracer/bvh/bvh_layout.h). */
int64_t memsys_node_bytes(const rtcfg *cfg);


/* The most lines of `line` bytes an object of `bytes` bytes touches in the
 * memory image's layout (a node: bytes = machine.branching x 32; a
 * triangle: 48); see memsys_config.c. */
int64_t memsys_lines_touched(int64_t bytes, int64_t line);

#endif
