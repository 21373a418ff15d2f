/* accel_top.c — the top-level assembly (see accel_top.h). */
#include "model/accel_top.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/interrupt.h"
#include "kernel/vcd.h"
#include "model/dram/dram_ctrl.h"
#include "model/dram/dram_port.h"
#include "model/energy/energy.h"
#include "model/dram/dram_timing.h"
#include "model/ray/ist.h"
#include "model/mem/memsys.h"
#include "model/ray/sort_net.h"
#include "model/ray/trv.h"

#define SLICE_CYCLES 65536u
/* Slices while running to a mark (accel_top_run_until): how far past the
 * mark a window may end, against the thousands of cycles a window lasts. */
#define MARK_SLICE_CYCLES 256u
/* The kernel detector's margin over the machine's longest wait: the fixed
 * window it had before the bound was derived (kernel/sim.h default). */
#define ACCEL_DEADLOCK_MARGIN 100000u

struct accel_top {
    accel_params p;
    accel_image img;
    accel_source src;
    ks_sim *sim;
    ks_clock *clk;
    ks_stats *stats;
    ks_vcd *vcd;
    accel_ray *rays;
    sched_unit *sched;
    trv_unit **trv;
    ist_unit *ist;
    memsys *mem;
    energy_model *energy;
    /* the ray side's FIFOs, per row of accel_ray_fifos (accel_config.h) and
     * instance (the TRV's index, or 0): a kernel FIFO, or the consumer's
     * ring for a ring row */
    ks_fifo **fifo[ACCEL_FIFO_COUNT];
    const pipe_ring **ring[ACCEL_FIFO_COUNT];
    char (*names)[32];
    uint64_t cycles, rays_done;
    double mrps, seconds;
    /* derived statistics */
    uint64_t stat_cycles, stat_rays, stat_dram_bytes;
    uint64_t stat_failed;      /* the run stopped on a failure */
    char failure[128];         /* its one-line cause, "" when none */
    /* failure detection (docs/accel.md "Machines that cannot run, failure bounds, the livelock guard") */
    uint64_t longest_wait;     /* the longest a valid run may do no work, cycles */
    uint64_t deadlock_window;  /* kernel detector: no progress of any unit */
    uint64_t livelock_window;  /* watchdog: no committed work (0 = off) */
    uint64_t guard_cycle;      /* where the livelock guard was engaged, 0: never */
    double stat_mrps, stat_dram_gbs, stat_in_flight;
    uint64_t stat_traffic[6];   /* dram_node_bytes .. dram_refetch_misses (traffic_stats) */
    double stat_dram_pj_per_byte;
    accel_series *series;      /* interval statistics, NULL: none (model/series.h) */
    uint64_t *series_busy;     /* the TRVs' busy cycles at a sample */
    /* what each utilization statistic divides: a unit's busy cycles (the
     * TRVs', then the IST's) by the frame's cycles */
    struct util_ref {
        const uint64_t *busy, *cycles;
    } util[ACCEL_MAX_TRV + 1];
};

/* Instances of a row of accel_ray_fifos: one per TRV, or one. */
static uint32_t ray_fifo_instances(const accel_top *t, const accel_fifo_desc *d)
{
    return accel_fifo_per_trv(d) ? t->p.trv_count : 1;
}

/* Creates the kernel FIFOs of the ray side from accel_ray_fifos, TRV by
 * TRV in the table's order (trv0.new, trv0.leaf, ..., trv1.new, ...), and
 * records the rings the TRVs and the IST hold for the ring rows. */
static int build_ray_fifos(accel_top *t, const rtcfg *cfg, char *err, size_t errlen)
{
    for (int r = 0; r < ACCEL_FIFO_COUNT; r++) {
        size_t n = ray_fifo_instances(t, &accel_ray_fifos[r]);
        if (!(t->fifo[r] = calloc(n, sizeof *t->fifo[r])) || !(t->ring[r] = calloc(n, sizeof *t->ring[r]))) {
            snprintf(err, errlen, "out of memory for the ray-side FIFOs");
            return -1;
        }
    }
    for (uint32_t i = 0; i < t->p.trv_count; i++) {
        t->ring[ACCEL_FIFO_TRV_LOOP][i] = &t->trv[i]->loop;
        for (int r = 0; r < ACCEL_FIFO_COUNT; r++) {
            const accel_fifo_desc *d = &accel_ray_fifos[r];
            if (d->ring || i >= ray_fifo_instances(t, d))
                continue;
            char nm[64];
            uint32_t cap = (uint32_t)rtcfg_int(cfg, d->key);
            accel_fifo_expand(d->name, i, nm, sizeof nm);
            t->fifo[r][i] = ks_fifo_create(t->sim, nm, sizeof(trv_msg), cap, t->p.fifo_latency, t->clk);
            if (!t->fifo[r][i]) {
                char from[32], to[32];
                snprintf(err, errlen, "FIFO %s (%s = %u, %s -> %s): %s", nm, d->key, cap,
                         accel_fifo_expand(d->producer, i, from, sizeof from),
                         accel_fifo_expand(d->consumer, i, to, sizeof to), ks_sim_error(t->sim));
                return -1;
            }
        }
    }
    t->ring[ACCEL_FIFO_IST_LOOP][0] = &t->ist->loop;
    return 0;
}

static double util_formula(const ks_stats *reg, void *user)
{
    (void)reg;
    const struct util_ref *u = user;
    double cyc = (double)*u->cycles;
    return cyc > 0 ? (double)*u->busy / cyc : 0.0;
}

/* unit.utilization: its busy cycles over the frame's, through t->util[k]. */
static int register_util(accel_top *t, int k, const ks_module_desc *d, const char *unit, const uint64_t *busy)
{
    t->util[k] = (struct util_ref){busy, &t->stat_cycles};
    return ks_stat_decl_formula(t->stats, d, unit, "utilization", util_formula, &t->util[k]);
}

/* The frame's figures, registered by the top level itself. */
static const ks_desc_item accel_items[] = {
    {KS_DESC_STAT, "cycles", "cycles", "", "",
     "accelerator cycles of the frame (to the last ray's completion, or to where a failed run stopped)"},
    {KS_DESC_STAT, "run_failed", "flag", "", "",
     "1 when the run stopped on a deadlock, a livelock or stack overflows: the statistics then cover the cycles "
     "simulated until it stopped"},
    {KS_DESC_STAT, "rays", "rays", "", "", "rays traced (primary and bounce)"},
    {KS_DESC_STAT, "mrps", "Mrays/s", "", "", "million rays per second at the machine clock"},
    {KS_DESC_STAT, "dram_bytes", "bytes", "", "", "bytes transferred from/to main memory"},
    {KS_DESC_STAT, "dram_bandwidth_gbs", "GB/s", "", "", "mean main memory bandwidth over the frame"},
    {KS_DESC_STAT, "rays_in_flight_mean", "rays", "", "", "time-averaged rays in flight"},
    /* what explains the DRAM traffic (docs/results.md "DRAM traffic"): the
     * memory arbiter's per-input counts, input 0 the node L2, 1 the
     * primitive cache (model/mem/mem_arbiter.h) */
    {KS_DESC_STAT, "dram_node_bytes", "bytes", "", "", "main memory bytes of node fills (node L2 misses)"},
    {KS_DESC_STAT, "dram_triangle_bytes", "bytes", "", "", "main memory bytes of triangle fills (primitive cache misses)"},
    {KS_DESC_STAT, "dram_footprint_bytes", "bytes", "", "",
     "distinct bytes the frame read from main memory (32-byte granules): the traffic of a cache that never evicts"},
    {KS_DESC_STAT, "dram_refetch_bytes", "bytes", "", "",
     "main memory bytes read again after an eviction (capacity and conflict misses): dram_bytes - footprint"},
    {KS_DESC_STAT, "dram_compulsory_misses", "requests", "", "",
     "line fills whose line no earlier fill of the frame touched (first touch)"},
    {KS_DESC_STAT, "dram_refetch_misses", "requests", "", "", "line fills of a line filled before (refetches)"},
    {KS_DESC_STAT, "dram_pj_per_byte", "pJ/byte", "", "",
     "DRAM energy (dynamic and background) per byte transferred; 0 without energy or traffic"},
    {KS_DESC_END, 0, 0, 0, 0, 0},
};
const ks_module_desc accel_top_module_desc = {"accel", "the frame's figures (top level)", accel_items, "machine"};

