/* scheduler.c — ray slots, admission and bounce feeding (see scheduler.h). */
#include "model/ray/scheduler.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The unit's parameters: the keys of its configuration section, written
 * only here (type, default, range, unit, source); --help-module prints
 * them after the table below, which names the section. */
static const rtcfg_param sched_params_tab[] = {
    {"admit_per_cycle", RTCFG_INT, "1", 1, 64, 0, NULL, "rays/cycle", "rays the scheduler admits per cycle (ours)"},
    {"shade_latency", RTCFG_INT, "0", 0, 1000000, 0, NULL, "cycles",
     "completion to bounce-ray ready: shading outside the accelerator (ours)"},
    {"watchdog_cycles", RTCFG_INT, "2000000", 0, 1e12, 0, NULL, "cycles",
     "stop with a report when no work is done (no node visit, triangle test or completed ray) for this long "
     "plus the machine's longest wait (docs/accel.md); 0 = off"},
    /* The paper leaves the ray generator's pixel order open; tiles decide
     * primary rays' DRAM traffic (docs/paper.md "Pixel order"). The frame
     * (frame/frame.h) reads these two keys; the scheduler admits primary
     * rays in the order it is handed them. */
    {"pixel_order", RTCFG_ENUM, "morton", 0, 0, 0, "scanline|tiles|morton", "",
     "order of the frame's primary rays: scanline, square tiles of sched.tile pixels (tiles and their pixels "
     "in scanline order), or Morton (Z) order; bounces follow their path (ours: morton, the least DRAM traffic "
     "on Crytek Sponza, docs/paper.md)"},
    {"tile", RTCFG_INT, "32", 1, 65535, 0, NULL, "pixels",
     "side of a square tile with sched.pixel_order = tiles (ours: 32, docs/paper.md)"},
};
const rtcfg_schema sched_schema = {"sched", "ray scheduler", sched_params_tab, 5, NULL};

static const ks_desc_item sched_items[] = {
    {KS_DESC_PORT, "to_trv[i]", "out fifo<trv_msg>", "", "", "new rays to TRV i"},
    {KS_DESC_PORT, "from_trv[i]", "in fifo<trv_msg>", "", "", "finished rays from TRV i"},
    {KS_DESC_STAT, "admitted", "rays", "", "", "rays admitted"},
    {KS_DESC_STAT, "primaries", "rays", "", "", "primary rays admitted"},
    {KS_DESC_STAT, "bounces", "rays", "", "", "bounce rays admitted"},
    {KS_DESC_STAT, "completed", "rays", "", "", "rays completed"},
    {KS_DESC_STAT, "failed", "rays", "", "", "rays that overflowed their stack"},
    /* only in runs with occlusion rays */
    {KS_DESC_STAT, "occlusion_rays", "rays", "", "", "occlusion rays completed (any hit ends them; no sort)"},
    {KS_DESC_STAT, "occluded", "rays", "", "", "occlusion rays that hit something in (tmin, tmax)"},
    {KS_DESC_STAT, "max_in_flight", "rays", "", "", "most rays in flight at once"},
    {KS_DESC_STAT, "latency_max", "cycles", "", "", "longest ray latency, admission to completion"},
    {KS_DESC_STAT, "admit_stall_cycles", "cycles", "", "", "cycles a ready ray found no free slot or a full TRV FIFO"},
    {KS_DESC_STAT, "latency_mean", "cycles", "", "", "mean ray latency, admission to completion"},
    {KS_DESC_STAT, "rays_in_flight_mean", "rays", "", "", "time-averaged rays in flight"},
    {KS_DESC_STAT, "latency", "cycles", "", "", "ray latency histogram"},
    {KS_DESC_END, 0, 0, 0, 0, 0}};

const ks_module_desc sched_module_desc = {"sched", "ray scheduler: ray slots, primary rays, bounce feeding", sched_items, "sched"};

