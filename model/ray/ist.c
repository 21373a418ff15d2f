/* ist.c — IST unit timing (see ist.h); the test itself is ist_core.c. */
#include "model/ray/ist.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The unit's parameters: the keys of its configuration section, written
 * only here (type, default, range, unit, source); --help-module prints
 * them after the table below, which names the section. */
static const rtcfg_param ist_params_tab[] = {
    {"latency", RTCFG_INT, "16", 1, 256, 0, NULL, "cycles",
     "Wald test pipeline depth after the primitive cache access (ours)"},
    {"flops_per_test", RTCFG_INT, "39", 1, 256, 0, NULL, "FLOP",
     "FLOPs per Wald test, division = 11 (paper sec. 3.2): 28 + 11"},
};
const rtcfg_schema ist_schema = {"ist", "intersection unit", ist_params_tab, 2, NULL};

static const ks_desc_item ist_items[] = {
    {KS_DESC_PORT, "in[i]", "in fifo<trv_msg>", "", "", "leaf work from TRV i (round-robin)"},
    {KS_DESC_PORT, "out[i]", "out fifo<trv_msg>", "", "", "rays back to TRV i for the stack pop"},
    {KS_DESC_PORT, "prim_cache", "cache probe", "", "", "primitive cache (48 B unaligned reads)"},
    {KS_DESC_PORT, "pipe", "internal fifo<trv_msg>", "", "", "test pipeline (latency ist.latency)"},
    {KS_DESC_PORT, "loop", "internal fifo<trv_msg>", "", "", "rays whose triangle fetch missed"},
    {KS_DESC_STAT, "busy_cycles", "cycles", "", "", "cycles a triangle test issued"},
    {KS_DESC_STAT, "tests", "tests", "", "", "triangle tests (committed)"},
    {KS_DESC_STAT, "hits", "tests", "", "", "tests that found an intersection in range"},
    {KS_DESC_STAT, "closer_hits", "tests", "", "", "hits that became the ray's closest"},
    {KS_DESC_STAT, "leaves", "leaves", "", "", "leaves finished"},
    {KS_DESC_STAT, "loops_miss", "tests", "", "", "tests invalidated by a primitive cache miss"},
    {KS_DESC_STAT, "loops_blocked", "tests", "", "", "tests invalidated because the primitive cache was blocked"},
    {KS_DESC_STAT, "exit_stall_cycles", "cycles", "", "", "cycles the exit stage waited for a full output FIFO"},
    {KS_DESC_STAT, "issue_stall_cycles", "cycles", "", "", "cycles issue waited for a full pipe"},
    {KS_DESC_STAT, "bank_stall_cycles", "cycles", "", "", "cycles issue waited for a primitive read spanning one bank twice"},
    {KS_DESC_STAT, "flops", "FLOP", "", "", "FLOPs of issued tests (division = 11, paper sec. 3.2)"},
    {KS_DESC_STAT, "utilization", "fraction", "", "", "busy cycles / frame cycles"},
    {KS_DESC_PART, "fpu", "FPU", "", "",
     "one Wald test per cycle: ist.flops_per_test FLOP units; energy per FLOP of committed and invalidated tests"},
    {KS_DESC_END, 0, 0, 0, 0, 0}};

const ks_module_desc ist_module_desc = {"ist", "ray-triangle intersection unit (Wald 2004), fully pipelined", ist_items, "ist"};

static int ist_step(void *user, uint64_t cycle);

static int ist_busy(void *user)
{
    ist_unit *u = user;
    return u->rays_in_unit > 0;
}

static void ist_describe(void *user, char *buf, unsigned cap)
{
    ist_unit *u = user;
    int n = snprintf(buf, cap, "%u rays held; issuing ray %lld; pipe %u/%u, loop %u/%u; out", (unsigned)u->rays_in_unit,
                     (long long)u->cur, u->pipe.count, u->pipe.cap,
                     u->loop.count, u->loop.cap);
    for (uint32_t i = 0; i < u->ntrv && n > 0 && (unsigned)n < cap; i++)
        n += snprintf(buf + n, cap - (unsigned)n, " %u/%u", ks_fifo_occupancy(u->out[i]), ks_fifo_capacity(u->out[i]));
}

static bool ist_setup(ist_unit *u, const char *name, const ist_params *p, const accel_image *img, accel_ray *rays,
              ks_sim *sim, ks_clock *clk, uint32_t loop_capacity, uint32_t pipe_capacity, char *err, unsigned errlen)
{
    memset(u, 0, sizeof *u);
    /* p->latency is the whole test pipeline, ist.latency + prim.hit_latency
     * (accel_top.c); the keys' ranges are checked where they are declared
     * (accel_config.c, memsys_config.c), so only an impossible pipeline is
     * refused here */
    if (p->latency < 1) {
        snprintf(err, errlen, "%s: test pipeline latency 0 (ist.latency + prim.hit_latency must be >= 1)", name);
        return false;
    }
    u->p = *p;
    u->core.img = img;
    u->rays = rays;
    u->clk = clk;
    u->cur = -1;
    if (!pipe_ring_init(&u->pipe, pipe_capacity ? pipe_capacity : p->latency + 1, p->latency)) {
        snprintf(err, errlen, "%s: out of memory", name);
        return false;
    }
    if (!pipe_ring_init(&u->loop, loop_capacity ? loop_capacity : 32, 1)) {
        snprintf(err, errlen, "%s: out of memory", name);
        pipe_ring_free(&u->pipe);
        return false;
    }
    (void)sim;
    u->proc = ks_clocked_create(clk, name, ist_step, u);
    ks_clocked_set_describe(u->proc, ist_busy, ist_describe);
    return true;
}