static double fifo_writes_fn(const ks_stats *reg, void *user)
{
    (void)reg;
    return (double)ks_fifo_total_writes(user);
}

static double fifo_reads_fn(const ks_stats *reg, void *user)
{
    (void)reg;
    return (double)ks_fifo_total_reads(user);
}

/* fifo.<name>.writes and .reads for every FIFO of the sim (energy: each
 * access of a FIFO's RAM). */
static int register_fifo_stats(accel_top *t)
{
    int rc = 0;
    for (uint32_t i = 0; i < ks_sim_fifo_count(t->sim); i++) {
        ks_fifo *f = ks_sim_fifo_at(t->sim, i);
        char nm[128];
        snprintf(nm, sizeof nm, "fifo.%s", ks_fifo_name(f));
        rc |= ks_stat_decl_formula(t->stats, &ks_fifo_module_desc, nm, "writes", fifo_writes_fn, f);
        rc |= ks_stat_decl_formula(t->stats, &ks_fifo_module_desc, nm, "reads", fifo_reads_fn, f);
    }
    return rc;
}

static int energy_fifo_index(energy_machine *m, const char *key)
{
    for (int i = 0; i < m->nfifo; i++)
        if (!strcmp(m->fifo[i].key, key))
            return i;
    return -1;
}

static void energy_add_fifo(energy_machine *m, const char *key, double entries, double width)
{
    int i = energy_fifo_index(m, key);
    if (i < 0 && m->nfifo < (int)(sizeof m->fifo / sizeof m->fifo[0])) {
        i = m->nfifo++;
        m->fifo[i].key = key;
        m->fifo[i].entries = entries;
        m->fifo[i].width_bytes = width;
    }
    if (i >= 0)
        m->fifo[i].count++;
}

/* The machine as the energy model sees it: its FPUs, stacks, caches and
 * FIFOs (energy.h). */
static energy_model *build_energy_model(accel_top *t, const rtcfg *cfg, char *err, size_t errlen)
{
    energy_machine m = {0};
    const trv_core_params *c = &t->p.trv.core;
    m.trv_count = t->p.trv_count;
    m.trv_flop_units = (double)t->p.width * t->p.trv.box_flops + sort_net_get(t->p.width)->ncmps;
    m.ist_flop_units = t->p.ist.flops_per_test;
    m.stack_slots = c->slots;
    m.stack_depth = c->stack_depth;
    m.stack_banks = c->stack_banks;
    /* a node reference, plus its distance with the distance stack (sec. 3.1) */
    m.stack_entry_bytes = c->distance_cull ? 8 : 4;
    static const char *const caches[3] = {"node_l1", "node_l2", "prim"};
    for (int i = 0; i < 3; i++) {
        m.cache[i].name = caches[i];
        m.cache[i].count = i == 0 ? t->p.trv_count : 1;
        cache_params cp;
        memsys_cache_params(cfg, caches[i], &cp);
        /* the array built: an index-addressed cache holds whole node words
         * (cache.h), a node-sized word the SRAM table may lack (energy_table.h) */
        m.cache[i].size = (double)cache_core_capacity_bytes(&cp);
        m.cache[i].line = (double)cp.line_bytes;
        m.cache[i].ways = (double)cp.ways;
        m.cache[i].ports = cp.ports;
        m.cache[i].banks = cp.banks;
        m.cache[i].node_word = cp.index_addressed;
    }
    m.ncache = 3;
    /* the ray side's FIFOs carry a ray each; the memory side's a line or a request */
    double ray_bytes = (double)rtcfg_int(cfg, "energy.fifo_ray_bytes");
    for (int r = 0; r < ACCEL_FIFO_COUNT; r++) {
        const accel_fifo_desc *d = &accel_ray_fifos[r];
        for (uint32_t i = 0; i < ray_fifo_instances(t, d); i++)
            energy_add_fifo(&m, d->key, (double)rtcfg_int(cfg, d->key), ray_bytes);
    }
    double req_bytes = (double)rtcfg_int(cfg, "energy.fifo_request_bytes");
    for (int i = 0; i < memsys_fifo_count(t->mem); i++) {
        const char *key = NULL;
        uint32_t line = 0;
        ks_fifo *f = memsys_fifo_at(t->mem, i, &key, &line);
        energy_add_fifo(&m, key, ks_fifo_capacity(f), line ? line : req_bytes);
    }
    m.dram_modeled = memsys_dram_port(t->mem) && *rtcfg_str(cfg, "memory.dram_power");
    m.fixed_mem_pj_per_byte = rtcfg_real(cfg, "energy.fixed_mem_pj_per_byte");
    energy_model *em = energy_model_create(cfg, &m, err, errlen);
    /* every part must be declared in its unit's description (--help-module),
     * so a unit cannot add energy or area unseen */
    for (int i = 0; em && i < em->nparts; i++) {
        const energy_part *p = &em->parts[i];
        const ks_module_desc *d = p->module ? accel_module_desc(p->module) : NULL;
        if (!d || !ks_module_desc_find(d, KS_DESC_PART, p->decl)) {
            snprintf(err, errlen, "energy part %s is not declared in the description of module %s", p->name,
                     p->module ? p->module : "(none)");
            energy_model_destroy(em);
            em = NULL;
        }
    }
    return em;
}

