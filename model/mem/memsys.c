/* memsys.c — builds the memory hierarchy; see memsys.h. */
#include "model/mem/memsys.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/dram/dram_energy.h"
#include "model/dram/dram_port.h"
#include "model/dram/dram_timing.h"
#include "model/mem/fixed_mem.h"
#include "model/mem/mem_arbiter.h"
#include "model/mem/mem_dram_adapter.h"

#define MEMSYS_MAX_TRV 64
#define MEMSYS_MAX_FIFOS (2 * MEMSYS_MAX_TRV + 16)

struct memsys {
    int ntrv;
    cache_unit *l1[MEMSYS_MAX_TRV], *l2, *prim;
    mem_arbiter *l2_arb, *mem_arb;
    fixed_mem *fmem;
    dram_spec *spec;              /* lpddr3: must outlive the run */
    dram_power_spec *power;
    dram_port *port;
    mem_dram_adapter *adapter;
    memsys_model model;
    /* every FIFO, with the configuration key of its capacity and the line
     * bytes an item carries (0: a request) */
    ks_fifo *fifo[MEMSYS_MAX_FIFOS];
    const char *fifo_key[MEMSYS_MAX_FIFOS];
    uint32_t fifo_line[MEMSYS_MAX_FIFOS];
    int nfifo;
};

static ks_fifo *mk_fifo(memsys *ms, ks_sim *sim, ks_clock *clk, const rtcfg *cfg, const char *name, const char *key,
                        size_t elem, uint32_t line, char *err, size_t errlen)
{
    uint32_t depth = (uint32_t)rtcfg_int(cfg, key), lat = (uint32_t)rtcfg_int(cfg, "fifo.mem_latency");
    ks_fifo *f = ks_fifo_create(sim, name, elem, depth, lat, clk);
    if (!f) {
        snprintf(err, errlen, "FIFO %s (%s = %u): %s", name, key, depth, ks_sim_error(sim));
        return NULL;
    }
    ms->fifo[ms->nfifo] = f;
    ms->fifo_key[ms->nfifo] = key;
    ms->fifo_line[ms->nfifo++] = line;
    return f;
}

/* Statistics of the memory side as a whole. */
static const ks_desc_item totals_items[] = {
    {KS_DESC_STAT, "node_l1.hit_rate", "ratio", "", "", "hits / accesses over all node L1s"},
    {KS_DESC_STAT, "memory.bytes_total", "bytes", "", "", "bytes moved to/from main memory"},
    {KS_DESC_END, 0, 0, 0, 0, 0},
};
const ks_module_desc memsys_totals_module_desc = {"memory_side", "totals of the memory hierarchy", totals_items, NULL};

static double l1_hit_rate(const ks_stats *reg, void *user)
{
    (void)reg;
    const memsys *ms = user;
    uint64_t h = 0, a = 0;
    for (int i = 0; i < ms->ntrv; i++) {
        const cache_stats *s = cache_core_stats_live(cache_get_core(ms->l1[i]));
        h += s->hits;
        a += s->accesses;
    }
    return a ? (double)h / (double)a : 0.0;
}

static double memory_bytes_fn(const ks_stats *reg, void *user)
{
    (void)reg;
    return (double)memsys_memory_bytes(user);
}

