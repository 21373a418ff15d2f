/* trv.c — TRV unit timing (see trv.h); the pass logic is trv_core.c. */
#include "model/ray/trv.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The unit's parameters: the keys of its configuration section, written
 * only here (type, default, range, unit, source); --help-module prints
 * them after the table below, which names the section. */
static const rtcfg_param trv_params_tab[] = {
    {"count", RTCFG_INT, "4", 1, 64, 0, NULL, "units", "TRV units per IST (paper sec. 3: 4)"},
    {"slots", RTCFG_INT, "32", 1, 1024, 0, NULL, "rays", "ray slots = stacks per TRV (paper sec. 3: 32)"},
    {"stack_depth", RTCFG_INT, "64", 1, 4096, 0, NULL, "entries", "entries per ray stack (paper sec. 3: 64)"},
    {"stack_banks", RTCFG_INT, "0", 0, 64, 0, NULL, "banks",
     "stack memory banks; 0 = N for N > 2 (N-1 pushes plus the pop, paper sec. 3.1), 1 for BVH2"},
    {"distance_stack", RTCFG_ENUM, "auto", 0, 0, 0, "auto|on|off", "",
     "distance stack culling; auto = on for N > 2 only (paper sec. 3.1)"},
    {"stages_box", RTCFG_INT, "3", 1, 32, 0, NULL, "stages", "slab test stages: sub, mul, min/max compare (ours)"},
    {"stages_stack", RTCFG_INT, "1", 1, 8, 0, NULL, "stages", "stack access stages (ours)"},
    {"stages_next", RTCFG_INT, "1", 1, 8, 0, NULL, "stages", "next-state stages (ours)"},
    {"box_flops", RTCFG_INT, "12", 1, 64, 0, NULL, "FLOP", "FLOPs per slab test lane: 6 sub + 6 mul (bvh_layout.h)"},
};
const rtcfg_schema trv_schema = {"trv", "traversal units (sort stages = sorting network depth, sort_net.h)",
                                       trv_params_tab, 9, NULL};