void accel_top_figures(const accel_top *t, accel_figures *out)
{
    accel_figures f = {0};
    f.cycles = t->stat_cycles;
    f.rays = t->stat_rays;
    f.mrps = t->stat_mrps;
    f.dram_bytes = t->stat_dram_bytes;
    f.dram_gbs = t->stat_dram_gbs;
    f.in_flight_mean = t->stat_in_flight;
    f.dram_node_bytes = t->stat_traffic[0];
    f.dram_triangle_bytes = t->stat_traffic[1];
    f.dram_footprint_bytes = t->stat_traffic[2];
    f.dram_refetch_bytes = t->stat_traffic[3];
    f.dram_compulsory_misses = t->stat_traffic[4];
    f.dram_refetch_misses = t->stat_traffic[5];
    f.dram_pj_per_byte = t->stat_dram_pj_per_byte;
    const sched_unit *s = t->sched;
    f.primaries = s->primaries;
    f.bounces = s->bounces;
    f.failed = s->failed;
    f.occlusion = s->src.occlusion;   /* as sched_register */
    f.occlusion_rays = s->occlusion_rays;
    f.occluded = s->occluded;
    f.max_in_flight = s->max_in_flight;
    f.latency_mean = sched_latency_mean(s);
    f.trv_count = t->p.trv_count;
    for (uint32_t i = 0; i < t->p.trv_count; i++) {
        const trv_unit *u = t->trv[i];
        f.trv_busy_cycles[i] = u->busy_cycles;
        f.trv_flops += u->flops;
        f.trv_sort_passes += u->core.st.sort_passes;
        f.trv_stack_pops += u->core.stack.st.pops;
        f.trv_stack_pushes += u->core.stack.st.pushes;
        f.trv_issue_loop += u->issue_loop;
        const cache_stats *cs = cache_core_stats_live(memsys_node_l1(t->mem, (int)i));
        f.node_l1.accesses += cs->accesses;
        f.node_l1.hits += cs->hits;
        f.node_l1.fills += cs->fills;
    }
    f.ist_busy_cycles = t->ist->busy_cycles;
    f.ist_flops = t->ist->flops;
    f.ist_loops_miss = t->ist->core.st.loops_miss;
    f.ist_loops_blocked = t->ist->core.st.loops_blocked;
    accel_cache_figures *level[2] = {&f.node_l2, &f.prim};
    const cache_core *core[2] = {memsys_node_l2(t->mem), memsys_prim(t->mem)};
    for (int k = 0; k < 2; k++) {
        const cache_stats *cs = cache_core_stats_live(core[k]);
        *level[k] = (accel_cache_figures){cs->accesses, cs->hits, cs->fills};
    }
    for (int k = 0; k < 2; k++)
        mem_arbiter_input(memsys_mem_arbiter(t->mem), k, &f.mem_arbiter[k]);
    f.mem_requests = memsys_memory_requests(t->mem);
    f.mem_latency_sum = memsys_memory_latency_sum(t->mem);
    dram_port *port = memsys_dram_port(t->mem);
    if (port) {
        f.lpddr3 = true;
        f.row_hit_rate = dram_port_row_hit_rate(port);
    }
    if (t->energy) {
        const energy_result *r = &t->energy->r;
        f.energy = true;
        f.energy_mj = r->total_energy_mj;
        memcpy(f.unit_mj, r->energy_mj, sizeof f.unit_mj);
        memcpy(f.unit_dynamic_mj, r->dynamic_mj, sizeof f.unit_dynamic_mj);
        memcpy(f.unit_static_mj, r->static_mj, sizeof f.unit_static_mj);
        if (t->energy->m.dram_modeled) {
            f.dram_energy = true;
            dram_port_energy_uJ(port, &f.dram_energy_uJ, &f.dram_background_uJ);
        }
    }
    *out = f;
}

/* Adds the reads and writes of kernel FIFO ff to the energy model's FIFO j. */
static void add_fifo_activity(energy_activity *a, int j, const ks_fifo *ff)
{
    a->fifo_reads[j] += (double)ks_fifo_total_reads(ff);
    a->fifo_writes[j] += (double)ks_fifo_total_writes(ff);
}

/* The writes of ring row r of accel_ray_fifos over all its instances (=
 * its reads: a ray written to a loop ring comes back once): every ray a
 * TRV issues from its loop was written to it; a ray goes round the IST's
 * loop after each missed or blocked test. */
static double ring_writes(const accel_figures *f, accel_fifo_id r)
{
    switch (r) {
    case ACCEL_FIFO_TRV_LOOP: return (double)f->trv_issue_loop;
    case ACCEL_FIFO_IST_LOOP: return (double)f->ist_loops_miss + (double)f->ist_loops_blocked;
    default: return 0;
    }
}

/* The energy activity of the run so far, from its figures f
 * (accel_top_figures) and the FIFOs' counts: every count the energy model
 * prices, seconds of frame time, DRAM energy up to the DRAM port's
 * statistics end (the current time until finish_stats sets it) and
 * dram_bytes. The counts are whole numbers below 2^53, so their sums are
 * exact in any order. */
static void gather_activity(accel_top *t, const accel_figures *f, double seconds, double dram_bytes,
                            energy_activity *out)
{
    energy_model *em = t->energy;
    energy_activity a = {0};
    a.seconds = seconds;
    /* slab tests of all lanes, and one FLOP per comparator of each sort */
    double comparators = sort_net_get(t->p.width)->ncmps;
    a.trv_flops = (double)f->trv_flops + comparators * (double)f->trv_sort_passes;
    a.stack_reads = (double)f->trv_stack_pops;
    a.stack_writes = (double)f->trv_stack_pushes;
    /* the ray side's FIFOs: kernel FIFOs, or rings (accel_config.h) */
    for (int r = 0; r < ACCEL_FIFO_COUNT; r++) {
        const accel_fifo_desc *d = &accel_ray_fifos[r];
        int j = energy_fifo_index(&em->m, d->key);
        if (j < 0)
            continue;
        if (d->ring) {
            a.fifo_reads[j] += ring_writes(f, (accel_fifo_id)r);
            a.fifo_writes[j] += ring_writes(f, (accel_fifo_id)r);
            continue;
        }
        for (uint32_t i = 0; i < ray_fifo_instances(t, d); i++)
            add_fifo_activity(&a, j, t->fifo[r][i]);
    }
    a.ist_flops = (double)f->ist_flops;
    const accel_cache_figures *level[3] = {&f->node_l1, &f->node_l2, &f->prim};
    for (int k = 0; k < 3; k++) {
        a.cache_reads[k] = (double)level[k]->accesses;
        a.cache_writes[k] = (double)level[k]->fills;
    }
    for (int i = 0; i < memsys_fifo_count(t->mem); i++) {
        const char *key = NULL;
        ks_fifo *ff = memsys_fifo_at(t->mem, i, &key, NULL);
        int j = energy_fifo_index(&em->m, key);
        if (j >= 0)
            add_fifo_activity(&a, j, ff);
    }
    if (f->dram_energy) {
        a.dram_dynamic_nj = (f->dram_energy_uJ - f->dram_background_uJ) * 1e3;
        a.dram_static_nj = f->dram_background_uJ * 1e3;
    }
    a.dram_bytes = dram_bytes;
    *out = a;
}

static void compute_energy(accel_top *t)
{
    accel_figures f;
    energy_activity a;
    accel_top_figures(t, &f);
    gather_activity(t, &f, t->seconds, (double)f.dram_bytes, &a);
    energy_compute(t->energy, &a, f.mrps);
}

static const char *const traffic_stat_names[6] = {"dram_node_bytes",      "dram_triangle_bytes",
                                                  "dram_footprint_bytes", "dram_refetch_bytes",
                                                  "dram_compulsory_misses", "dram_refetch_misses"};

/* The frame's DRAM traffic by kind and cause, from the memory arbiter's
 * counts (input 0: node L2, 1: primitive cache). */
static void traffic_stats(accel_top *t)
{
    accel_figures f;
    accel_top_figures(t, &f);
    const mem_arbiter_input_stats *in = f.mem_arbiter;
    uint64_t *v = t->stat_traffic;
    v[0] = in[0].bytes;
    v[1] = in[1].bytes;
    v[2] = in[0].footprint_bytes + in[1].footprint_bytes;
    v[3] = v[0] + v[1] > v[2] ? v[0] + v[1] - v[2] : 0;
    v[4] = in[0].first_touch + in[1].first_touch;
    v[5] = in[0].refetches + in[1].refetches;
}

static uint64_t ceil_div(uint64_t a, uint64_t b) { return b ? (a + b - 1) / b : 0; }

