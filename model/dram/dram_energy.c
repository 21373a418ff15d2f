/* dram_energy.c — DRAMPower-method energy (dram_energy.h). */
#include "model/dram/dram_energy.h"

#include "config/ini_file.h"

#include <stdio.h>
#include <string.h>

typedef struct pkey {
    const char *name;
    double lo, hi;
    size_t off;
    int is_int;
} pkey;

#define D(n, lo, hi) {#n, lo, hi, offsetof(dram_power_spec, n), 0}
#define I(n, lo, hi) {#n, lo, hi, offsetof(dram_power_spec, n), 1}
static const pkey pkeys[] = {
    D(clk_mhz, 1, 10000), D(vdd1, 0.1, 5), D(vdd2, 0.1, 5),
    D(idd0, 0, 10000), D(idd02, 0, 10000), D(idd2n, 0, 10000), D(idd2n2, 0, 10000),
    D(idd3n, 0, 10000), D(idd3n2, 0, 10000), D(idd4r, 0, 10000), D(idd4r2, 0, 10000),
    D(idd4w, 0, 10000), D(idd4w2, 0, 10000), D(idd5, 0, 10000), D(idd52, 0, 10000),
    I(burst_length, 1, 64), I(data_rate, 1, 8), I(nRAS, 1, 1000), I(nRC, 1, 1000), I(nRP, 1, 1000),
    I(nRFC, 1, 100000), I(dies_per_channel, 1, 64),
};
#define NPKEYS (int)(sizeof pkeys / sizeof pkeys[0])

typedef struct ploader {
    dram_power_spec *p;
    const char *names[NPKEYS]; /* of pkeys, for ini_file_key_index */
    int seen[NPKEYS];
} ploader;

static int phandler(ini_file *f, void *user, const char *section, const char *name, const char *value)
{
    ploader *L = user;
    const int i = ini_file_key_index(f, section, name, L->names, NPKEYS);
    if (i < 0)
        return -1;
    double v;
    if (ini_file_number(value, &v) || !(v >= pkeys[i].lo && v <= pkeys[i].hi) ||
        (pkeys[i].is_int && v != (double)(long)v))
        return ini_file_error(f, "%s = '%s' invalid, allowed %s %g..%g", name, value,
                              pkeys[i].is_int ? "integer" : "number", pkeys[i].lo, pkeys[i].hi);
    if (pkeys[i].is_int)
        *(int *)((char *)L->p + pkeys[i].off) = (int)v;
    else
        *(double *)((char *)L->p + pkeys[i].off) = v;
    L->seen[i] = 1;
    return 0;
}

int dram_power_spec_load(dram_power_spec *p, const char *path, char *err, size_t errlen)
{
    ploader L = {.p = p};
    for (int i = 0; i < NPKEYS; i++)
        L.names[i] = pkeys[i].name;
    memset(p, 0, sizeof *p);
    static const ini_file_opts opts = {.what = "a DRAM power", .section = "memspec"};
    if (ini_file_read(path, &opts, phandler, &L, err, errlen))
        return -1;
    for (int i = 0; i < NPKEYS; i++)
        if (!L.seen[i]) {
            snprintf(err, errlen, "%s: missing key %s in [memspec] (allowed %g..%g)", path, pkeys[i].name,
                     pkeys[i].lo, pkeys[i].hi);
            return -1;
        }
    if (p->nRC < p->nRAS || p->nRFC < p->nRP) {
        snprintf(err, errlen, "%s: need nRC >= nRAS and nRFC >= nRP", path);
        return -1;
    }
    return 0;
}

/* mA * V = mW; mW * ns = pJ */
static double tck_ns(const dram_power_spec *p) { return 1000.0 / p->clk_mhz; }

double dram_energy_per_act(const dram_power_spec *p)
{
    return p->dies_per_channel * (p->vdd1 * (p->idd0 - p->idd3n) + p->vdd2 * (p->idd02 - p->idd3n2)) * p->nRAS *
           tck_ns(p);
}
double dram_energy_per_pre(const dram_power_spec *p)
{
    return p->dies_per_channel * (p->vdd1 * (p->idd0 - p->idd2n) + p->vdd2 * (p->idd02 - p->idd2n2)) *
           (p->nRC - p->nRAS) * tck_ns(p);
}
double dram_energy_per_rd(const dram_power_spec *p)
{
    return p->dies_per_channel * (p->vdd1 * (p->idd4r - p->idd3n) + p->vdd2 * (p->idd4r2 - p->idd3n2)) *
           ((double)p->burst_length / p->data_rate) * tck_ns(p);
}
double dram_energy_per_wr(const dram_power_spec *p)
{
    return p->dies_per_channel * (p->vdd1 * (p->idd4w - p->idd3n) + p->vdd2 * (p->idd4w2 - p->idd3n2)) *
           ((double)p->burst_length / p->data_rate) * tck_ns(p);
}
double dram_energy_per_ref(const dram_power_spec *p)
{
    return p->dies_per_channel * (p->vdd1 * (p->idd5 - p->idd3n) + p->vdd2 * (p->idd52 - p->idd3n2)) * p->nRFC *
           tck_ns(p);
}

void dram_energy_compute(const dram_power_spec *p, const dram_energy_in *in, dram_energy *o)
{
    memset(o, 0, sizeof *o);
    o->act_pJ = (double)in->n_act * dram_energy_per_act(p);
    o->pre_pJ = (double)in->n_pre_banks * dram_energy_per_pre(p);
    o->rd_pJ = (double)in->n_rd * dram_energy_per_rd(p);
    o->wr_pJ = (double)in->n_wr * dram_energy_per_wr(p);
    o->ref_pJ = (double)in->n_ref * dram_energy_per_ref(p);
    uint64_t act = in->open_cycles + in->n_ref * (uint64_t)(p->nRFC - p->nRP);
    if (act > in->total_cycles)
        act = in->total_cycles;
    o->act_cycles = act;
    o->pre_cycles = in->total_cycles - act;
    const double t = tck_ns(p) * p->dies_per_channel;
    o->act_stby_pJ = (double)act * t * (p->vdd1 * p->idd3n + p->vdd2 * p->idd3n2);
    o->pre_stby_pJ = (double)o->pre_cycles * t * (p->vdd1 * p->idd2n + p->vdd2 * p->idd2n2);
    o->total_pJ = o->act_pJ + o->pre_pJ + o->rd_pJ + o->wr_pJ + o->ref_pJ + o->act_stby_pJ + o->pre_stby_pJ;
}