static const ks_desc_item trv_items[] = {
    {KS_DESC_PORT, "in_new", "in fifo<trv_msg>", "", "", "new rays from the scheduler"},
    {KS_DESC_PORT, "in_ist", "in fifo<trv_msg>", "", "", "rays back from the IST after a leaf"},
    {KS_DESC_PORT, "out_ist", "out fifo<trv_msg>", "", "", "rays with a leaf to test"},
    {KS_DESC_PORT, "out_done", "out fifo<trv_msg>", "", "", "finished rays to the scheduler"},
    {KS_DESC_PORT, "node_l1", "cache probe", "", "", "node L1 (cache_core_access; miss -> looping for next chance)"},
    {KS_DESC_PORT, "pipe", "internal fifo<trv_msg>", "", "", "the pipeline stages after issue (latency depth-1)"},
    {KS_DESC_PORT, "loop", "internal fifo<trv_msg>", "", "", "rays going round again"},
    {KS_DESC_STAT, "busy_cycles", "cycles", "", "", "cycles a ray was issued into the pipeline"},
    {KS_DESC_STAT, "passes", "passes", "", "", "ray passes through the pipeline"},
    {KS_DESC_STAT, "visits", "nodes", "", "", "node visits (committed)"},
    {KS_DESC_STAT, "pop_passes", "passes", "", "", "passes that popped the stack"},
    {KS_DESC_STAT, "loops_miss", "passes", "", "", "passes invalidated by a node L1 miss (looping for next chance)"},
    {KS_DESC_STAT, "loops_blocked", "passes", "", "", "passes invalidated because the node L1 was blocked"},
    {KS_DESC_STAT, "box_tests", "tests", "", "", "slab tests of used child slots"},
    {KS_DESC_STAT, "box_lanes", "tests", "", "", "slab test lanes active (N per visit)"},
    {KS_DESC_STAT, "sort_passes", "passes", "", "", "passes through the sorting network"},
    {KS_DESC_STAT, "sort_swaps", "swaps", "", "", "compare-exchanges that swapped"},
    {KS_DESC_STAT, "stack_pushes", "entries", "", "", "stack entries written"},
    {KS_DESC_STAT, "stack_pops", "entries", "", "", "stack entries read (pops and culls)"},
    {KS_DESC_STAT, "stack_ops", "operations", "", "", "stack operations (one per pass that touches the stack)"},
    {KS_DESC_STAT, "stack_conflict_cycles", "cycles", "", "", "issue stalls from stack bank conflicts"},
    {KS_DESC_STAT, "stack_max_depth", "entries", "", "", "deepest stack of any ray slot"},
    {KS_DESC_STAT, "stack_bank#_writes", "entries", "", "", "stack entries written to this bank"},
    {KS_DESC_STAT, "stack_bank#_reads", "entries", "", "", "stack entries read from this bank (pops and culls)"},
    {KS_DESC_STAT, "culls", "entries", "", "", "stack entries discarded by the distance stack"},
    {KS_DESC_STAT, "to_ist", "rays", "", "", "rays sent to the IST with a leaf"},
    {KS_DESC_STAT, "done", "rays", "", "", "rays finished"},
    {KS_DESC_STAT, "stack_overflows", "rays", "", "", "rays whose stack overflowed"},
    {KS_DESC_STAT, "issue_new", "rays", "", "", "issues of new rays"},
    {KS_DESC_STAT, "issue_ist", "rays", "", "", "issues of rays back from the IST"},
    {KS_DESC_STAT, "issue_loop", "rays", "", "", "issues of looping/continuing rays"},
    {KS_DESC_STAT, "exit_stall_cycles", "cycles", "", "", "cycles the exit stage waited for a full output FIFO"},
    {KS_DESC_STAT, "stack_stall_cycles", "cycles", "", "", "cycles issue waited for a multi-cycle stack operation"},
    {KS_DESC_STAT, "flops", "FLOP", "", "", "slab test FLOPs (all N lanes per visit)"},
    {KS_DESC_STAT, "utilization", "fraction", "", "", "busy cycles / frame cycles"},
    {KS_DESC_PART, "fpu", "FPU", "", "",
     "slab tests and sort: branching x trv.box_flops + comparators FLOP units; energy per FLOP (docs/energy.md)"},
    {KS_DESC_PART, "stack_bank", "SRAM", "", "",
     "trv.stack_banks RAMs of trv.slots x depth/banks entries, 1R1W; pushes write, pops and culls read"},
    {KS_DESC_END, 0, 0, 0, 0, 0}};

const ks_module_desc trv_module_desc = {"trv", "BVH/MBVH traversal unit: node fetch, slab tests, sort, banked stack",
                                        trv_items, "trv"};

static const char *const trv_state_names[] = {"idle", "issue", "stall", "wait_out"};
enum { TRV_ST_IDLE, TRV_ST_ISSUE, TRV_ST_STALL, TRV_ST_WAIT_OUT };

uint32_t trv_pipeline_depth(const trv_params *p)
{
    const sort_net *net = sort_net_get(p->core.width);
    uint32_t sort = net ? (uint32_t)net->layers : 0;
    return p->stages_fetch + p->stages_box + sort + p->stages_stack + p->stages_next;
}

static int trv_step(void *user, uint64_t cycle);

static int trv_busy(void *user)
{
    trv_unit *t = user;
    return t->rays_in_unit > 0;
}

static void trv_describe(void *user, char *buf, unsigned cap)
{
    trv_unit *t = user;
    snprintf(buf, cap,
             "%u rays held; pipe %u/%u, loop %u/%u; in_new %u, in_ist %u waiting; out_ist %u/%u, out_done %u/%u%s",
             (unsigned)t->rays_in_unit, t->pipe.count, t->pipe.cap,
             t->loop.count, t->loop.cap, t->in_new ? ks_fifo_occupancy(t->in_new) : 0,
             t->in_ist ? ks_fifo_occupancy(t->in_ist) : 0, t->out_ist ? ks_fifo_occupancy(t->out_ist) : 0,
             t->out_ist ? ks_fifo_capacity(t->out_ist) : 0, t->out_done ? ks_fifo_occupancy(t->out_done) : 0,
             t->out_done ? ks_fifo_capacity(t->out_done) : 0,
             pipe_ring_ready(&t->pipe, ks_clock_cycle(t->clk)) ? " (exit stage waits for a full output FIFO)" : "");
}