/* An upper bound, in accelerator cycles, on how long a valid run of the
 * machine cfg may go without any committed work (a node visit, a triangle
 * test, a completed ray): a bounce ray waiting for its shading
 * (sched.shade_latency), then line fetches one after the other, as many as
 * the caches can have outstanding at once (every MSHR: a downstream cache
 * with one MSHR serializes them, and a node may need up to 8 lines), each
 * a round trip through every FIFO, cache and arbiter to the memory and back
 * at the memory's slowest (fixed: latency + one line at the configured
 * bandwidth; LPDDR3: a row miss, PRE + ACT + RD each at the spec's largest
 * constraint, per burst, plus postponed refreshes), doubled. Only a failed
 * run waits this long, so a loose bound costs nothing but time before a
 * real livelock is reported; one too tight turns a valid run into a false
 * failure. */
static uint64_t longest_wait_of(const rtcfg *cfg, const accel_params *p, const memsys *mem, uint32_t ist_pipe)
{
    double period_ps = 1e6 / p->clock_mhz;
    uint64_t line = (uint64_t)memsys_line_bytes(cfg, "node_l2");
    if ((uint64_t)memsys_line_bytes(cfg, "prim") > line)
        line = (uint64_t)memsys_line_bytes(cfg, "prim");
    uint64_t memory;
    const dram_spec *spec = memsys_dram_spec(mem);
    if (spec) {
        int32_t worst = 0;
        for (int i = 0; i < spec->nconstraints; i++)
            if (spec->constraint[i].cycles > worst)
                worst = spec->constraint[i].cycles;
        uint64_t per_burst = 3 * (uint64_t)worst + (uint64_t)spec->read_latency;
        uint64_t per_req = per_burst * ceil_div(line, spec->tx_bytes > 0 ? (uint64_t)spec->tx_bytes : 1);
        uint64_t dram_cycles = per_req + (uint64_t)(1 + spec->max_postponed_refresh) * (uint64_t)worst;
        memory = (uint64_t)ceil((double)dram_cycles * spec->tck_ps / period_ps);
    } else {
        double gbs = rtcfg_real(cfg, "memory.fixed_bandwidth_gbs");
        /* one line at gbs GB/s, in cycles of p->clock_mhz */
        uint64_t transfer = gbs > 0 ? (uint64_t)ceil((double)line * p->clock_mhz * 1e6 / (gbs * 1e9)) : 0;
        memory = (uint64_t)rtcfg_int(cfg, "memory.fixed_latency") + transfer + 1;
    }
    uint64_t round_trip = memory +
                          (uint64_t)(rtcfg_int(cfg, "node_l1.hit_latency") + rtcfg_int(cfg, "node_l2.hit_latency") +
                                     rtcfg_int(cfg, "prim.hit_latency")) +
                          12 * (uint64_t)rtcfg_int(cfg, "fifo.mem_latency") + 6 * (uint64_t)p->fifo_latency +
                          ist_pipe + accel_trv_depth_of(cfg);
    uint64_t fetches = (uint64_t)p->trv_count * (uint64_t)rtcfg_int(cfg, "node_l1.mshrs") +
                       (uint64_t)(rtcfg_int(cfg, "node_l2.mshrs") + rtcfg_int(cfg, "prim.mshrs")) + 1;
    return (uint64_t)p->sched.shade_latency + 2 * fetches * round_trip;
}

