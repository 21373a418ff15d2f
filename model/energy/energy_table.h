/* energy_table.h — SRAM and FPU figures at 45 nm, read from data files
 * (model/data/energy/sram_45nm.ini, fpu_45nm.ini), and the rule that gives
 * a figure to a structure the tables do not list exactly.
 *
 * Contract:
 *  - energy_table_load() reads both files; every row must have every key,
 *    with a positive value; errors name file:line (or file and section) and
 *    the key.
 *  - energy_sram_figure() returns the figure of one SRAM structure:
 *      candidates: rows of the same kind (cache/ram) and ports, and for
 *      caches the same line and ways;
 *      choice: the candidate nearest in size, then in word width (distance
 *      |ln(size/size_row)| + |ln(width/width_row)|; ties go to the earlier
 *      row);
 *      scaling: s = size / size_row, w = width / width_row; area and leakage
 *      scale with s (bits), access energies with sqrt(s * w) (the bits read
 *      grow with w, the wire length with the square root of the array);
 *      limits: w within [1/4, 4], s within [1/4, 4] for caches and at
 *      most 4 for RAMs (a RAM may be any smaller: auto-sized FIFOs of a few
 *      entries; the laws then overestimate); outside, or with no candidate,
 *      the structure has no figure and the call fails with a message naming
 *      the structure and what the tables offer (never a silent zero).
 *  - node words (energy_sram_req.node_word: an index-addressed node cache,
 *    whose line is one node of N x 32 B, docs/energy.md): when no row has
 *    that line, each figure (area, read, write, leakage) is interpolated
 *    linearly in the line width between the two neighbouring line widths
 *    of rows of the same kind, ports and ways, each scaled to the size by
 *    the rule above; outside the widths the rows cover, extrapolated from
 *    the two nearest, up to 2x beyond the widest (or below the narrowest);
 *    a figure <= 0 fails. 16 KB, 4-way, 96 B from the 64 and 128 B rows:
 *    the mean of the two (energy_table.c cites the law's source).
 * Deterministic; no state beyond the loaded table. */
#ifndef RTSIM_MODEL_ENERGY_TABLE_H
#define RTSIM_MODEL_ENERGY_TABLE_H

#include <stddef.h>

#define ENERGY_MAX_ROWS 64

typedef enum energy_kind { ENERGY_CACHE, ENERGY_RAM } energy_kind;
typedef enum energy_ports { ENERGY_1RW, ENERGY_1R1W } energy_ports;

/* One row of the SRAM table, or a figure derived from one. */
typedef struct energy_sram {
    char name[48];           /* the row's section */
    energy_kind kind;
    energy_ports ports;
    double size, ways, line; /* bytes; ways (caches); bytes per access */
    double area_mm2, read_nj, write_nj, leak_mw;
} energy_sram;

typedef struct energy_fpu {
    double energy_pj_per_flop;
    double area_mm2_per_flop_unit;  /* hardware doing one FLOP per cycle */
    double leak_mw_per_flop_unit;
} energy_fpu;

/* How a figure grows with ports: the ratio of a p0-port array to a 1-port
 * one; a p-port structure scales by ratio^(ln p / ln p0) (section
 * [multiport] of the SRAM table; p0 = 0 when the table has none). */
typedef struct energy_multiport {
    double p0, area, read, write, leak;
} energy_multiport;

typedef struct energy_table {
    energy_sram rows[ENERGY_MAX_ROWS];
    int nrows;
    energy_multiport mp;
    energy_fpu fpu;
    char sram_path[4096], fpu_path[4096];   /* PATH_MAX: the whole path, for messages */
} energy_table;

/* A structure to be given a figure. ways is ignored for RAMs. */
typedef struct energy_sram_req {
    const char *what;        /* for messages, e.g. "node_l1" */
    energy_kind kind;
    energy_ports ports;
    double size, ways, line;
    int node_word;           /* 1: line is a node-sized word (node-word rule above) */
} energy_sram_req;

int energy_table_load(energy_table *t, const char *sram_path, const char *fpu_path, char *err, size_t errlen);
/* 0 with the (scaled) figure in *out, or -1 with a message. */
/* Scales a 1-port figure to `ports` ports by the table's [multiport] law;
 * -1 with a message naming `what` when the table has none. */
int energy_sram_ports(const energy_table *t, const char *what, unsigned ports, energy_sram *fig, char *err,
                      size_t errlen);

int energy_sram_figure(const energy_table *t, const energy_sram_req *req, energy_sram *out, char *err,
                       size_t errlen);

#endif
