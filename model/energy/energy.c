/* energy.c — energy, power and area from activity (see energy.h, docs/energy.md). */
#include "model/energy/energy.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const rtcfg_param energy_params_tab[] = {
    {"enabled", RTCFG_BOOL, "true", 0, 0, 0, NULL, "",
     "compute energy, power and area; false runs a machine the SRAM table cannot cover, without those figures"},
    {"sram_table", RTCFG_STRING, "sram_45nm_lop.ini", 0, 0, 0, NULL, "file",
     "SRAM figures (CACTI 6.5, 45 nm): sram_45nm_lop.ini (itrs-lop cells, the closest to the paper's Table 1 "
     "cache, stack and FIFO power, docs/paper.md), sram_45nm.ini (itrs-hp), sram_45nm_lstpcell.ini, "
     "sram_45nm_300k.ini; a name without '/' is looked up in model/data/energy"},
    {"fpu_table", RTCFG_STRING, "fpu_45nm.ini", 0, 0, 0, NULL, "file",
     "FPU figures (Galal and Horowitz 2011); a name without '/' is looked up in model/data/energy"},
    {"fifo_ray_bytes", RTCFG_INT, "48", 1, 1024, 0, NULL, "bytes",
     "record width of the ray-side FIFOs: origin, direction, t range, ray id (ours)"},
    {"fifo_request_bytes", RTCFG_INT, "8", 1, 1024, 0, NULL, "bytes",
     "record width of memory request FIFOs: a 32-bit address and a tag (ours); data FIFOs carry a line"},
    {"fixed_mem_pj_per_byte", RTCFG_REAL, "120", 0, 1e6, 0, NULL, "pJ/byte",
     "DRAM energy per byte with memory.model = fixed (ours: the LPDDR3 model's figure on diffuse rays, "
     "background included)"},
};
const rtcfg_schema energy_schema = {"energy", "energy and area model (docs/energy.md)", energy_params_tab, 6, NULL};

int energy_add_schema(rtcfg *cfg, char *err, size_t errlen) { return rtcfg_add_schema(cfg, &energy_schema, err, errlen); }

static const char *const unit_names[EU_COUNT] = {"trv", "ist", "stack", "cache", "fifo", "dram"};
const char *energy_unit_name(energy_unit u) { return u < EU_COUNT ? unit_names[u] : "?"; }

const energy_part_kind energy_part_kinds[] = {
    {"trv", "fpu"}, {"trv", "stack_bank"}, {"ist", "fpu"}, {"cache", "sram"},
    {"fifo", "ram"}, {"dram", "dram"}, {"fixed_mem", "dram"},
};
const int energy_part_kind_count = (int)(sizeof energy_part_kinds / sizeof energy_part_kinds[0]);

static energy_part *add_part(energy_model *em, const char *name, energy_unit unit, unsigned count, char *err,
                             size_t errlen)
{
    if (em->nparts == ENERGY_MAX_PARTS) {
        snprintf(err, errlen, "energy model: more than %d parts", ENERGY_MAX_PARTS);
        return NULL;
    }
    energy_part *p = &em->parts[em->nparts++];
    memset(p, 0, sizeof *p);
    snprintf(p->name, sizeof p->name, "%s", name);
    /* which unit description declares it (energy_part_kinds) */
    static const struct { energy_unit unit; const char *prefix, *module, *decl; } owners[] = {
        {EU_TRV, "trv.fpu", "trv", "fpu"},         {EU_STACK, "trv.stack", "trv", "stack_bank"},
        {EU_IST, "ist.fpu", "ist", "fpu"},         {EU_CACHE, "", "cache", "sram"},
        {EU_FIFO, "", "fifo", "ram"},
    };
    for (size_t i = 0; i < sizeof owners / sizeof owners[0]; i++)
        if (owners[i].unit == unit && !strncmp(name, owners[i].prefix, strlen(owners[i].prefix))) {
            p->module = owners[i].module;
            p->decl = owners[i].decl;
        }
    p->unit = unit;
    p->count = count;
    return p;
}

static int add_sram(energy_model *em, const char *name, energy_unit unit, unsigned count,
                    const energy_sram_req *req, char *err, size_t errlen)
{
    energy_part *p = add_part(em, name, unit, count, err, errlen);
    if (!p)
        return -1;
    return energy_sram_figure(&em->table, req, &p->fig, err, errlen);
}