accel_top *accel_top_create(const rtcfg *cfg, const accel_image *img, const accel_source *src,
                            const accel_top_opts *opts, char *err, size_t errlen)
{
    accel_top_opts noopts = {0};
    if (!opts)
        opts = &noopts;
    accel_top *t = calloc(1, sizeof *t);
    if (!t) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    accel_params_get(cfg, &t->p);
    t->img = *img;
    t->src = *src;
    if (img->width != t->p.width) {
        snprintf(err, errlen, "machine.branching = %d but the BVH image is %d-wide (build the BVH with width %d)",
                 t->p.width, img->width, t->p.width);
        free(t);
        return NULL;
    }
    uint32_t ntrv = t->p.trv_count, slots = t->p.trv.core.slots;
    if (ntrv > ACCEL_MAX_TRV) {   /* trv.count's range keeps it within */
        snprintf(err, errlen, "trv.count = %u: at most %d TRVs", ntrv, ACCEL_MAX_TRV);
        free(t);
        return NULL;
    }
    t->sim = ks_sim_create();
    t->stats = ks_stats_create();
    ks_time period = (ks_time)llround(1e6 / t->p.clock_mhz);
    t->clk = ks_clock_create(t->sim, "clk", period);
    if (opts->vcd_path) {
        ks_time end = opts->vcd_end_cycle ? (ks_time)opts->vcd_end_cycle * period : KS_TIME_MAX;
        t->vcd = ks_vcd_open(t->sim, opts->vcd_path, "1ns", (ks_time)opts->vcd_begin_cycle * period, end,
                             opts->vcd_filter);
        if (!t->vcd) {
            snprintf(err, errlen, "--vcd %s: %s", opts->vcd_path, ks_sim_error(t->sim));
            accel_top_destroy(t);
            return NULL;
        }
    }
    t->rays = calloc((size_t)ntrv * slots, sizeof *t->rays);
    t->trv = calloc(ntrv, sizeof *t->trv);
    t->names = calloc(ntrv, sizeof *t->names);
    if (!t->rays || !t->trv || !t->names) {
        snprintf(err, errlen, "out of memory for %u TRVs x %u slots", ntrv, slots);
        accel_top_destroy(t);
        return NULL;
    }
    /* the memory side first: the TRV fetch stages and the IST's front take
     * the L1 and primitive cache hit latencies */
    t->mem = memsys_build(t->sim, t->clk, cfg, (int)ntrv, t->stats, err, errlen);
    if (!t->mem) {
        accel_top_destroy(t);
        return NULL;
    }
    /* trv.stages_fetch is the node L1 hit latency (accel_params_get) */
    assert(t->p.trv.stages_fetch == memsys_node_l1_latency(t->mem));
    t->p.ist.latency += memsys_prim_latency(t->mem);
    /* failure detection windows derived from the machine: the kernel's
     * detector (no unit made progress) and the watchdog (no committed work:
     * node visits, triangle tests, completed rays), each the configured
     * margin plus the longest wait of a valid run */
    t->longest_wait = longest_wait_of(cfg, &t->p, t->mem, t->p.ist.latency + 1);
    t->deadlock_window = (opts->deadlock_cycles ? opts->deadlock_cycles : ACCEL_DEADLOCK_MARGIN) + t->longest_wait;
    t->livelock_window = t->p.sched.watchdog_cycles ? t->p.sched.watchdog_cycles + t->longest_wait : 0;
    ks_sim_set_deadlock_cycles(t->sim, t->deadlock_window);
    /* units, in the order they are stepped each cycle: consumers of a FIFO
     * see its items at the ready time whatever the order (latency >= 1) */
    if (!(t->sched = sched_create("sched", &t->p.sched, src, t->rays, ntrv, slots, t->clk, err, (unsigned)errlen))) {
        accel_top_destroy(t);
        return NULL;
    }
    for (uint32_t i = 0; i < ntrv; i++) {
        snprintf(t->names[i], sizeof t->names[i], "trv%u", i);
        if (!(t->trv[i] = trv_create(i, t->names[i], &t->p.trv, &t->img, t->rays, t->sim, t->clk,
                                     (uint32_t)rtcfg_int(cfg, accel_ray_fifos[ACCEL_FIFO_TRV_LOOP].key), err,
                                     (unsigned)errlen))) {
            accel_top_destroy(t);
            return NULL;
        }
    }
    if (!(t->ist = ist_create("ist", &t->p.ist, &t->img, t->rays, t->sim, t->clk,
                              (uint32_t)rtcfg_int(cfg, accel_ray_fifos[ACCEL_FIFO_IST_LOOP].key), 0, err,
                              (unsigned)errlen))) {
        accel_top_destroy(t);
        return NULL;
    }
    if (build_ray_fifos(t, cfg, err, errlen))
        goto fail;
    ks_fifo **f_new = t->fifo[ACCEL_FIFO_NEW], **f_leaf = t->fifo[ACCEL_FIFO_LEAF],
            **f_ret = t->fifo[ACCEL_FIFO_RETURN], **f_done = t->fifo[ACCEL_FIFO_DONE];
    for (uint32_t i = 0; i < ntrv; i++) {
        trv_connect(t->trv[i], f_new[i], f_ret[i], f_leaf[i], f_done[i]);
        if (opts->events)
            trv_set_events(t->trv[i], opts->events, opts->events_user);
    }
    sched_connect(t->sched, f_new, f_done);
    ist_connect(t->ist, ntrv, f_leaf, f_ret);
    if (opts->events)
        ist_set_events(t->ist, opts->events, opts->events_user);

    for (uint32_t i = 0; i < ntrv; i++) {
        trv_set_probe(t->trv[i], cache_core_probe, memsys_node_l1(t->mem, (int)i));
        t->trv[i]->core.present = cache_core_present;
        ks_clocked_wake_on(t->trv[i]->proc, memsys_node_l1_filled(t->mem, (int)i));
    }
    ist_set_probe(t->ist, cache_core_probe, memsys_prim(t->mem));
    ks_clocked_wake_on(t->ist->proc, memsys_prim_filled(t->mem));
    if (opts->exhaustive) {
        ks_clock_set_exhaustive(t->clk, 1);
        if (memsys_dram_port(t->mem))
            ks_clock_set_exhaustive(dram_port_clock(memsys_dram_port(t->mem)), 1);
    }

    /* statistics: the frame's figures first, then per unit, each from its
     * unit's description (an undeclared name fails here) */
    const ks_module_desc *top = &accel_top_module_desc;
    int rc = 0;
    rc |= ks_stat_decl_counter(t->stats, top, NULL, "cycles", &t->stat_cycles);
    rc |= ks_stat_decl_counter(t->stats, top, NULL, "run_failed", &t->stat_failed);
    rc |= ks_stat_decl_counter(t->stats, top, NULL, "rays", &t->stat_rays);
    rc |= ks_stat_decl_real(t->stats, top, NULL, "mrps", &t->stat_mrps);
    rc |= ks_stat_decl_counter(t->stats, top, NULL, "dram_bytes", &t->stat_dram_bytes);
    rc |= ks_stat_decl_real(t->stats, top, NULL, "dram_bandwidth_gbs", &t->stat_dram_gbs);
    rc |= ks_stat_decl_real(t->stats, top, NULL, "rays_in_flight_mean", &t->stat_in_flight);
    for (int k = 0; k < 6; k++)
        rc |= ks_stat_decl_counter(t->stats, top, NULL, traffic_stat_names[k], &t->stat_traffic[k]);
    rc |= ks_stat_decl_real(t->stats, top, NULL, "dram_pj_per_byte", &t->stat_dram_pj_per_byte);
    rc |= sched_register(t->sched, "sched", t->stats, t->vcd);
    for (uint32_t i = 0; i < ntrv; i++) {
        rc |= trv_register(t->trv[i], t->names[i], t->stats, t->vcd);
        rc |= register_util(t, (int)i, &trv_module_desc, t->names[i], &t->trv[i]->busy_cycles);
    }
    rc |= ist_register(t->ist, "ist", t->stats, t->vcd);
    rc |= register_util(t, (int)ntrv, &ist_module_desc, "ist", &t->ist->busy_cycles);
    if (rc) {
        snprintf(err, errlen, "statistics: %s", ks_stats_error(t->stats));
        goto fail;
    }
    /* energy and area: a part without a figure fails here, at start-up */
    if (register_fifo_stats(t)) {
        snprintf(err, errlen, "FIFO statistics: %s", ks_stats_error(t->stats));
        goto fail;
    }
    if (rtcfg_bool(cfg, "energy.enabled") &&
        (!(t->energy = build_energy_model(t, cfg, err, errlen)) || energy_register_stats(t->energy, t->stats, err, errlen)))
        goto fail;
    if (opts->series) {
        if (!(t->series_busy = calloc(ntrv, sizeof *t->series_busy))) {
            snprintf(err, errlen, "out of memory for the series");
            goto fail;
        }
        t->series = opts->series;
        accel_series_start(t->series, ntrv, t->p.clock_mhz, t->energy);
    }
    if (t->vcd && ks_vcd_var_count(t->vcd) == 0) {
        /* a VCD without variables is of no use, and looked like a valid one */
        snprintf(err, errlen, "--vcd-filter %s: matches none of the traced variables (globs on full dotted names, "
                 "e.g. 'trv0.*,ist.*'; docs/accel.md)", opts->vcd_filter ? opts->vcd_filter : "");
        goto fail;
    }
    return t;
fail:
    accel_top_destroy(t);
    return NULL;
}

void accel_top_destroy(accel_top *t)
{
    if (!t)
        return;
    if (t->vcd)
        ks_vcd_discard(t->vcd);   /* still open: the run never finished (accel_top_run closes it) */
    energy_model_destroy(t->energy);
    if (t->trv)
        for (uint32_t i = 0; i < t->p.trv_count; i++)
            trv_destroy(t->trv[i]);
    if (t->mem)
        memsys_destroy(t->mem);
    sched_destroy(t->sched);
    ist_destroy(t->ist);
    if (t->sim)
        ks_sim_destroy(t->sim);
    if (t->stats)
        ks_stats_destroy(t->stats);
    free(t->rays);
    free(t->trv);
    for (int r = 0; r < ACCEL_FIFO_COUNT; r++) {
        free(t->fifo[r]);
        free(t->ring[r]);
    }
    free(t->names);
    free(t->series_busy);
    free(t);
}

/* Ends a row of the series at `cycle` (model/series.h): the run's
 * cumulative counts there, read without changing any state a result
 * depends on. */