static int sched_step(void *user, uint64_t cycle);

static int sched_busy(void *user)
{
    sched_unit *s = user;
    return !sched_finished(s);
}

static void sched_describe(void *user, char *buf, unsigned cap)
{
    sched_unit *s = user;
    uint32_t free_total = 0;
    for (uint32_t i = 0; i < s->ntrv; i++)
        free_total += s->nfree[i];
    snprintf(buf, cap, "%llu rays in flight, %u free slots, %llu/%llu primaries admitted, %u bounces waiting",
             (unsigned long long)s->in_flight, free_total, (unsigned long long)s->next_primary,
             (unsigned long long)s->src.primary_count, s->pend_count);
}

static void sched_teardown(sched_unit *s);

static bool sched_setup(sched_unit *s, const char *name, const sched_params *p, const accel_source *src, accel_ray *rays,
                uint32_t ntrv, uint32_t slots, ks_clock *clk, char *err, unsigned errlen)
{
    memset(s, 0, sizeof *s);
    if (ntrv < 1 || ntrv > 64 || slots < 1 || p->admit_per_cycle < 1) {
        snprintf(err, errlen, "scheduler: %u TRVs (allowed 1..64), %u slots (>= 1), admit_per_cycle %u (>= 1)", ntrv,
                 slots, p->admit_per_cycle);
        return false;
    }
    s->p = *p;
    s->src = *src;
    s->rays = rays;
    s->ntrv = ntrv;
    s->slots = slots;
    s->clk = clk;
    size_t total = (size_t)ntrv * slots;
    s->ray_in = calloc(total, sizeof *s->ray_in);
    s->free_slots = calloc(total, sizeof *s->free_slots);
    s->nfree = calloc(ntrv, sizeof *s->nfree);
    s->pend = calloc(total, sizeof *s->pend);
    if (!s->ray_in || !s->free_slots || !s->nfree || !s->pend) {
        sched_teardown(s);
        snprintf(err, errlen, "scheduler: out of memory");
        return false;
    }
    for (uint32_t t = 0; t < ntrv; t++) {
        /* slot 0 on top */
        for (uint32_t k = 0; k < slots; k++)
            s->free_slots[(size_t)t * slots + k] = slots - 1 - k;
        s->nfree[t] = slots;
    }
    s->proc = ks_clocked_create(clk, name, sched_step, s);
    ks_clocked_set_describe(s->proc, sched_busy, sched_describe);
    return true;
}

void sched_connect(sched_unit *s, ks_fifo **to_trv, ks_fifo **from_trv)
{
    for (uint32_t i = 0; i < s->ntrv; i++) {
        s->to_trv[i] = to_trv[i];
        s->from_trv[i] = from_trv[i];
        ks_clocked_wake_on(s->proc, ks_fifo_ev_freed(to_trv[i]));
        ks_clocked_wake_on(s->proc, ks_fifo_ev_written(from_trv[i]));
    }
}

double sched_latency_mean(const sched_unit *s)
{
    return s->completed ? (double)s->latency_sum / (double)s->completed : 0.0;
}

static double latency_mean(const ks_stats *reg, void *user)
{
    (void)reg;
    return sched_latency_mean(user);
}

static double in_flight_mean(const ks_stats *reg, void *user)
{
    (void)reg;
    const sched_unit *s = user;
    return sched_mean_in_flight(s, s->last_area_cycle);
}

