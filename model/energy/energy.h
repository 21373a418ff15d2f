/* energy.h — energy, power and area of the accelerator from its activity
 * (paper sec. 3.2, Table 1; docs/energy.md).
 *
 * The machine is a list of parts, each belonging to one unit of the paper's
 * Table 1 (TRV, IST, stack, cache, FIFO, DRAM):
 *  - FPU parts: hardware for a number of FLOPs per cycle (area and leakage
 *    per such unit, energy per FLOP executed);
 *  - SRAM parts: caches, stack banks and FIFOs, each given a CACTI figure by
 *    energy_table.h's rule (area, leakage, energy per read and per write);
 *  - the DRAM: its energy comes from the LPDDR3 model (commands and
 *    background, DRAMPower's method), or bytes x a figure per byte with the
 *    fixed-latency memory.
 * Dynamic energy is counted per event (FLOP, read, write), so an idle unit
 * adds none: it is clock-gated and contributes only its static (leakage)
 * power, for the whole frame. Area counts FPUs and memory blocks only, as
 * the paper does; the DRAM has no area.
 *
 * Contract:
 *  - energy_model_create() builds the parts of a machine and gives every
 *    SRAM part its figure; a part with no figure fails here, at start-up,
 *    with a message naming the part (never a silent zero).
 *  - energy_compute() is pure arithmetic on an activity record: the same
 *    activity gives the same result, bit for bit.
 *  - energy_register_stats() registers energy_mj, power_mw, area_mm2,
 *    mrps_per_mm2 and, per unit, energy.<unit>_mj (and _dynamic_mj,
 *    _static_mj), power.<unit>_mw and area.<unit>_mm2; their values are
 *    those of the last energy_compute(). */
#ifndef RTSIM_MODEL_ENERGY_H
#define RTSIM_MODEL_ENERGY_H

#include <stddef.h>
#include <stdint.h>

#include "kernel/stats.h"
#include "config/config.h"
#include "model/energy/energy_table.h"

typedef enum energy_unit {
    EU_TRV,
    EU_IST,
    EU_STACK,
    EU_CACHE,
    EU_FIFO,
    EU_DRAM,
    EU_COUNT
} energy_unit;

/* Table 1's names: "trv", "ist", "stack", "cache", "fifo", "dram". */
const char *energy_unit_name(energy_unit u);

#define ENERGY_MAX_PARTS 48

typedef struct energy_part {
    char name[48];           /* e.g. "node_l1", "fifo.ray_new", "trv fpu" */
    energy_unit unit;
    const char *module;      /* the module whose description declares the part */
    const char *decl;        /* its KS_DESC_PART name there */
    unsigned count;          /* identical instances */
    int is_fpu;
    double flop_units;       /* FPU: FLOPs per cycle of one instance */
    energy_sram fig;         /* SRAM: figure of one instance */
} energy_part;

/* The machine as the energy model sees it (filled by the top level). */
typedef struct energy_machine {
    unsigned trv_count;
    double trv_flop_units;   /* per TRV: slab-test lanes x FLOPs + sort comparators */
    double ist_flop_units;   /* FLOPs of one intersection test (one issued per cycle) */
    /* stacks of one TRV: banks of (slots x ceil(depth / banks)) entries */
    unsigned stack_slots, stack_depth, stack_banks, stack_entry_bytes;
    /* caches: size, line, ways, ports, banks (the line is per bank) */
    /* node_word: index-addressed, the line is a node (energy_table.h's node-word rule) */
    struct { const char *name; unsigned count; double size, line, ways; unsigned ports, banks, node_word; } cache[3];
    int ncache;
    /* FIFOs: one entry per configuration key */
    struct { const char *key; unsigned count; double entries, width_bytes; } fifo[24];
    int nfifo;
    int dram_modeled;        /* 1: LPDDR3 energy from the port; 0: fixed memory, bytes x pJ/byte */
    double fixed_mem_pj_per_byte;
} energy_machine;

/* Activity of one run, summed over instances. */
typedef struct energy_activity {
    double seconds;          /* frame time at the machine clock */
    double trv_flops, ist_flops;
    double stack_reads, stack_writes;
    double cache_reads[3], cache_writes[3];  /* same order as energy_machine.cache */
    double fifo_reads[24], fifo_writes[24];  /* same order as energy_machine.fifo */
    double dram_dynamic_nj, dram_static_nj;  /* LPDDR3 model */
    double dram_bytes;                       /* fixed memory */
} energy_activity;

/* out = to - from, every count and the seconds (the activity of an interval
 * of a run; the energy model is linear in it). */
void energy_activity_between(const energy_activity *from, const energy_activity *to, energy_activity *out);

typedef struct energy_result {
    double dynamic_mj[EU_COUNT], static_mj[EU_COUNT], energy_mj[EU_COUNT];
    double power_mw[EU_COUNT], area_mm2[EU_COUNT];
    double total_energy_mj, total_power_mw, total_area_mm2;
    double mrps, mrps_per_mm2;
} energy_result;

typedef struct energy_model {
    energy_table table;
    energy_machine m;
    energy_part parts[ENERGY_MAX_PARTS];
    int nparts;
    int fifo_part0, cache_part0, stack_part, trv_part, ist_part; /* indices into parts */
    energy_result r;
} energy_model;

/* Every (module, part) the model builds; a unit description's KS_DESC_PART
 * must be one of them, and each must be declared (tb_energy checks both). */
typedef struct energy_part_kind {
    const char *module, *decl;
} energy_part_kind;
extern const energy_part_kind energy_part_kinds[];
extern const int energy_part_kind_count;

/* The [energy] configuration section (tables, FIFO record widths, ...). */
extern const rtcfg_schema energy_schema;
int energy_add_schema(rtcfg *cfg, char *err, size_t errlen);

/* Loads the tables named by cfg's [energy] keys and builds the parts of m.
 * NULL with a message on error. */
energy_model *energy_model_create(const rtcfg *cfg, const energy_machine *m, char *err, size_t errlen);
/* Same from tables already loaded (tests). */
energy_model *energy_model_create_with(const energy_table *table, const energy_machine *m, char *err,
                                       size_t errlen);
void energy_model_destroy(energy_model *em);

/* Fills em->r; mrps is the run's rays per microsecond (for MRPS/mm2). */
void energy_compute(energy_model *em, const energy_activity *a, double mrps);

int energy_register_stats(energy_model *em, ks_stats *st, char *err, size_t errlen);
/* Its statistics, declared (--help-module energy). */
extern const ks_module_desc energy_module_desc;

/* Summary lines: energy per frame by unit, average power, area by unit, MRPS/mm2. */
void energy_print_summary(const energy_model *em, FILE *out);

#endif