static void series_sample(accel_top *t, uint64_t cycle)
{
    accel_series_point p = {0};
    const sched_unit *s = t->sched;
    p.cycle = cycle;
    p.admitted = s->admitted;
    p.completed = s->completed;
    p.in_flight = s->in_flight;
    p.in_flight_area = s->in_flight_area + (cycle > s->last_area_cycle ? s->in_flight * (cycle - s->last_area_cycle) : 0);
    for (uint32_t i = 0; i < t->p.trv_count; i++) {
        t->series_busy[i] = t->trv[i]->busy_cycles;
        const cache_stats *cs = cache_core_stats_live(memsys_node_l1(t->mem, (int)i));
        p.cache_acc[0] += cs->accesses;
        p.cache_hit[0] += cs->hits;
    }
    p.trv_busy = t->series_busy;
    p.ist_busy = t->ist->busy_cycles;
    const cache_core *c[2] = {memsys_node_l2(t->mem), memsys_prim(t->mem)};
    for (int k = 0; k < 2; k++) {
        const cache_stats *cs = cache_core_stats_live(c[k]);
        p.cache_acc[k + 1] = cs->accesses;
        p.cache_hit[k + 1] = cs->hits;
    }
    p.dram_bytes = memsys_memory_bytes(t->mem);
    dram_port *port = memsys_dram_port(t->mem);
    if (port) {
        dram_port_sync(port);
        const dram_ctrl *dc = dram_port_ctrl(port);
        p.dram = true;
        p.dram_cycles = (uint64_t)dram_clock(dc);
        for (int ch = 0; ch < memsys_dram_spec(t->mem)->channels; ch++) {
            dram_chan_stats cs;
            dram_chan_stats_get(dc, ch, &cs);
            p.row_hits += cs.row_hits;
            p.row_accesses += cs.row_hits + cs.row_misses + cs.row_conflicts;
            p.queue_sum += cs.queue_occupancy_sum;
        }
    }
    energy_activity act;
    if (t->energy) {
        accel_figures f;
        accel_top_figures(t, &f);
        gather_activity(t, &f, (double)cycle / (t->p.clock_mhz * 1e6), (double)p.dram_bytes, &act);
    }
    accel_series_sample(t->series, &p, t->energy ? &act : NULL);
}

/* ks_sim_run to the end of cycle `end`; with a series, in steps that end
 * at its rows' boundaries, each sampled (a frame that has every ray done
 * leaves its last row to finish_stats). Stopping and going on is the same
 * simulation as one call (kernel/sim.h). */
static ks_run_status run_to(accel_top *t, uint64_t end)
{
    ks_time period = ks_clock_period(t->clk);
    if (t->series) {
        for (uint64_t next; (next = accel_series_next(t->series)) < end;) {
            ks_run_status st = ks_sim_run(t->sim, (ks_time)next * period);
            if (st != KS_RUN_TIME_LIMIT)
                return st;
            if (sched_finished(t->sched) || ks_interrupted())
                break;
            series_sample(t, next);
        }
    }
    return ks_sim_run(t->sim, (ks_time)end * period);
}

/* stop_cycle: where a failed run stopped (0 when it completed); its
 * statistics cover the cycles simulated until then. */
static void finish_stats(accel_top *t, uint64_t stop_cycle)
{
    t->rays_done = t->sched->completed;
    t->cycles = t->rays_done ? t->sched->last_complete_cycle + 1 : 0;
    if (stop_cycle > t->cycles)
        t->cycles = stop_cycle;
    t->seconds = (double)t->cycles / (t->p.clock_mhz * 1e6);
    t->mrps = t->seconds > 0 ? (double)t->rays_done / t->seconds / 1e6 : 0.0;
    t->stat_cycles = t->cycles;
    t->stat_rays = t->rays_done;
    t->stat_mrps = t->mrps;
    /* DRAM statistics (cycles, background energy) up to the frame's end, not
     * to where the simulation stopped idling */
    if (t->mem && memsys_dram_port(t->mem))
        dram_port_set_stats_end(memsys_dram_port(t->mem), (ks_time)t->cycles * ks_clock_period(t->clk));
    t->stat_dram_bytes = t->mem ? memsys_memory_bytes(t->mem) : 0;
    t->stat_dram_gbs = t->seconds > 0 ? (double)t->stat_dram_bytes / t->seconds / 1e9 : 0.0;
    t->stat_in_flight = sched_mean_in_flight(t->sched, t->cycles);
    traffic_stats(t);
    if (t->series)
        series_sample(t, t->cycles);   /* the last row ends with the frame */
    if (t->energy)
        compute_energy(t);
    accel_figures f;
    accel_top_figures(t, &f);   /* DRAM energy 0 without an energy model */
    t->stat_dram_pj_per_byte = t->stat_dram_bytes ? f.unit_mj[EU_DRAM] * 1e9 / (double)t->stat_dram_bytes : 0.0;
}

/* Appends one line per busy unit and its cache to err (watchdog report). */
static void describe_units(accel_top *t, uint64_t now, char *err, size_t errlen, int n)
{
    char line[512];
    for (uint32_t i = 0; i < t->p.trv_count && n >= 0 && (size_t)n < errlen; i++) {
        if (!t->trv[i]->rays_in_unit)
            continue;
        cache_core_describe(memsys_node_l1(t->mem, (int)i), (int64_t)now, line, sizeof line);
        n += snprintf(err + n, errlen - (size_t)n, "\n  trv%u: %llu rays held; node L1: %s", i,
                      (unsigned long long)t->trv[i]->rays_in_unit, line);
        for (uint32_t k = 0; k < t->p.trv.core.slots && (size_t)n < errlen; k++) {
            const accel_ray *r = &t->rays[i * t->p.trv.core.slots + k];
            bool held = false;
            for (uint32_t j = 0; j < t->sched->nfree[i]; j++)
                held |= t->sched->free_slots[(size_t)i * t->sched->slots + j] == k;
            if (held)
                continue;   /* a free slot */
            n += snprintf(err + n, errlen - (size_t)n, "\n    ray %u (pixel %u bounce %u): phase %d target %u/%u, %u loops",
                          r->uid, r->pixel, r->bounce, r->phase, r->target_ref, r->target_meta, r->loops);
        }
    }
    if (t->ist->rays_in_unit && n >= 0 && (size_t)n < errlen) {
        cache_core_describe(memsys_prim(t->mem), (int64_t)now, line, sizeof line);
        n += snprintf(err + n, errlen - (size_t)n, "\n  ist: %llu rays held; primitive cache: %s",
                      (unsigned long long)t->ist->rays_in_unit, line);
    }
    if (n >= 0 && (size_t)n < errlen) {
        cache_core_describe(memsys_node_l2(t->mem), (int64_t)now, line, sizeof line);
        snprintf(err + n, errlen - (size_t)n, "\n  node L2: %s", line);
    }
}

/* Work that brings the frame closer to its end: committed node visits and
 * triangle tests (a pass or test invalidated by a miss does not count) and
 * completed rays. A run where it stops growing is stuck (livelock). */
static uint64_t committed_work(const accel_top *t)
{
    uint64_t w = t->sched->completed + t->ist->core.st.tests;
    for (uint32_t i = 0; i < t->p.trv_count; i++)
        w += t->trv[i]->core.st.visits;
    return w;
}

/* Runs slices of the simulation until the frame ends or fails (rc 1, err and
 * t->failure set) or, with stop_primaries > 0, until the scheduler has taken
 * that many primary rays (*stopped; checked every MARK_SLICE_CYCLES, so the
 * caller reads where it actually stopped). *now_out: the cycle reached. */