void ist_connect(ist_unit *u, uint32_t ntrv, ks_fifo **in, ks_fifo **out)
{
    u->ntrv = ntrv;
    for (uint32_t i = 0; i < ntrv; i++) {
        u->in[i] = in[i];
        u->out[i] = out[i];
        ks_clocked_wake_on(u->proc, ks_fifo_ev_written(in[i]));
        ks_clocked_wake_on(u->proc, ks_fifo_ev_freed(out[i]));
    }
}

void ist_set_probe(ist_unit *u, accel_probe_fn probe, void *ctx)
{
    u->core.probe = probe;
    u->core.probe_ctx = ctx;
}

void ist_set_events(ist_unit *u, accel_event_fn fn, void *user)
{
    u->core.ev = fn;
    u->core.ev_user = user;
}

int ist_register(ist_unit *u, const char *name, ks_stats *st, ks_vcd *vcd)
{
    int rc = 0;
    if (st) {
        rc |= ks_stat_decl_counter(st, &ist_module_desc, name, "busy_cycles", &u->busy_cycles);
        rc |= ks_stat_decl_counter(st, &ist_module_desc, name, "tests", &u->core.st.tests);
        rc |= ks_stat_decl_counter(st, &ist_module_desc, name, "hits", &u->core.st.hits);
        rc |= ks_stat_decl_counter(st, &ist_module_desc, name, "closer_hits", &u->core.st.closer);
        rc |= ks_stat_decl_counter(st, &ist_module_desc, name, "leaves", &u->core.st.leaves);
        rc |= ks_stat_decl_counter(st, &ist_module_desc, name, "loops_miss", &u->core.st.loops_miss);
        rc |= ks_stat_decl_counter(st, &ist_module_desc, name, "loops_blocked", &u->core.st.loops_blocked);
        rc |= ks_stat_decl_counter(st, &ist_module_desc, name, "exit_stall_cycles", &u->exit_stall_cycles);
        rc |= ks_stat_decl_counter(st, &ist_module_desc, name, "issue_stall_cycles", &u->issue_stall_cycles);
        rc |= ks_stat_decl_counter(st, &ist_module_desc, name, "bank_stall_cycles", &u->bank_stall_cycles);
        rc |= ks_stat_decl_counter(st, &ist_module_desc, name, "flops", &u->flops);
    }
    if (vcd) {
        u->vcd = true;
        char nm[160];
        snprintf(nm, sizeof nm, "%s.issue_ray", name);
        u->v_issue_ray = ks_vcd_var_int(vcd, nm, 32, 0xFFFFFFFFu);
        snprintf(nm, sizeof nm, "%s.issue_tri", name);
        u->v_tri = ks_vcd_var_int(vcd, nm, 32, 0xFFFFFFFFu);
        snprintf(nm, sizeof nm, "%s.exit_ray", name);
        u->v_exit_ray = ks_vcd_var_int(vcd, nm, 32, 0xFFFFFFFFu);
        snprintf(nm, sizeof nm, "%s.pipe.occupancy", name);
        u->pipe.v_occ = ks_vcd_var_int(vcd, nm, 16, 0);
        snprintf(nm, sizeof nm, "%s.loop.occupancy", name);
        u->loop.v_occ = ks_vcd_var_int(vcd, nm, 16, 0);
        /* the issue stage is test1, the pipeline after it test2.. */
        const pipe_stage_part parts[] = {{"test", u->p.latency + 1}};
        pipe_trace_init(&u->stage_rays, vcd, name, parts, 1);
    }
    return rc;
}

static inline uint64_t head_cycle(const ks_fifo *f, ks_clock *clk)
{
    if (!f || !ks_fifo_occupancy(f))
        return UINT64_MAX;
    return ks_clock_cycle_at_or_after(clk, ks_fifo_head_ready_time(f));
}