static bool trv_setup(trv_unit *t, uint32_t id, const char *name, const trv_params *p, const accel_image *img,
              accel_ray *rays, ks_sim *sim, ks_clock *clk, uint32_t loop_capacity, char *err, unsigned errlen)
{
    memset(t, 0, sizeof *t);
    if (!trv_core_init(&t->core, &p->core, img, NULL, NULL, err, errlen))
        return false;
    t->p = *p;
    t->id = id;
    t->rays = rays;
    t->clk = clk;
    t->depth = trv_pipeline_depth(p);
    const sort_net *net = sort_net_get(p->core.width);
    t->latency_bypass = t->depth - 1 - (net ? (uint32_t)net->layers : 0);
    /* one ray per stage after issue: capacity depth, exit depth-1 cycles later */
    if (!pipe_ring_init(&t->pipe, t->depth, t->depth - 1)) {
        snprintf(err, errlen, "%s: out of memory", name);
        trv_core_free(&t->core);
        return false;
    }
    /* the loop back to the issue stage: a bounded FIFO (fifo.ray_trv_loop), one cycle */
    if (!pipe_ring_init(&t->loop, loop_capacity ? loop_capacity : p->core.slots, 1)) {
        snprintf(err, errlen, "%s: out of memory", name);
        pipe_ring_free(&t->pipe);
        trv_core_free(&t->core);
        return false;
    }
    (void)sim;
    t->proc = ks_clocked_create(clk, name, trv_step, t);
    ks_clocked_set_describe(t->proc, trv_busy, trv_describe);
    return true;
}

void trv_connect(trv_unit *t, ks_fifo *in_new, ks_fifo *in_ist, ks_fifo *out_ist, ks_fifo *out_done)
{
    t->in_new = in_new, t->in_ist = in_ist, t->out_ist = out_ist, t->out_done = out_done;
    ks_clocked_wake_on(t->proc, ks_fifo_ev_written(in_new));
    ks_clocked_wake_on(t->proc, ks_fifo_ev_written(in_ist));
    ks_clocked_wake_on(t->proc, ks_fifo_ev_freed(out_ist));
    ks_clocked_wake_on(t->proc, ks_fifo_ev_freed(out_done));
}

void trv_set_probe(trv_unit *t, accel_probe_fn probe, void *ctx)
{
    t->core.probe = probe;
    t->core.probe_ctx = ctx;
}

void trv_set_events(trv_unit *t, accel_event_fn fn, void *user)
{
    t->core.ev = fn;
    t->core.ev_user = user;
}