static int run_slices(accel_top *t, accel_progress_fn progress, void *user, uint64_t stop_primaries,
                      bool *stopped, uint64_t *now_out, char *err, size_t errlen)
{
    ks_time period = ks_clock_period(t->clk);
    uint64_t now_cycle = (uint64_t)(ks_sim_now(t->sim) / period), slice_end = now_cycle;
    uint64_t last_work = 0, last_work_cycle = now_cycle;
    int rc = 0;
    *stopped = false;
    for (;;) {
        slice_end += stop_primaries ? MARK_SLICE_CYCLES : SLICE_CYCLES;
        ks_run_status st = run_to(t, slice_end);
        now_cycle = (uint64_t)(ks_sim_now(t->sim) / period);
        if (progress)
            progress(user, now_cycle, t->sched->completed, t->sched->admitted);
        if (stop_primaries && t->sched->next_primary >= stop_primaries && !sched_finished(t->sched) &&
            st != KS_RUN_DEADLOCK && !ks_interrupted()) {
            *stopped = true;
            break;
        }
        if (ks_interrupted()) {
            /* Ctrl-C/SIGTERM (kernel/interrupt.h): stop between two slices,
             * so the VCD ends at a complete time step */
            snprintf(err, errlen, "interrupted by %s at cycle %llu", ks_interrupt_name(ks_interrupted()),
                     (unsigned long long)now_cycle);
            snprintf(t->failure, sizeof t->failure, "interrupted at cycle %llu", (unsigned long long)now_cycle);
            rc = 1;
            break;
        }
        if (st == KS_RUN_DEADLOCK) {
            snprintf(err, errlen, "deadlock at cycle %llu:\n%s", (unsigned long long)now_cycle,
                     ks_sim_deadlock_report(t->sim));
            snprintf(t->failure, sizeof t->failure, "deadlock at cycle %llu", (unsigned long long)now_cycle);
            rc = 1;
            break;
        }
        if (sched_finished(t->sched) || st == KS_RUN_FINISHED) {
            if (!sched_finished(t->sched)) {
                snprintf(err, errlen, "simulation ran dry at cycle %llu with %llu rays in flight:\n%s",
                         (unsigned long long)now_cycle, (unsigned long long)t->sched->in_flight,
                         ks_sim_deadlock_report(t->sim));
                snprintf(t->failure, sizeof t->failure, "ran dry at cycle %llu", (unsigned long long)now_cycle);
                rc = 1;
            }
            break;
        }
        uint64_t work = committed_work(t);
        if (work != last_work) {
            last_work = work;
            last_work_cycle = now_cycle;
        }
        if (t->sched->last_complete_cycle > last_work_cycle)
            last_work_cycle = t->sched->last_complete_cycle;
        /* Half-way to the watchdog, engage the TRVs' forward-progress guard
         * (trv_core.h): rays that thrash a node L1 (their fills evicting
         * each other's lines before they look again) then take turns. A
         * run that never starves never engages it, so its figures are the
         * plain model's; one that does says so in its summary. */
        if (t->livelock_window && !t->guard_cycle && t->sched->in_flight &&
            now_cycle > last_work_cycle + t->livelock_window / 2) {
            t->guard_cycle = now_cycle;
            for (uint32_t i = 0; i < t->p.trv_count; i++)
                t->trv[i]->core.guard = true;
        }
        if (t->livelock_window && t->sched->in_flight && now_cycle > last_work_cycle + t->livelock_window) {
            int n = snprintf(err, errlen,
                             "no node visit, triangle test or completed ray for %llu cycles (sched.watchdog_cycles = "
                             "%llu + the machine's longest wait %llu) at cycle %llu with %llu rays in flight "
                             "(livelock: rays keep looping):",
                             (unsigned long long)(now_cycle - last_work_cycle),
                             (unsigned long long)t->p.sched.watchdog_cycles, (unsigned long long)t->longest_wait,
                             (unsigned long long)now_cycle, (unsigned long long)t->sched->in_flight);
            describe_units(t, now_cycle, err, errlen, n);
            snprintf(t->failure, sizeof t->failure, "livelock (no ray completed) at cycle %llu",
                     (unsigned long long)now_cycle);
            rc = 1;
            break;
        }
    }
    *now_out = now_cycle;
    return rc;
}

int accel_top_run(accel_top *t, accel_progress_fn progress, void *user, char *err, size_t errlen)
{
    bool stopped;
    uint64_t now_cycle;
    int rc = run_slices(t, progress, user, 0, &stopped, &now_cycle, err, errlen);
    finish_stats(t, rc ? now_cycle : 0);
    if (rc == 0 && t->sched->any_failed) {
        accel_figures f;
        accel_top_figures(t, &f);
        snprintf(err, errlen,
                 "%llu rays overflowed their %u-entry traversal stack: the stack is too small for this scene "
                 "(raise trv.stack_depth, allowed 1..4096)",
                 (unsigned long long)f.failed, t->p.trv.core.stack_depth);
        snprintf(t->failure, sizeof t->failure, "%llu rays overflowed their stack", (unsigned long long)f.failed);
        rc = 1;
    }
    t->stat_failed = rc != 0 && !ks_interrupted();   /* interrupted: partial, not failed */
    if (t->vcd) {
        if (ks_vcd_close(t->vcd) && rc == 0) {
            snprintf(err, errlen, "VCD: %s", ks_sim_error(t->sim));
            rc = 1;
        }
        t->vcd = NULL;
    }
    return rc;
}

int accel_top_run_until(accel_top *t, uint64_t primaries, accel_point *p, char *err, size_t errlen)
{
    bool stopped;
    uint64_t now_cycle;
    memset(p, 0, sizeof *p);
    int rc = run_slices(t, NULL, NULL, primaries ? primaries : 1, &stopped, &now_cycle, err, errlen);
    if (rc)
        return 1;
    p->finished = !stopped;
    p->cycle = now_cycle;
    if (t->series)
        series_sample(t, now_cycle);   /* a row ends at every mark */
    p->primaries = t->sched->next_primary;
    p->completed = t->sched->completed;
    p->latency_sum = t->sched->latency_sum;
    p->dram_bytes = t->mem ? (double)memsys_memory_bytes(t->mem) : 0.0;
    const cache_core *backed[2] = {memsys_node_l2(t->mem), memsys_prim(t->mem)};
    for (int i = 0; i < 2; i++) {
        const cache_stats *cs = cache_core_stats_live(backed[i]);
        p->backed_fills += cs->fills;
        p->backed_cold_fills += cs->fills - cs->evictions;
    }
    if (t->energy) {
        accel_figures f;
        accel_top_figures(t, &f);
        gather_activity(t, &f, (double)now_cycle / (t->p.clock_mhz * 1e6), p->dram_bytes, &p->act);
    }
    return 0;
}

int accel_top_warm_caches(accel_top *t, const cache_core *const *l1, int nl1, const cache_core *l2,
                          const cache_core *prim)
{
    if (!t->mem || nl1 != (int)t->p.trv_count)
        return -1;
    for (int i = 0; i < nl1; i++)
        if (l1[i] && cache_core_copy_contents(memsys_node_l1(t->mem, i), l1[i]))
            return -1;
    if (l2 && cache_core_copy_contents(memsys_node_l2(t->mem), l2))
        return -1;
    if (prim && cache_core_copy_contents(memsys_prim(t->mem), prim))
        return -1;
    return 0;
}

const energy_result *accel_top_interval_energy(accel_top *t, const accel_point *a, const accel_point *b)
{
    if (!t->energy)
        return NULL;
    energy_activity d;
    energy_activity_between(&a->act, &b->act, &d);
    energy_compute(t->energy, &d, 0);
    return &t->energy->r;
}

uint64_t accel_top_cycles(const accel_top *t) { return t->cycles; }
uint64_t accel_top_rays(const accel_top *t) { return t->rays_done; }
double accel_top_mrps(const accel_top *t) { return t->mrps; }
ks_stats *accel_top_stats(accel_top *t) { return t->stats; }
const accel_params *accel_top_params(const accel_top *t) { return &t->p; }
uint64_t accel_top_guard_cycle(const accel_top *t) { return t->guard_cycle; }
void accel_top_detach_series(accel_top *t) { t->series = NULL; }

