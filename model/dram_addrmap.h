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

#include "model/dram_timing.h"

enum dram_field { DRAM_F_CH, DRAM_F_RA, DRAM_F_BA, DRAM_F_RO, DRAM_F_CO, DRAM_NFIELD };

typedef struct dram_addr {
    uint32_t channel, rank, bank, row, column;
} dram_addr;

typedef struct dram_addrmap {
    int offset_bits;              /* log2(burst bytes) */
    int nfields;
    uint8_t field[DRAM_NFIELD];   /* from least significant upward */
    uint8_t bits[DRAM_NFIELD];
} dram_addrmap;

/* 0, or -1 with a message naming the mapping and the allowed fields. */
int dram_addrmap_init(dram_addrmap *m, const dram_spec *spec, char *err, size_t errlen);

static inline void dram_addrmap_decode(const dram_addrmap *m, uint64_t addr, dram_addr *out)
{
    uint32_t v[DRAM_NFIELD] = {0};
    addr >>= m->offset_bits;
    for (int i = 0; i < m->nfields; i++) {
        v[m->field[i]] = (uint32_t)(addr & ((1ull << m->bits[i]) - 1));
        addr >>= m->bits[i];
    }
    out->channel = v[DRAM_F_CH];
    out->rank = v[DRAM_F_RA];
    out->bank = v[DRAM_F_BA];
    out->row = v[DRAM_F_RO];
    out->column = v[DRAM_F_CO];
}

/* Inverse of decode (for tests and trace generators). */
uint64_t dram_addrmap_encode(const dram_addrmap *m, const dram_addr *a);

#endif