/* pipe items: result 0 = back to the TRV, 1 = loop */
/* The step, with the VCD code compiled out when vcd is false. */
static inline __attribute__((always_inline)) int ist_step_body(ist_unit *u, uint64_t cycle, const bool vcd)
{
    int progress = 0;

    const pipe_item *head = pipe_ring_ready(&u->pipe, cycle);
    if (head) {
        const accel_ray *r = &u->rays[head->ray];
        ks_fifo *out = head->result ? NULL : u->out[r->trv];
        if (out ? ks_fifo_can_write(out) : !pipe_ring_full(&u->loop)) {
            pipe_item it = pipe_ring_pop_v(&u->pipe, vcd);
            trv_msg m = {it.ray, 0};
            if (out) {
                u->rays_in_unit--;
                KS_FIFO_WRITE(out, &m);
            } else {
                pipe_ring_push_v(&u->loop, it.ray, 0, cycle, vcd);
            }
            if (vcd && u->v_exit_ray)
                ks_vcd_set(u->v_exit_ray, m.ray);
            progress++;
        } else {
            u->exit_stall_cycles++;
        }
    } else if (vcd && u->v_exit_ray) {
        ks_vcd_set(u->v_exit_ray, 0xFFFFFFFFu);
    }

    if (u->cur < 0) {
        /* pick the next ray: looping rays first, then the TRVs round-robin */
        trv_msg m;
        if (pipe_ring_ready(&u->loop, cycle)) {
            u->cur = pipe_ring_pop_v(&u->loop, vcd).ray;
        } else {
            for (uint32_t k = 0; k < u->ntrv; k++) {
                uint32_t i = (u->rr + k) % u->ntrv;
                if (ks_fifo_can_read(u->in[i]) && KS_FIFO_READ(u->in[i], &m)) {
                    u->cur = m.ray;
                    u->rays_in_unit++;
                    u->rr = (i + 1) % u->ntrv;
                    break;
                }
            }
        }
        if (u->cur >= 0)
            progress++;
    }
    if (u->cur >= 0 && cycle < u->busy_until) {
        u->bank_stall_cycles++;
        progress++;
    } else if (u->cur >= 0) {
        accel_ray *r = &u->rays[u->cur];
        /* a test that ends the ray's stay (last triangle or miss) needs a pipe slot */
        if (!pipe_ring_full(&u->pipe)) {
            uint32_t tri = r->tri_next;
            ist_result res = ist_core_test(&u->core, r, cycle);
            u->busy_cycles++;
            u->flops += u->p.flops_per_test;
            if (vcd && u->v_issue_ray) {
                ks_vcd_set(u->v_issue_ray, (uint64_t)u->cur);
                ks_vcd_set(u->v_tri, tri);
                pipe_trace_issue(&u->stage_rays, cycle, (uint32_t)u->cur);
            }
            if (res != IST_LOOP_MISS && res != IST_LOOP_BLOCKED && u->core.port_cycles > 1)
                u->busy_until = cycle + u->core.port_cycles;   /* both lines in one bank */
            if (res != IST_MORE) {
                pipe_ring_push_v(&u->pipe, (uint32_t)u->cur, res == IST_LAST ? 0u : 1u, cycle, vcd);
                u->cur = -1;
            }
            progress++;
        } else {
            u->issue_stall_cycles++;
        }
    } else if (vcd && u->v_issue_ray) {
        ks_vcd_set(u->v_issue_ray, 0xFFFFFFFFu);
        ks_vcd_set(u->v_tri, 0xFFFFFFFFu);
    }
    if (vcd && pipe_trace_on(&u->stage_rays))
        pipe_trace_update(&u->stage_rays, cycle);
    if (!progress) {
        uint64_t next = pipe_ring_next_exit(&u->pipe), c;
        if ((c = pipe_ring_next_exit(&u->loop)) < next)
            next = c;
        for (uint32_t i = 0; i < u->ntrv; i++)
            if ((c = head_cycle(u->in[i], u->clk)) < next)
                next = c;
        if (vcd && pipe_trace_occupied(&u->stage_rays, cycle))
            next = cycle + 1;   /* VCD on: the stage variables change every cycle */
        if (next != UINT64_MAX && next > cycle)
            ks_clocked_sleep_until_cycle(u->proc, next);
    }
    return progress;
}

static int ist_step(void *user, uint64_t cycle)
{
    ist_unit *u = user;
    return u->vcd ? ist_step_body(u, cycle, true) : ist_step_body(u, cycle, false);
}

static void ist_teardown(ist_unit *u)
{
    pipe_ring_free(&u->pipe);
    pipe_ring_free(&u->loop);
    pipe_trace_free(&u->stage_rays);
}

ist_unit *ist_create(const char *name, const ist_params *p, const accel_image *img, accel_ray *rays, ks_sim *sim,
                     ks_clock *clk, uint32_t loop_capacity, uint32_t pipe_capacity, char *err, unsigned errlen)
{
    ist_unit *u = calloc(1, sizeof *u);
    if (!u) {
        snprintf(err, errlen, "ist: out of memory");
        return NULL;
    }
    if (!ist_setup(u, name, p, img, rays, sim, clk, loop_capacity, pipe_capacity, err, errlen)) {
        free(u);
        return NULL;
    }
    return u;
}

void ist_destroy(ist_unit *u)
{
    if (!u)
        return;
    ist_teardown(u);
    free(u);
}