memsys *memsys_build(ks_sim *sim, ks_clock *clk, const rtcfg *cfg, int ntrv, ks_stats *stats, char *err,
                     size_t errlen)
{
    if (ntrv < 1 || ntrv > MEMSYS_MAX_TRV) {
        snprintf(err, errlen, "memsys: %d TRVs (allowed 1..%d)", ntrv, MEMSYS_MAX_TRV);
        return NULL;
    }
    cache_params p1, p2, pp;
    memsys_cache_params(cfg, "node_l1", &p1);
    memsys_cache_params(cfg, "node_l2", &p2);
    memsys_cache_params(cfg, "prim", &pp);
    if (cache_core_check_params(&p1, "node_l1", err, errlen) || cache_core_check_params(&p2, "node_l2", err, errlen) ||
        cache_core_check_params(&pp, "prim", err, errlen))
        return NULL;
    if (p1.line_bytes > p2.line_bytes) {
        snprintf(err, errlen, "node_l1.line = %u must be <= node_l2.line = %u (an L1 fill is one L2 line)",
                 p1.line_bytes, p2.line_bytes);
        return NULL;
    }
    memsys *ms = calloc(1, sizeof *ms);
    if (!ms) {
        snprintf(err, errlen, "memsys: out of memory");
        return NULL;
    }
    ms->ntrv = ntrv;
    ms->model = (memsys_model)rtcfg_enum(cfg, "memory.model");
    char name[64];
    ks_fifo *l1_miss[MEMSYS_MAX_TRV], *l1_fill[MEMSYS_MAX_TRV];

    /* what a FIFO's item carries: a request, or a line of the cache it fills
     * (the memory's responses fill the node L2 and the primitive cache) */
    uint32_t mem_line = p2.line_bytes > pp.line_bytes ? p2.line_bytes : pp.line_bytes;
#define FIFO(var, nm, key, type, line)                                                                                 \
    do {                                                                                                               \
        if (!((var) = mk_fifo(ms, sim, clk, cfg, (nm), (key), sizeof(type), (line), err, errlen)))                    \
            goto fail;                                                                                                 \
    } while (0)

    for (int i = 0; i < ntrv; i++) {
        snprintf(name, sizeof name, "node_l1_%d", i);
        if (!(ms->l1[i] = cache_create(sim, clk, name, &p1, err, errlen)))
            goto fail;
        snprintf(name, sizeof name, "node_l1_%d.miss", i);
        FIFO(l1_miss[i], name, "fifo.mem_l1_miss", mem_req, 0);
        snprintf(name, sizeof name, "node_l1_%d.fill", i);
        FIFO(l1_fill[i], name, "fifo.mem_l1_fill", mem_resp, p1.line_bytes);
        cache_connect(ms->l1[i], l1_miss[i], l1_fill[i], NULL, NULL);
    }
    ks_fifo *l2_req, *l2_resp, *l2_miss, *l2_fill, *prim_miss, *prim_fill, *mem_req_f, *mem_resp_f;
    FIFO(l2_req, "node_l2.req", "fifo.mem_l2_req", mem_req, 0);
    FIFO(l2_resp, "node_l2.resp", "fifo.mem_l2_resp", mem_resp, p1.line_bytes);   /* an L1 line */
    FIFO(l2_miss, "node_l2.miss", "fifo.mem_l2_miss", mem_req, 0);
    FIFO(l2_fill, "node_l2.fill", "fifo.mem_l2_fill", mem_resp, p2.line_bytes);
    FIFO(prim_miss, "prim.miss", "fifo.mem_prim_miss", mem_req, 0);
    FIFO(prim_fill, "prim.fill", "fifo.mem_prim_fill", mem_resp, pp.line_bytes);
    FIFO(mem_req_f, "memory.req", "fifo.mem_req", mem_req, 0);
    FIFO(mem_resp_f, "memory.resp", "fifo.mem_resp", mem_resp, mem_line);
    if (!(ms->l2_arb = mem_arbiter_create(sim, clk, "l2_arbiter", ntrv, err, errlen)))
        goto fail;
    mem_arbiter_connect(ms->l2_arb, l1_miss, l1_fill, l2_req, l2_resp);
    if (!(ms->l2 = cache_create(sim, clk, "node_l2", &p2, err, errlen)))
        goto fail;
    cache_connect(ms->l2, l2_miss, l2_fill, l2_req, l2_resp);
    if (!(ms->prim = cache_create(sim, clk, "prim", &pp, err, errlen)))
        goto fail;
    cache_connect(ms->prim, prim_miss, prim_fill, NULL, NULL);
    ks_fifo *mem_in[2] = {l2_miss, prim_miss}, *mem_out[2] = {l2_fill, prim_fill};
    if (!(ms->mem_arb = mem_arbiter_create(sim, clk, "mem_arbiter", 2, err, errlen)))
        goto fail;
    mem_arbiter_connect(ms->mem_arb, mem_in, mem_out, mem_req_f, mem_resp_f);
    uint32_t outstanding = (uint32_t)rtcfg_int(cfg, "memory.max_outstanding");
    if (ms->model == MEMSYS_FIXED) {
        /* GB/s at the accelerator clock: bytes per cycle = GB/s * 1000 / MHz */
        double bpc = rtcfg_real(cfg, "memory.fixed_bandwidth_gbs") * 1000.0 / rtcfg_real(cfg, "machine.clock_mhz");
        if (!(ms->fmem = fixed_mem_create(sim, clk, "memory", (uint32_t)rtcfg_int(cfg, "memory.fixed_latency"), bpc,
                                          outstanding, err, errlen)))
            goto fail;
        fixed_mem_connect(ms->fmem, mem_req_f, mem_resp_f);
    } else {
        char path[RTCFG_PATH_MAX], why[RTCFG_MSG_MAX];
        /* the standard file with the [dram] keys of the configuration (memsys_config.h) */
        ms->spec = calloc(1, sizeof *ms->spec);
        if (!ms->spec) {
            snprintf(err, errlen, "memory.dram_config: out of memory");
            goto fail;
        }
        if (memsys_dram_spec_load(cfg, ms->spec, err, errlen))
            goto fail;
        const char *pfile = rtcfg_str(cfg, "memory.dram_power");
        if (*pfile) {
            if (snprintf(path, sizeof path, "%s%s%s", strchr(pfile, '/') ? "" : rtcfg_data_dir(),
                         strchr(pfile, '/') ? "" : "/", pfile) >= (int)sizeof path) {
                snprintf(err, errlen, "memory.dram_power = %s: path longer than %d characters", pfile,
                         RTCFG_PATH_MAX - 1);
                goto fail;
            }
            ms->power = calloc(1, sizeof *ms->power);
            if (!ms->power || dram_power_spec_load(ms->power, path, why, sizeof why)) {
                snprintf(err, errlen, "memory.dram_power = %s: %s", pfile, ms->power ? why : "out of memory");
                goto fail;
            }
        }
        ks_fifo *dreq, *dresp;
        FIFO(dreq, "dram.req", "fifo.mem_dram_req", dram_port_req, 0);
        FIFO(dresp, "dram.resp", "fifo.mem_dram_resp", dram_port_resp, mem_line);
        if (!(ms->adapter = mem_dram_adapter_create(sim, clk, "memory", outstanding, err, errlen)))
            goto fail;
        mem_dram_adapter_connect(ms->adapter, mem_req_f, mem_resp_f, dreq, dresp);
        if (!(ms->port = dram_port_create(sim, "dram", ms->spec, ms->power, dreq, dresp, stats, err, errlen)))
            goto fail;
    }
#undef FIFO
    if (stats) {
        int rc = 0;
        for (int i = 0; i < ntrv; i++) {
            snprintf(name, sizeof name, "node_l1_%d", i);
            rc |= cache_register(ms->l1[i], stats, name);
        }
        rc |= ks_stat_decl_formula(stats, &memsys_totals_module_desc, NULL, "node_l1.hit_rate", l1_hit_rate, ms);
        rc |= cache_register(ms->l2, stats, "node_l2");
        rc |= cache_register(ms->prim, stats, "prim");
        rc |= mem_arbiter_register(ms->l2_arb, stats, "l2_arbiter");
        rc |= mem_arbiter_register(ms->mem_arb, stats, "mem_arbiter");
        if (ms->fmem)
            rc |= fixed_mem_register(ms->fmem, stats, "memory");
        if (ms->adapter)
            rc |= mem_dram_adapter_register(ms->adapter, stats, "memory");
        rc |= ks_stat_decl_formula(stats, &memsys_totals_module_desc, NULL, "memory.bytes_total", memory_bytes_fn, ms);
        if (rc) {
            snprintf(err, errlen, "memsys: registering statistics: %s", ks_stats_error(stats));
            goto fail;
        }
    }
    return ms;
fail:
    memsys_destroy(ms);
    return NULL;
}