energy_model *energy_model_create_with(const energy_table *table, const energy_machine *m, char *err,
                                       size_t errlen)
{
    energy_model *em = calloc(1, sizeof *em);
    if (!em) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    em->table = *table;
    em->m = *m;
    energy_part *p;
    /* FPUs: a TRV's slab tests and sorting network, the IST's Wald test */
    em->trv_part = em->nparts;
    if (!(p = add_part(em, "trv.fpu", EU_TRV, m->trv_count, err, errlen)))
        goto fail;
    p->is_fpu = 1;
    p->flop_units = m->trv_flop_units;
    em->ist_part = em->nparts;
    if (!(p = add_part(em, "ist.fpu", EU_IST, 1, err, errlen)))
        goto fail;
    p->is_fpu = 1;
    p->flop_units = m->ist_flop_units;
    /* stacks: per TRV, stack_banks banks of slots x ceil(depth / banks) entries,
     * one read and one write port (a pop and a push in the same cycle) */
    if (m->stack_banks < 1 || m->stack_entry_bytes < 1) {
        snprintf(err, errlen, "energy model: stack with %u banks of %u-byte entries", m->stack_banks,
                 m->stack_entry_bytes);
        goto fail;
    }
    double per_bank = (double)m->stack_slots * (double)((m->stack_depth + m->stack_banks - 1) / m->stack_banks);
    energy_sram_req sreq = {"trv stack bank (trv.slots, trv.stack_depth, trv.stack_banks)", ENERGY_RAM, ENERGY_1R1W,
                            per_bank * m->stack_entry_bytes, 0, m->stack_entry_bytes, 0};
    em->stack_part = em->nparts;
    if (add_sram(em, "trv.stack_bank", EU_STACK, m->trv_count * m->stack_banks, &sreq, err, errlen))
        goto fail;
    /* caches: one CACTI array per bank */
    em->cache_part0 = em->nparts;
    for (int i = 0; i < m->ncache; i++) {
        char what[96];
        snprintf(what, sizeof what, "%s (%s.size / %s.banks)", m->cache[i].name, m->cache[i].name, m->cache[i].name);
        energy_sram_req creq = {what, ENERGY_CACHE, ENERGY_1RW, m->cache[i].size / m->cache[i].banks,
                                m->cache[i].ways, m->cache[i].line, (int)m->cache[i].node_word};
        if (add_sram(em, m->cache[i].name, EU_CACHE, m->cache[i].count * m->cache[i].banks, &creq, err, errlen))
            goto fail;
        /* a multi-ported cache: the 1-port figure scaled by the table's law */
        snprintf(what, sizeof what, "%s.ports", m->cache[i].name);
        if (energy_sram_ports(&em->table, what, m->cache[i].ports, &em->parts[em->nparts - 1].fig, err, errlen))
            goto fail;
    }
    /* FIFOs: 1R1W RAMs of entries x record width */
    em->fifo_part0 = em->nparts;
    for (int i = 0; i < m->nfifo; i++) {
        char what[96];
        snprintf(what, sizeof what, "FIFO %s", m->fifo[i].key);
        energy_sram_req freq = {what, ENERGY_RAM, ENERGY_1R1W, m->fifo[i].entries * m->fifo[i].width_bytes, 0,
                                m->fifo[i].width_bytes, 0};
        if (add_sram(em, m->fifo[i].key, EU_FIFO, m->fifo[i].count, &freq, err, errlen))
            goto fail;
    }
    return em;
fail:
    free(em);
    return NULL;
}

/* 0, or -1 when the path does not fit buf (refused, never cut) */
static int data_path(const char *file, char *buf, size_t len)
{
    int n = strchr(file, '/') ? snprintf(buf, len, "%s", file) : snprintf(buf, len, "%s/energy/%s", rtcfg_data_dir(), file);
    return n < 0 || (size_t)n >= len ? -1 : 0;
}

