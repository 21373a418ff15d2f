/* dram_addrmap.c — parses the mapping string (dram_addrmap.h). */
#include "model/dram/dram_addrmap.h"

#include <stdio.h>
#include <string.h>

static int log2i(int v)
{
    int b = 0;
    while ((1 << b) < v)
        b++;
    return b;
}

int dram_addrmap_init(dram_addrmap *m, const dram_spec *spec, char *err, size_t errlen)
{
    static const char *const names[DRAM_NFIELD] = {"Ch", "Ra", "Ba", "Ro", "Co"};
    const int width[DRAM_NFIELD] = {log2i(spec->channels), log2i(spec->ranks), log2i(spec->banks),
                                    log2i(spec->rows), log2i(spec->columns / spec->prefetch)};
    memset(m, 0, sizeof *m);
    m->offset_bits = log2i(spec->tx_bytes);
    const char *s = spec->mapping;
    size_t len = strlen(s);
    int used[DRAM_NFIELD] = {0};
    if (len != 2 * DRAM_NFIELD)
        goto bad;
    for (int i = 0; i < DRAM_NFIELD; i++) {
        /* string is MSB first; field[0] is the least significant */
        const char *tok = s + len - 2 * (size_t)(i + 1);
        int f = -1;
        for (int k = 0; k < DRAM_NFIELD; k++)
            if (strncmp(tok, names[k], 2) == 0)
                f = k;
        if (f < 0 || used[f]++)
            goto bad;
        m->field[i] = (uint8_t)f;
        m->bits[i] = (uint8_t)width[f];
    }
    m->nfields = DRAM_NFIELD;
    int at = m->offset_bits;
    for (int i = 0; i < DRAM_NFIELD; i++) {
        m->shift[m->field[i]] = (uint8_t)at;
        m->mask[m->field[i]] = (1ull << m->bits[i]) - 1;
        at += m->bits[i];
    }
    return 0;
bad:
    snprintf(err, errlen, "%s: [controller] mapping '%s' invalid: allowed a permutation of the fields Ro Ba Ra Co Ch "
             "written most significant first, e.g. RoBaRaCoCh", spec->source, s);
    return -1;
}

uint64_t dram_addrmap_encode(const dram_addrmap *m, const dram_addr *a)
{
    const uint32_t v[DRAM_NFIELD] = {a->channel, a->rank, a->bank, a->row, a->column};
    uint64_t addr = 0;
    int shift = m->offset_bits;
    for (int i = 0; i < m->nfields; i++) {
        addr |= (uint64_t)(v[m->field[i]] & ((1u << m->bits[i]) - 1)) << shift;
        shift += m->bits[i];
    }
    return addr;
}