void memsys_destroy(memsys *ms)
{
    if (!ms)
        return;
    for (int i = 0; i < ms->ntrv; i++)
        cache_destroy(ms->l1[i]);
    cache_destroy(ms->l2);
    cache_destroy(ms->prim);
    mem_arbiter_destroy(ms->l2_arb);
    mem_arbiter_destroy(ms->mem_arb);
    fixed_mem_destroy(ms->fmem);
    mem_dram_adapter_destroy(ms->adapter);
    dram_port_destroy(ms->port);
    free(ms->spec);
    free(ms->power);
    free(ms);
}

int memsys_trv_count(const memsys *ms) { return ms->ntrv; }
cache_core *memsys_node_l1(memsys *ms, int trv) { return cache_get_core(ms->l1[trv]); }
cache_core *memsys_prim(memsys *ms) { return cache_get_core(ms->prim); }
cache_core *memsys_node_l2(memsys *ms) { return cache_get_core(ms->l2); }
uint32_t memsys_node_l1_latency(const memsys *ms) { return cache_core_get_params(cache_get_core(ms->l1[0]))->hit_latency; }
uint32_t memsys_prim_latency(const memsys *ms) { return cache_core_get_params(cache_get_core(ms->prim))->hit_latency; }
ks_event *memsys_node_l1_filled(memsys *ms, int trv) { return cache_ev_filled(ms->l1[trv]); }
ks_event *memsys_prim_filled(memsys *ms) { return cache_ev_filled(ms->prim); }