energy_model *energy_model_create(const rtcfg *cfg, const energy_machine *m, char *err, size_t errlen)
{
    char sram[RTCFG_PATH_MAX], fpu[RTCFG_PATH_MAX], why[RTCFG_MSG_MAX];
    const char *sf = rtcfg_str(cfg, "energy.sram_table"), *ff = rtcfg_str(cfg, "energy.fpu_table");
    if (data_path(sf, sram, sizeof sram) || data_path(ff, fpu, sizeof fpu)) {
        snprintf(err, errlen, "energy tables (energy.sram_table = %s, energy.fpu_table = %s): path longer than %d "
                 "characters", sf, ff, RTCFG_PATH_MAX - 1);
        return NULL;
    }
    energy_table *t = malloc(sizeof *t);
    if (!t) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    if (energy_table_load(t, sram, fpu, why, sizeof why)) {
        snprintf(err, errlen, "energy tables (energy.sram_table, energy.fpu_table): %s", why);
        free(t);
        return NULL;
    }
    energy_model *em = energy_model_create_with(t, m, why, sizeof why);
    free(t);
    if (!em)
        snprintf(err, errlen, "energy model: %s (--set energy.enabled=false runs without energy and area)", why);
    return em;
}

void energy_model_destroy(energy_model *em) { free(em); }

void energy_activity_between(const energy_activity *from, const energy_activity *to, energy_activity *out)
{
    *out = *to;
    out->seconds -= from->seconds;
    out->trv_flops -= from->trv_flops, out->ist_flops -= from->ist_flops;
    out->stack_reads -= from->stack_reads, out->stack_writes -= from->stack_writes;
    for (size_t i = 0; i < sizeof out->cache_reads / sizeof out->cache_reads[0]; i++) {
        out->cache_reads[i] -= from->cache_reads[i];
        out->cache_writes[i] -= from->cache_writes[i];
    }
    for (size_t i = 0; i < sizeof out->fifo_reads / sizeof out->fifo_reads[0]; i++) {
        out->fifo_reads[i] -= from->fifo_reads[i];
        out->fifo_writes[i] -= from->fifo_writes[i];
    }
    out->dram_dynamic_nj -= from->dram_dynamic_nj, out->dram_static_nj -= from->dram_static_nj;
    out->dram_bytes -= from->dram_bytes;
}

void energy_compute(energy_model *em, const energy_activity *a, double mrps)
{
    energy_result *r = &em->r;
    memset(r, 0, sizeof *r);
    const energy_fpu *fpu = &em->table.fpu;
    /* dynamic energy in nJ per unit, static power in mW per unit */
    double dyn_nj[EU_COUNT] = {0}, leak_mw[EU_COUNT] = {0};
    for (int i = 0; i < em->nparts; i++) {
        const energy_part *p = &em->parts[i];
        double reads = 0, writes = 0;
        if (p->is_fpu) {
            double flops = i == em->trv_part ? a->trv_flops : a->ist_flops;
            dyn_nj[p->unit] += flops * fpu->energy_pj_per_flop / 1000.0;
            leak_mw[p->unit] += p->count * p->flop_units * fpu->leak_mw_per_flop_unit;
            r->area_mm2[p->unit] += p->count * p->flop_units * fpu->area_mm2_per_flop_unit;
            continue;
        }
        if (i == em->stack_part) {
            reads = a->stack_reads;
            writes = a->stack_writes;
        } else if (i >= em->fifo_part0) {
            reads = a->fifo_reads[i - em->fifo_part0];
            writes = a->fifo_writes[i - em->fifo_part0];
        } else if (i >= em->cache_part0) {
            reads = a->cache_reads[i - em->cache_part0];
            writes = a->cache_writes[i - em->cache_part0];
        }
        dyn_nj[p->unit] += reads * p->fig.read_nj + writes * p->fig.write_nj;
        leak_mw[p->unit] += p->count * p->fig.leak_mw;
        r->area_mm2[p->unit] += p->count * p->fig.area_mm2;
    }
    if (em->m.dram_modeled) {
        dyn_nj[EU_DRAM] = a->dram_dynamic_nj;
        r->static_mj[EU_DRAM] = a->dram_static_nj / 1e6;
    } else {
        dyn_nj[EU_DRAM] = a->dram_bytes * em->m.fixed_mem_pj_per_byte / 1000.0;
    }
    for (int u = 0; u < EU_COUNT; u++) {
        r->dynamic_mj[u] = dyn_nj[u] / 1e6;
        if (u != EU_DRAM)
            r->static_mj[u] = leak_mw[u] * a->seconds; /* mW x s = mJ */
        r->energy_mj[u] = r->dynamic_mj[u] + r->static_mj[u];
        r->power_mw[u] = a->seconds > 0 ? r->energy_mj[u] / a->seconds : 0.0;
        r->total_energy_mj += r->energy_mj[u];
        r->total_area_mm2 += r->area_mm2[u];
    }
    r->total_power_mw = a->seconds > 0 ? r->total_energy_mj / a->seconds : 0.0;
    r->mrps = mrps;
    r->mrps_per_mm2 = r->total_area_mm2 > 0 ? mrps / r->total_area_mm2 : 0.0;
}