int sched_register(sched_unit *s, const char *name, ks_stats *st, ks_vcd *vcd)
{
    char nm[160];
    int rc = 0;
    if (st) {
        const ks_module_desc *d = &sched_module_desc;
        rc |= ks_stat_decl_counter(st, d, name, "admitted", &s->admitted);
        rc |= ks_stat_decl_counter(st, d, name, "primaries", &s->primaries);
        rc |= ks_stat_decl_counter(st, d, name, "bounces", &s->bounces);
        rc |= ks_stat_decl_counter(st, d, name, "completed", &s->completed);
        rc |= ks_stat_decl_counter(st, d, name, "failed", &s->failed);
        if (s->src.occlusion) {
            rc |= ks_stat_decl_counter(st, d, name, "occlusion_rays", &s->occlusion_rays);
            rc |= ks_stat_decl_counter(st, d, name, "occluded", &s->occluded);
        }
        rc |= ks_stat_decl_counter(st, d, name, "max_in_flight", &s->max_in_flight);
        rc |= ks_stat_decl_counter(st, d, name, "latency_max", &s->latency_max);
        rc |= ks_stat_decl_counter(st, d, name, "admit_stall_cycles", &s->admit_stall_cycles);
        rc |= ks_stat_decl_formula(st, d, name, "latency_mean", latency_mean, s);
        rc |= ks_stat_decl_formula(st, d, name, "rays_in_flight_mean", in_flight_mean, s);
        s->lat_hist = ks_stat_decl_histogram(st, d, name, "latency", 0, 20000, 40);
        rc |= s->lat_hist ? 0 : -1;
    }
    if (vcd) {
        snprintf(nm, sizeof nm, "%s.rays_in_flight", name);
        s->v_in_flight = ks_vcd_var_int(vcd, nm, 16, 0);
        snprintf(nm, sizeof nm, "%s.admit_ray", name);
        s->v_admit_ray = ks_vcd_var_int(vcd, nm, 32, 0xFFFFFFFFu);
        snprintf(nm, sizeof nm, "%s.done_ray", name);
        s->v_done_ray = ks_vcd_var_int(vcd, nm, 32, 0xFFFFFFFFu);
    }
    return rc;
}

bool sched_finished(const sched_unit *s)
{
    return s->next_primary >= s->src.primary_count && s->pend_count == 0 && s->in_flight == 0;
}

static void account_in_flight(sched_unit *s, uint64_t cycle)
{
    if (cycle > s->last_area_cycle) {
        s->in_flight_area += s->in_flight * (cycle - s->last_area_cycle);
        s->last_area_cycle = cycle;
    }
}

double sched_mean_in_flight(const sched_unit *s, uint64_t now)
{
    uint64_t area = s->in_flight_area + (now > s->last_area_cycle ? s->in_flight * (now - s->last_area_cycle) : 0);
    return now ? (double)area / (double)now : 0.0;
}

static void sched_teardown(sched_unit *s)
{
    free(s->ray_in);
    free(s->free_slots);
    free(s->nfree);
    free(s->pend);
    s->ray_in = NULL, s->free_slots = NULL, s->nfree = NULL, s->pend = NULL;
}

static void complete(sched_unit *s, uint32_t rec, uint64_t cycle)
{
    accel_ray *r = &s->rays[rec];
    bool failed = r->phase == RAY_FAILED;
    accel_hit hit = {r->closest, r->u, r->v, r->prim};
    uint64_t lat = cycle - r->admit_cycle;
    s->completed++;
    s->latency_sum += lat;
    if (lat > s->latency_max)
        s->latency_max = lat;
    if (s->lat_hist)
        ks_histogram_add(s->lat_hist, (double)lat);
    if (r->occlusion) {
        s->occlusion_rays++;
        s->occluded += r->prim != ACCEL_NO_HIT;
    }
    if (failed) {
        s->failed++;
        s->any_failed = true;
    }
    if (s->src.complete)
        s->src.complete(s->src.user, r->uid, &s->ray_in[rec], &hit, r->admit_cycle, cycle, r->visits, r->tri_tests,
                        failed);
    accel_ray_in next;
    if (!failed && s->src.bounce && s->src.bounce(s->src.user, &s->ray_in[rec], &hit, &next)) {
        sched_pending *pd = &s->pend[(s->pend_head + s->pend_count) % (s->ntrv * s->slots)];
        pd->ray = next;
        pd->ready = cycle + s->p.shade_latency;
        s->pend_count++;
    }
    uint32_t t = r->trv;
    s->free_slots[(size_t)t * s->slots + s->nfree[t]++] = r->slot;
    account_in_flight(s, cycle);
    s->in_flight--;
    s->last_complete_cycle = cycle;
    if (s->v_done_ray)
        ks_vcd_set(s->v_done_ray, r->uid);
}