int trv_register(trv_unit *t, const char *name, ks_stats *st, ks_vcd *vcd)
{
    int rc = 0;
    if (st) {
        trv_core_stats *c = &t->core.st;
        trv_stack_stats *s = &t->core.stack.st;
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "busy_cycles", &t->busy_cycles);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "passes", &c->passes);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "visits", &c->visits);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "pop_passes", &c->pop_passes);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "loops_miss", &c->loops_miss);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "loops_blocked", &c->loops_blocked);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "box_tests", &c->box_tests);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "box_lanes", &c->box_lanes);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "sort_passes", &c->sort_passes);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "sort_swaps", &c->sort_swaps);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "stack_pushes", &s->pushes);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "stack_pops", &s->pops);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "stack_ops", &s->ops);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "stack_conflict_cycles", &s->conflict_cycles);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "stack_max_depth", &s->max_depth_stat);
        for (uint32_t b = 0; b < t->core.stack.banks; b++) {
            char bn[48];
            snprintf(bn, sizeof bn, "stack_bank%u_writes", b);
            rc |= ks_stat_decl_counter(st, &trv_module_desc, name, bn, &s->bank_writes[b]);
            snprintf(bn, sizeof bn, "stack_bank%u_reads", b);
            rc |= ks_stat_decl_counter(st, &trv_module_desc, name, bn, &s->bank_reads[b]);
        }
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "culls", &c->culls);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "to_ist", &c->to_ist);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "done", &c->done);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "stack_overflows", &c->overflows);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "issue_new", &t->issue_new);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "issue_ist", &t->issue_ist);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "issue_loop", &t->issue_loop);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "exit_stall_cycles", &t->exit_stall_cycles);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "stack_stall_cycles", &t->stack_stall_cycles);
        rc |= ks_stat_decl_counter(st, &trv_module_desc, name, "flops", &t->flops);
    }
    if (vcd) {
        t->vcd = true;
        char nm[160];
        snprintf(nm, sizeof nm, "%s.state", name);
        t->v_state = ks_vcd_var_enum(vcd, nm, trv_state_names, 4, TRV_ST_IDLE);
        snprintf(nm, sizeof nm, "%s.issue_ray", name);
        t->v_issue_ray = ks_vcd_var_int(vcd, nm, 32, 0xFFFFFFFFu);
        snprintf(nm, sizeof nm, "%s.exit_ray", name);
        t->v_exit_ray = ks_vcd_var_int(vcd, nm, 32, 0xFFFFFFFFu);
        snprintf(nm, sizeof nm, "%s.rays_held", name);
        t->v_rays = ks_vcd_var_int(vcd, nm, 16, 0);
        snprintf(nm, sizeof nm, "%s.pipe.occupancy", name);
        t->pipe.v_occ = ks_vcd_var_int(vcd, nm, 16, 0);
        snprintf(nm, sizeof nm, "%s.loop.occupancy", name);
        t->loop.v_occ = ks_vcd_var_int(vcd, nm, 16, 0);
        /* stage s of the pipeline (0 = issue = fetch1) by function, in the
         * order of trv_pipeline_depth */
        const sort_net *net = sort_net_get(t->p.core.width);
        const pipe_stage_part parts[] = {
            {"fetch", t->p.stages_fetch}, {"box", t->p.stages_box}, {"sort", net ? (uint32_t)net->layers : 0},
            {"stack", t->p.stages_stack}, {"next", t->p.stages_next}};
        pipe_trace_init(&t->stage_rays, vcd, name, parts, sizeof parts / sizeof parts[0]);
    }
    return rc;
}

static void trv_teardown(trv_unit *t)
{
    trv_core_free(&t->core);
    pipe_ring_free(&t->pipe);
    pipe_ring_free(&t->loop);
    pipe_trace_free(&t->stage_rays);
}

/* Earliest future cycle at which a FIFO head becomes readable (UINT64_MAX if none). */
static inline uint64_t head_cycle(const ks_fifo *f, ks_clock *clk)
{
    if (!f || !ks_fifo_occupancy(f))
        return UINT64_MAX;
    return ks_clock_cycle_at_or_after(clk, ks_fifo_head_ready_time(f));
}