static const ks_desc_item energy_items[] = {
    {KS_DESC_STAT, "energy_mj", "mJ", "", "", "energy of the frame: all units, dynamic and static"},
    {KS_DESC_STAT, "power_mw", "mW", "", "", "average power over the frame"},
    {KS_DESC_STAT, "area_mm2", "mm2", "", "", "area of the FPUs and memory blocks (caches, stacks, FIFOs)"},
    {KS_DESC_STAT, "mrps_per_mm2", "MRPS/mm2", "", "", "performance per area"},
    /* per unit (trv, ist, stack, cache, fifo, dram); the specific names first */
    {KS_DESC_STAT, "energy.*_dynamic_mj", "mJ", "", "",
     "dynamic energy of the * unit(s): per FLOP, access or DRAM command"},
    {KS_DESC_STAT, "energy.*_static_mj", "mJ", "", "",
     "static energy of the * unit(s): leakage (DRAM: background) over the frame"},
    {KS_DESC_STAT, "energy.*_mj", "mJ", "", "", "energy of the frame in the * unit(s), dynamic and static"},
    {KS_DESC_STAT, "power.*_mw", "mW", "", "", "average power of the * unit(s)"},
    {KS_DESC_STAT, "area.*_mm2", "mm2", "", "", "area of the * unit(s): FPUs and memory blocks"},
    {KS_DESC_END, 0, 0, 0, 0, 0},
};
const ks_module_desc energy_module_desc = {"energy", "energy, power and area from activity (docs/energy.md)", energy_items, "energy"};

int energy_register_stats(energy_model *em, ks_stats *st, char *err, size_t errlen)
{
    energy_result *r = &em->r;
    const ks_module_desc *d = &energy_module_desc;
    int rc = 0;
    rc |= ks_stat_decl_real(st, d, NULL, "energy_mj", &r->total_energy_mj);
    rc |= ks_stat_decl_real(st, d, NULL, "power_mw", &r->total_power_mw);
    rc |= ks_stat_decl_real(st, d, NULL, "area_mm2", &r->total_area_mm2);
    rc |= ks_stat_decl_real(st, d, NULL, "mrps_per_mm2", &r->mrps_per_mm2);
    for (int u = 0; u < EU_COUNT; u++) {
        const char *n = unit_names[u];
        char name[64];
        snprintf(name, sizeof name, "energy.%s_mj", n);
        rc |= ks_stat_decl_real(st, d, NULL, name, &r->energy_mj[u]);
        snprintf(name, sizeof name, "energy.%s_dynamic_mj", n);
        rc |= ks_stat_decl_real(st, d, NULL, name, &r->dynamic_mj[u]);
        snprintf(name, sizeof name, "energy.%s_static_mj", n);
        rc |= ks_stat_decl_real(st, d, NULL, name, &r->static_mj[u]);
        snprintf(name, sizeof name, "power.%s_mw", n);
        rc |= ks_stat_decl_real(st, d, NULL, name, &r->power_mw[u]);
        snprintf(name, sizeof name, "area.%s_mm2", n);
        rc |= ks_stat_decl_real(st, d, NULL, name, &r->area_mm2[u]);
    }
    if (rc)
        snprintf(err, errlen, "energy: cannot register statistics: %s", ks_stats_error(st));
    return rc ? -1 : 0;
}

void energy_print_summary(const energy_model *em, FILE *out)
{
    const energy_result *r = &em->r;
    fprintf(out, "energy      %.4g mJ/frame:", r->total_energy_mj);
    for (int u = 0; u < EU_COUNT; u++)
        fprintf(out, " %s %.3g", unit_names[u], r->energy_mj[u]);
    fprintf(out, "\npower       %.1f mW mean:", r->total_power_mw);
    for (int u = 0; u < EU_COUNT; u++)
        fprintf(out, " %s %.1f", unit_names[u], r->power_mw[u]);
    fprintf(out, "\narea        %.3f mm2:", r->total_area_mm2);
    for (int u = 0; u < EU_DRAM; u++)
        fprintf(out, " %s %.3f", unit_names[u], r->area_mm2[u]);
    fprintf(out, "; %.2f MRPS/mm2\n", r->mrps_per_mm2);
}