cache_unit *memsys_unit(memsys *ms, const char *name)
{
    if (strcmp(name, "node_l2") == 0)
        return ms->l2;
    if (strcmp(name, "prim") == 0)
        return ms->prim;
    for (int i = 0; i < ms->ntrv; i++)
        if (strcmp(name, cache_name(ms->l1[i])) == 0)
            return ms->l1[i];
    return NULL;
}

memsys_model memsys_memory_model(const memsys *ms) { return ms->model; }

uint64_t memsys_memory_bytes(const memsys *ms)
{
    return ms->fmem ? fixed_mem_bytes(ms->fmem) : ms->adapter ? mem_dram_adapter_bytes(ms->adapter) : 0;
}
uint64_t memsys_memory_requests(const memsys *ms)
{
    return ms->fmem ? fixed_mem_requests(ms->fmem) : ms->adapter ? mem_dram_adapter_requests(ms->adapter) : 0;
}
uint64_t memsys_memory_latency_sum(const memsys *ms)
{
    return ms->fmem ? fixed_mem_latency_sum(ms->fmem) : ms->adapter ? mem_dram_adapter_latency_sum(ms->adapter) : 0;
}
const mem_arbiter *memsys_mem_arbiter(const memsys *ms) { return ms->mem_arb; }
dram_port *memsys_dram_port(memsys *ms) { return ms->port; }
const dram_spec *memsys_dram_spec(const memsys *ms) { return ms->spec; }

int memsys_fifo_count(const memsys *ms) { return ms->nfifo; }
ks_fifo *memsys_fifo_at(const memsys *ms, int i, const char **key, uint32_t *line_bytes)
{
    if (i < 0 || i >= ms->nfifo)
        return NULL;
    if (key)
        *key = ms->fifo_key[i];
    if (line_bytes)
        *line_bytes = ms->fifo_line[i];
    return ms->fifo[i];
}

int memsys_busy(const memsys *ms)
{
    for (int i = 0; i < ms->ntrv; i++)
        if (cache_busy(ms->l1[i]))
            return 1;
    if (cache_busy(ms->l2) || cache_busy(ms->prim))
        return 1;
    if (ms->fmem && fixed_mem_busy(ms->fmem))
        return 1;
    if (ms->adapter && mem_dram_adapter_outstanding(ms->adapter))
        return 1;
    for (int i = 0; i < ms->nfifo; i++)
        if (ks_fifo_occupancy(ms->fifo[i]))
            return 1;
    return 0;
}

static const struct {
    const char *alias;
    const ks_module_desc *desc;
} module_aliases[] = {
    {"node_l1", &cache_module_desc},      {"node_l2", &cache_module_desc},  {"prim", &cache_module_desc},
    {"l2_arbiter", &mem_arbiter_module_desc},  {"mem_arbiter", &mem_arbiter_module_desc}, {"fixed", &fixed_mem_module_desc},
    {"memory", &mem_dram_adapter_module_desc}, {"lpddr3", &dram_port_module_desc},
};
static const ks_module_desc *const module_all[] = {&cache_module_desc, &mem_arbiter_module_desc, &fixed_mem_module_desc,
                                                   &mem_dram_adapter_module_desc, &dram_port_module_desc, &memsys_totals_module_desc};

const ks_module_desc *memsys_module_desc(const char *name)
{
    for (size_t i = 0; i < sizeof module_all / sizeof module_all[0]; i++)
        if (strcmp(module_all[i]->name, name) == 0)
            return module_all[i];
    for (size_t i = 0; i < sizeof module_aliases / sizeof module_aliases[0]; i++)
        if (strcmp(module_aliases[i].alias, name) == 0)
            return module_aliases[i].desc;
    return NULL;
}

void memsys_module_list(FILE *out)
{
    for (size_t i = 0; i < sizeof module_all / sizeof module_all[0]; i++)
        fprintf(out, "%s%s", i ? ", " : "", module_all[i]->name);
}