static int sched_step(void *user, uint64_t cycle)
{
    sched_unit *s = user;
    int progress = 0;
    for (uint32_t i = 0; i < s->ntrv; i++) {
        trv_msg m;
        if (ks_fifo_can_read(s->from_trv[i]) && KS_FIFO_READ(s->from_trv[i], &m)) {
            complete(s, m.ray, cycle);
            progress++;
        }
    }
    for (uint32_t k = 0; k < s->p.admit_per_cycle; k++) {
        bool bounce = s->pend_count && s->pend[s->pend_head].ready <= cycle;
        /* a primary only when slots + waiting bounces stay within the ray
         * storage, so the bounce ring (one entry per slot) cannot overflow */
        if (!bounce && (s->next_primary >= s->src.primary_count ||
                        s->in_flight + s->pend_count >= (uint64_t)s->ntrv * s->slots))
            break;
        /* a TRV with a free slot and room in its input FIFO, round-robin */
        uint32_t t = s->ntrv;
        for (uint32_t j = 0; j < s->ntrv; j++) {
            uint32_t c = (s->rr + j) % s->ntrv;
            if (s->nfree[c] && ks_fifo_can_write(s->to_trv[c])) {
                t = c;
                break;
            }
        }
        if (t == s->ntrv) {
            s->admit_stall_cycles++;
            break;
        }
        s->rr = (t + 1) % s->ntrv;
        uint32_t slot = s->free_slots[(size_t)t * s->slots + --s->nfree[t]];
        uint32_t rec = t * s->slots + slot;
        if (bounce) {
            s->ray_in[rec] = s->pend[s->pend_head].ray;
            s->pend_head = (s->pend_head + 1) % (s->ntrv * s->slots);
            s->pend_count--;
            s->bounces++;
        } else {
            s->src.primary(s->src.user, s->next_primary++, &s->ray_in[rec]);
            s->primaries++;
        }
        accel_ray *r = &s->rays[rec];
        accel_ray_start(r, &s->ray_in[rec], (uint32_t)s->next_uid++);
        r->trv = (uint16_t)t;
        r->slot = slot;
        r->admit_cycle = cycle;
        trv_msg m = {rec, 0};
        KS_FIFO_WRITE(s->to_trv[t], &m);
        account_in_flight(s, cycle);
        s->in_flight++;
        if (s->in_flight > s->max_in_flight)
            s->max_in_flight = s->in_flight;
        s->admitted++;
        if (s->v_admit_ray)
            ks_vcd_set(s->v_admit_ray, r->uid);
        progress++;
    }
    if (s->v_in_flight)
        ks_vcd_set(s->v_in_flight, s->in_flight);
    if (!progress && s->pend_count && s->pend[s->pend_head].ready > cycle)
        ks_clocked_sleep_until_cycle(s->proc, s->pend[s->pend_head].ready);
    return progress;
}

sched_unit *sched_create(const char *name, const sched_params *p, const accel_source *src, accel_ray *rays,
                         uint32_t ntrv, uint32_t slots, ks_clock *clk, char *err, unsigned errlen)
{
    sched_unit *s = calloc(1, sizeof *s);
    if (!s) {
        snprintf(err, errlen, "sched: out of memory");
        return NULL;
    }
    if (!sched_setup(s, name, p, src, rays, ntrv, slots, clk, err, errlen)) {
        free(s);
        return NULL;
    }
    return s;
}

void sched_destroy(sched_unit *s)
{
    if (!s)
        return;
    sched_teardown(s);
    free(s);
}