/* The step, with the VCD code compiled out when vcd is false. */
static inline __attribute__((always_inline)) int trv_step_body(trv_unit *t, uint64_t cycle, const bool vcd)
{
    int progress = 0;
    int state = TRV_ST_IDLE;

    /* exit stage: one ray per cycle leaves the pipeline */
    const pipe_item *head = pipe_ring_ready(&t->pipe, cycle);
    if (head) {
        ks_fifo *out = NULL;
        switch (head->result) {
        case TRV_TO_IST: out = t->out_ist; break;
        case TRV_DONE:
        case TRV_OVERFLOW: out = t->out_done; break;
        default: break;   /* next node or next chance: the loop */
        }
        if (out ? ks_fifo_can_write(out) : !pipe_ring_full(&t->loop)) {
            pipe_item it = pipe_ring_pop_v(&t->pipe, vcd);
            trv_msg m = {it.ray, 0};
            if (out) {
                t->rays_in_unit--;
                KS_FIFO_WRITE(out, &m);
            } else {
                pipe_ring_push_v(&t->loop, it.ray, 0, cycle, vcd);
            }
            if (vcd && t->v_exit_ray)
                ks_vcd_set(t->v_exit_ray, m.ray);
            progress++;
        } else {
            t->exit_stall_cycles++;
            state = TRV_ST_WAIT_OUT;
        }
    } else if (vcd && t->v_exit_ray) {
        ks_vcd_set(t->v_exit_ray, 0xFFFFFFFFu);
    }

    /* issue stage */
    if (cycle < t->busy_until) {
        state = TRV_ST_STALL;
        t->stack_stall_cycles++;
        progress++;   /* the stack stage is working (the exit stage keeps draining) */
    } else if (!pipe_ring_full(&t->pipe)) {
        trv_msg m;
        bool got = true;
        if (ks_fifo_can_read(t->in_ist) && KS_FIFO_READ(t->in_ist, &m)) {
            t->issue_ist++;
            t->rays_in_unit++;
        } else if (pipe_ring_ready(&t->loop, cycle)) {
            m.ray = pipe_ring_pop_v(&t->loop, vcd).ray;
            t->issue_loop++;
        } else if (ks_fifo_can_read(t->in_new) && KS_FIFO_READ(t->in_new, &m)) {
            t->issue_new++;
            t->rays_in_unit++;
        } else {
            got = false;
        }
        if (got) {
            accel_ray *r = &t->rays[m.ray];
            uint32_t stack_cycles = 0;
            uint64_t visits0 = t->core.st.visits;
            m.result = (uint32_t)trv_core_pass(&t->core, r, cycle, &stack_cycles);
            if (t->core.st.visits != visits0)
                t->flops += (uint64_t)t->p.box_flops * (uint64_t)t->p.core.width;
            if (m.result == TRV_OVERFLOW)
                t->failed = true;
            /* occlusion rays skip the sort stages (paper sec. 3.1) */
            pipe_ring_push_lat_v(&t->pipe, m.ray, m.result, cycle, r->occlusion ? t->latency_bypass : t->pipe.latency,
                                 vcd);
            t->busy_cycles++;
            if (m.result != TRV_LOOP_MISS && m.result != TRV_LOOP_BLOCKED && t->core.fetch_cycles > stack_cycles)
                stack_cycles = t->core.fetch_cycles;   /* a node spanning two lines of one L1 bank */
            if (stack_cycles > 1)
                t->busy_until = cycle + stack_cycles;
            if (vcd && t->v_issue_ray) {
                ks_vcd_set(t->v_issue_ray, m.ray);
                pipe_trace_issue(&t->stage_rays, cycle, m.ray);
            }
            state = TRV_ST_ISSUE;
            progress++;
        } else if (vcd && t->v_issue_ray) {
            ks_vcd_set(t->v_issue_ray, 0xFFFFFFFFu);
        }
    }
    if (vcd && t->v_state) {
        ks_vcd_set(t->v_state, (uint64_t)state);
        ks_vcd_set(t->v_rays, t->rays_in_unit);
        pipe_trace_update(&t->stage_rays, cycle);
    }
    if (!progress) {
        /* sleep until the next input or pipe head becomes readable (events
         * cover new writes and freed outputs) */
        uint64_t next = pipe_ring_next_exit(&t->pipe);
        uint64_t c;
        if ((c = pipe_ring_next_exit(&t->loop)) < next)
            next = c;
        if ((c = head_cycle(t->in_ist, t->clk)) < next)
            next = c;
        if ((c = head_cycle(t->in_new, t->clk)) < next)
            next = c;
        if (vcd && pipe_trace_occupied(&t->stage_rays, cycle))
            next = cycle + 1;   /* VCD on: the stage variables change every cycle */
        if (next != UINT64_MAX && next > cycle)
            ks_clocked_sleep_until_cycle(t->proc, next);
    }
    return progress;
}

static int trv_step(void *user, uint64_t cycle)
{
    trv_unit *t = user;
    return t->vcd ? trv_step_body(t, cycle, true) : trv_step_body(t, cycle, false);
}

trv_unit *trv_create(uint32_t id, const char *name, const trv_params *p, const accel_image *img, accel_ray *rays,
                     ks_sim *sim, ks_clock *clk, uint32_t loop_capacity, char *err, unsigned errlen)
{
    trv_unit *t = calloc(1, sizeof *t);
    if (!t) {
        snprintf(err, errlen, "trv: out of memory");
        return NULL;
    }
    if (!trv_setup(t, id, name, p, img, rays, sim, clk, loop_capacity, err, errlen)) {
        free(t);
        return NULL;
    }
    return t;
}

void trv_destroy(trv_unit *t)
{
    if (!t)
        return;
    trv_teardown(t);
    free(t);
}
