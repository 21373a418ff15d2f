/* dram_addrmap.h — physical address -> (channel, rank, bank, row, column).
 *
 * The mapping is a string of fields from the most to the least significant bits,
 * e.g. "RoBaRaCoCh" (Ramulator's default, lpddr3_1600_timing.txt:52-54): above
 * the log2(burst bytes) offset bits come Ch, then Co, Ra, Ba, Ro. Fields: Ro Ba
 * Ra Co Ch, each exactly once; widths are log2 of the organization counts
 * (columns count bursts: log2(columns/prefetch)). Bits above the row are ignored
 * (the row field takes its low bits), as in Ramulator. */
#ifndef RTSIM_DRAM_ADDRMAP_H
#define RTSIM_DRAM_ADDRMAP_H

#include <stddef.h>
#include <stdint.h>

#include "model/dram/dram_timing.h"

enum dram_field { DRAM_F_CH, DRAM_F_RA, DRAM_F_BA, DRAM_F_RO, DRAM_F_CO, DRAM_NFIELD };

typedef struct dram_addr {
    uint32_t channel, rank, bank, row, column;
} dram_addr;

typedef struct dram_addrmap {
    int offset_bits;              /* log2(burst bytes) */
    int nfields;
    uint8_t field[DRAM_NFIELD];   /* from least significant upward */
    uint8_t bits[DRAM_NFIELD];
    uint8_t shift[DRAM_NFIELD];   /* by field (enum dram_field): its lowest address bit */
    uint64_t mask[DRAM_NFIELD];   /* by field: (1 << width) - 1 */
} dram_addrmap;

/* 0, or -1 with a message naming the mapping and the allowed fields. */
int dram_addrmap_init(dram_addrmap *m, const dram_spec *spec, char *err, size_t errlen);

static inline void dram_addrmap_decode(const dram_addrmap *m, uint64_t addr, dram_addr *out)
{
    /* each field at its precomputed position (dram_addrmap_init), no loop */
    out->channel = (uint32_t)((addr >> m->shift[DRAM_F_CH]) & m->mask[DRAM_F_CH]);
    out->rank = (uint32_t)((addr >> m->shift[DRAM_F_RA]) & m->mask[DRAM_F_RA]);
    out->bank = (uint32_t)((addr >> m->shift[DRAM_F_BA]) & m->mask[DRAM_F_BA]);
    out->row = (uint32_t)((addr >> m->shift[DRAM_F_RO]) & m->mask[DRAM_F_RO]);
    out->column = (uint32_t)((addr >> m->shift[DRAM_F_CO]) & m->mask[DRAM_F_CO]);
}

/* Inverse of decode (for tests and trace generators). */
uint64_t dram_addrmap_encode(const dram_addrmap *m, const dram_addr *a);

#endif