/* 100 x part / whole, 0 when whole is 0. */
static double percent(double part, double whole) { return whole ? 100.0 * part / whole : 0.0; }

void accel_top_print_summary(accel_top *t, FILE *out)
{
    fprintf(out, "machine     %d-wide, %u TRV x %u slots, 1 IST, %.0f MHz\n", t->p.width, t->p.trv_count,
            t->p.trv.core.slots, t->p.clock_mhz);
    if (t->failure[0])
        fprintf(out, "status      FAILED: %s; the figures below cover the cycles simulated until then\n",
                t->failure);
    if (t->guard_cycle)
        fprintf(out, "guard       livelock guard engaged at cycle %llu: rays thrashed a node L1 and took turns from "
                     "then on (docs/accel.md)\n",
                (unsigned long long)t->guard_cycle);
    /* the figures the registry has too (accel_figures names each one's
     * statistic), so the summary and the JSON agree */
    accel_figures f;
    accel_top_figures(t, &f);
    double cycles = (double)f.cycles;
    fprintf(out, "cycles      %.0f\n", cycles);
    fprintf(out, "rays        %.0f (%.0f primary, %.0f bounce)\n", (double)f.rays, (double)f.primaries,
            (double)f.bounces);
    if (f.occlusion)
        fprintf(out, "occlusion   %.0f rays, %.0f occluded\n", (double)f.occlusion_rays, (double)f.occluded);
    fprintf(out, "MRPS        %.2f at %.0f MHz\n", f.mrps, t->p.clock_mhz);
    fprintf(out, "in flight   %.1f rays mean, %.0f max; latency %.0f cycles mean\n", f.in_flight_mean,
            (double)f.max_in_flight, f.latency_mean);
    fprintf(out, "utilization");
    for (uint32_t i = 0; i < f.trv_count; i++)
        fprintf(out, " trv%u %.1f%%", i, percent((double)f.trv_busy_cycles[i], cycles));
    fprintf(out, " ist %.1f%%\n", percent((double)f.ist_busy_cycles, cycles));
    const accel_cache_figures *c = &f.node_l1;
    fprintf(out, "caches      node L1 %.2f%% hits (%.0f accesses)", percent((double)c->hits, (double)c->accesses),
            (double)c->accesses);
    c = &f.node_l2;
    fprintf(out, ", node L2 %.2f%% (%.0f)", percent((double)c->hits, (double)c->accesses), (double)c->accesses);
    c = &f.prim;
    fprintf(out, ", prim %.2f%% (%.0f)\n", percent((double)c->hits, (double)c->accesses), (double)c->accesses);
    fprintf(out, "DRAM        %.2f MB, %.2f GB/s (%s memory)\n", (double)f.dram_bytes / 1e6, f.dram_gbs,
            memsys_memory_model(t->mem) == MEMSYS_LPDDR3 ? "LPDDR3" : "fixed-latency");
    fprintf(out, "traffic     nodes %.2f MB, triangles %.2f MB; footprint %.2f MB, refetched %.2f MB (%.0f first-touch "
                 "fills, %.0f refetches)",
            (double)f.dram_node_bytes / 1e6, (double)f.dram_triangle_bytes / 1e6, (double)f.dram_footprint_bytes / 1e6,
            (double)f.dram_refetch_bytes / 1e6, (double)f.dram_compulsory_misses, (double)f.dram_refetch_misses);
    if (f.lpddr3)
        fprintf(out, "; row hits %.1f%%", 100.0 * f.row_hit_rate);
    if (t->energy)
        fprintf(out, "; %.0f pJ/B", f.dram_pj_per_byte);
    fprintf(out, "\n");
    if (t->energy)
        energy_print_summary(t->energy, out);
}

/* First power of two strictly above the ring's maximum occupancy. */
static uint32_t ring_suggest(const pipe_ring *r)
{
    uint32_t s = 1;
    while (s <= r->max_count)
        s *= 2;
    return s;
}

/* The first power of two above the largest occupancy seen by instance i
 * of ray-side FIFO r (a kernel FIFO or a unit's ring). */
static uint32_t ray_fifo_suggestion(const accel_top *t, int r, uint32_t i)
{
    return t->fifo[r][i] ? ks_fifo_suggested_capacity(t->fifo[r][i]) : ring_suggest(t->ring[r][i]);
}

int accel_top_autosize(const accel_top *t, rtcfg *cfg, char *err, size_t errlen)
{
    /* ray side: the largest suggestion among the FIFOs of each key, but
     * never below the deadlock-free minimum (accel_config.h): what one frame
     * needed says nothing about a larger one (a machine sized on 8x4 once
     * deadlocked at 64x36) */
    for (int r = 0; r < ACCEL_FIFO_COUNT; r++) {
        uint32_t want = accel_fifo_min(cfg, (accel_fifo_id)r);
        for (uint32_t i = 0; i < ray_fifo_instances(t, &accel_ray_fifos[r]); i++)
            if (ray_fifo_suggestion(t, r, i) > want)
                want = ray_fifo_suggestion(t, r, i);
        if (rtcfg_set_int(cfg, accel_ray_fifos[r].key, want, err, errlen))
            return -1;
    }
    /* leaf + return: split the safe sum evenly where the sizes fall short */
    const char *leaf_key = accel_ray_fifos[ACCEL_FIFO_LEAF].key, *ret_key = accel_ray_fifos[ACCEL_FIFO_RETURN].key;
    int64_t leaf = rtcfg_int(cfg, leaf_key), ret = rtcfg_int(cfg, ret_key);
    int64_t need = (int64_t)accel_leaf_return_min(cfg);
    if (leaf + ret < need) {
        if (leaf < (need + 1) / 2)
            leaf = (need + 1) / 2;
        if (ret < need - leaf)
            ret = need - leaf;
        if (rtcfg_set_int(cfg, leaf_key, leaf, err, errlen) || rtcfg_set_int(cfg, ret_key, ret, err, errlen))
            return -1;
    }
    /* memory side: the largest suggestion among the FIFOs of each key */
    int n = memsys_fifo_count(t->mem);
    for (int i = 0; i < n; i++) {
        const char *key = NULL;
        ks_fifo *f = memsys_fifo_at(t->mem, i, &key, NULL);
        uint32_t want = ks_fifo_suggested_capacity(f);
        for (int j = 0; j < n; j++) {
            const char *kj = NULL;
            ks_fifo *g = memsys_fifo_at(t->mem, j, &kj, NULL);
            if (!strcmp(kj, key) && ks_fifo_suggested_capacity(g) > want)
                want = ks_fifo_suggested_capacity(g);
        }
        if (rtcfg_set_int(cfg, key, want, err, errlen))
            return -1;
    }
    return 0;
}

static const ks_module_desc *const all_descs[] = {&trv_module_desc, &ist_module_desc, &sched_module_desc,
                                                  &ks_fifo_module_desc, &accel_top_module_desc, &energy_module_desc};

const ks_module_desc *accel_module_desc(const char *name)
{
    for (size_t i = 0; i < sizeof all_descs / sizeof all_descs[0]; i++)
        if (!strcmp(all_descs[i]->name, name))
            return all_descs[i];
    return memsys_module_desc(name);   /* caches, arbiters, memories */
}

void accel_module_list(FILE *out)
{
    for (size_t i = 0; i < sizeof all_descs / sizeof all_descs[0]; i++)
        fprintf(out, "%s, ", all_descs[i]->name);
    memsys_module_list(out);
}
