/* accel_config.c — ray-side schemas (see accel_config.h). Numbers not in the
 * paper are marked "ours" in the descriptions and the presets. */
#include "model/accel_config.h"

#include "model/energy/energy.h"

#include <stdio.h>
#include <string.h>

#include "model/mem/memsys_config.h"
#include "model/ray/sort_net.h"
#include "tracer/bvh/bvh_layout.h"

#define FIFO_PARAM(name, desc) {name, RTCFG_INT, "32", 1, 65536, 0, NULL, "entries", desc}
static const rtcfg_param fifo_params_tab[] = {
    FIFO_PARAM("ray_new", "scheduler -> TRV new rays (per TRV; paper sec. 3: 32)"),
    FIFO_PARAM("ray_leaf", "TRV -> IST leaf work (per TRV)"),
    FIFO_PARAM("ray_return", "IST -> TRV rays back for the pop (per TRV)"),
    FIFO_PARAM("ray_done", "TRV -> scheduler finished rays (per TRV)"),
    FIFO_PARAM("ray_trv_loop", "TRV exit -> TRV issue (next node / next chance)"),
    FIFO_PARAM("ray_ist_loop", "IST exit -> IST issue (next chance after a miss)"),
    {"ray_latency", RTCFG_INT, "1", 1, 1000, 0, NULL, "cycles", "latency of the ray-side FIFOs between units"},
};
static int check_ray_side(const rtcfg *cfg, char *err, size_t errlen);
const rtcfg_schema accel_schema_fifo = {"fifo", "ray-side FIFOs", fifo_params_tab, 7, check_ray_side};

/* The BVH the machine walks: built on the host by the tracer (tracer/bvh/bvh.h),
 * whose builder the paper names but whose parameters it leaves open (sec.
 * 3.2: "BVH trees are constructed with a binned SAH sweep, and MBVHs with
 * Wald's top-down recursive splitting algorithm"). frame/frame.h
 * (rtsim_bvh_params) turns these keys into the builder's parameters. */
static const rtcfg_param bvh_params_tab[] = {
    {"builder", RTCFG_ENUM, "collapse", 0, 0, 0, "collapse|wald", "",
     "how an N-wide MBVH is built: collapse (the binned-SAH BVH2, its SAH also ending leaves, collapsed N wide) "
     "or wald (top-down recursive splitting, paper sec. 3.2: the same SAH splits, leaves cut by size only, "
     "grouped N wide); BVH2 machines ignore it (ours: collapse, docs/paper.md \"Builder\")"},
    {"leaf_size", RTCFG_INT, "4", 1, RT_LEAF_MAX, 0, NULL, "triangles", "most triangles in a leaf (ours)"},
    {"bins", RTCFG_INT, "16", 4, 256, 0, NULL, "bins", "SAH bins per axis of the binned sweep (ours)"},
    {"cost_node", RTCFG_REAL, "1", 1e-6, 1e6, 0, NULL, "", "SAH cost of a node visit (ours)"},
    {"cost_tri", RTCFG_REAL, "1", 1e-6, 1e6, 0, NULL, "", "SAH cost of a triangle test (ours)"},
};
const rtcfg_schema accel_schema_bvh = {"bvh", "the BVH built for the machine (host side)", bvh_params_tab, 5, NULL};

int accel_add_schemas(rtcfg *cfg, char *err, size_t errlen)
{
    const rtcfg_schema *all[] = {&trv_schema, &ist_schema, &sched_schema, &accel_schema_fifo,
                                 &accel_schema_bvh, &energy_schema};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        if (rtcfg_add_schema(cfg, all[i], err, errlen))
            return -1;
    return 0;
}

void accel_params_get(const rtcfg *cfg, accel_params *o)
{
    memset(o, 0, sizeof *o);
#define I(key) ((uint32_t)rtcfg_int(cfg, key))
    o->width = (int)rtcfg_int(cfg, "machine.branching");
    o->clock_mhz = rtcfg_real(cfg, "machine.clock_mhz");
    o->trv_count = I("trv.count");
    trv_core_params *c = &o->trv.core;
    c->width = o->width;
    c->slots = I("trv.slots");
    c->stack_depth = I("trv.stack_depth");
    c->stack_banks = I("trv.stack_banks");
    /* auto (0): N banks for an N-wide MBVH, the N-1 pushes of a visit plus
     * the pop in distinct banks (paper sec. 3.1: 4 banks for MBVH4, as the
     * CACTI figures of docs/energy.md assume); one 1R1W bank for BVH2 */
    if (c->stack_banks == 0)
        c->stack_banks = o->width > 2 ? (uint32_t)o->width : 1;
    int ds = rtcfg_enum(cfg, "trv.distance_stack");
    c->distance_cull = ds == 0 ? o->width > 2 : ds == 1;
    o->trv.stages_fetch = I("node_l1.hit_latency");   /* the fetch stages are the node L1 access */
    o->trv.stages_box = I("trv.stages_box");
    o->trv.stages_stack = I("trv.stages_stack");
    o->trv.stages_next = I("trv.stages_next");
    o->trv.box_flops = I("trv.box_flops");
    o->ist.latency = I("ist.latency");
    o->ist.flops_per_test = I("ist.flops_per_test");
    o->sched.admit_per_cycle = I("sched.admit_per_cycle");
    o->sched.shade_latency = I("sched.shade_latency");
    o->sched.watchdog_cycles = (uint64_t)rtcfg_int(cfg, "sched.watchdog_cycles");
    o->fifo_latency = I("fifo.ray_latency");
#undef I
}

/* ------------------------------------------------ deadlock-free minima
 * Why these bounds (docs/accel.md, "Machines that cannot run"): a TRV's
 * pipeline holds at most P = depth rays (one per stage, trv.h), and a TRV
 * owns at most trv.slots rays wherever they are (scheduler.h).
 *  - TRV loop: the exit stage waits for the loop FIFO and the issue stage
 *    waits for the pipeline, so the TRV deadlocks exactly when its pipeline
 *    is full, its head goes round the loop and the loop is full: P + loop
 *    rays of one TRV. With loop >= slots - P + 1 that many rays never exist.
 *  - Leaf + return: the TRV-IST cycle stops when a TRV's pipeline is full
 *    with its head bound for the IST, its leaf FIFO is full, the IST's
 *    pipeline head is one of its rays waiting for its full return FIFO: P +
 *    leaf + return + 1 rays of one TRV. With leaf + return >= slots - P it
 *    cannot happen.
 *  - IST loop: the IST takes a new ray only when no looping ray is ready, so
 *    it never holds more than its pipeline + 1 rays, one fewer than a full
 *    pipeline, a full loop and a ray at issue: any capacity >= 1 is safe.
 *  - new, done: the scheduler writes new rays only into free room and reads
 *    every done FIFO every cycle, so neither is part of a cycle of waits.
 * The memory side is covered in docs/accel.md (fills are always drained). */

uint32_t accel_trv_depth_of(const rtcfg *cfg)
{
    /* The unit's own formula (trv_pipeline_depth), on the stages the
     * configuration gives; the fetch stages are the node L1 access, as in
     * accel_params_get. */
    trv_params p;
    memset(&p, 0, sizeof p);
    p.core.width = (int)rtcfg_int(cfg, "machine.branching");
    p.stages_fetch = rtcfg_has(cfg, "node_l1.hit_latency") ? (uint32_t)rtcfg_int(cfg, "node_l1.hit_latency") : 1;
    p.stages_box = (uint32_t)rtcfg_int(cfg, "trv.stages_box");
    p.stages_stack = (uint32_t)rtcfg_int(cfg, "trv.stages_stack");
    p.stages_next = (uint32_t)rtcfg_int(cfg, "trv.stages_next");
    return trv_pipeline_depth(&p);
}

static uint32_t trv_loop_min(const rtcfg *cfg)
{
    uint32_t slots = (uint32_t)rtcfg_int(cfg, "trv.slots"), depth = accel_trv_depth_of(cfg);
    return slots >= depth ? slots - depth + 1 : 1;
}

const accel_fifo_desc accel_ray_fifos[ACCEL_FIFO_COUNT] = {
    [ACCEL_FIFO_NEW] = {"trv#.new", "fifo.ray_new", "sched", "trv#", false, NULL},
    [ACCEL_FIFO_LEAF] = {"trv#.leaf", "fifo.ray_leaf", "trv#", "ist", false, NULL},
    [ACCEL_FIFO_RETURN] = {"trv#.return", "fifo.ray_return", "ist", "trv#", false, NULL},
    [ACCEL_FIFO_DONE] = {"trv#.done", "fifo.ray_done", "trv#", "sched", false, NULL},
    [ACCEL_FIFO_TRV_LOOP] = {"trv#.loop", "fifo.ray_trv_loop", "trv#", "trv#", true, trv_loop_min},
    [ACCEL_FIFO_IST_LOOP] = {"ist.loop", "fifo.ray_ist_loop", "ist", "ist", true, NULL},
};

bool accel_fifo_per_trv(const accel_fifo_desc *d) { return strchr(d->name, '#') != NULL; }

const char *accel_fifo_expand(const char *pattern, uint32_t trv, char *buf, size_t len)
{
    const char *hash = strchr(pattern, '#');
    if (hash)
        snprintf(buf, len, "%.*s%u%s", (int)(hash - pattern), pattern, trv, hash + 1);
    else
        snprintf(buf, len, "%s", pattern);
    return buf;
}

uint32_t accel_fifo_min(const rtcfg *cfg, accel_fifo_id id)
{
    return accel_ray_fifos[id].min ? accel_ray_fifos[id].min(cfg) : 1;
}

uint32_t accel_leaf_return_min(const rtcfg *cfg)
{
    uint32_t slots = (uint32_t)rtcfg_int(cfg, "trv.slots"), depth = accel_trv_depth_of(cfg);
    return slots > depth + 2 ? slots - depth : 2;
}

static int check_ray_side(const rtcfg *cfg, char *err, size_t errlen)
{
    if (!rtcfg_has(cfg, "trv.slots"))
        return 0;
    uint32_t slots = (uint32_t)rtcfg_int(cfg, "trv.slots"), depth = accel_trv_depth_of(cfg);
    const char *loop_key = accel_ray_fifos[ACCEL_FIFO_TRV_LOOP].key;
    int64_t loop = rtcfg_int(cfg, loop_key);
    uint32_t loop_min = accel_fifo_min(cfg, ACCEL_FIFO_TRV_LOOP);
    if (loop < loop_min)
        return rtcfg_errorf(err, errlen,
                            "%s = %lld (%s) can deadlock a TRV: with trv.slots = %u and a %u-stage "
                            "pipeline it must be >= trv.slots - stages + 1 = %u (allowed %u..65536; stages = "
                            "node_l1.hit_latency + trv.stages_box + sort layers + trv.stages_stack + trv.stages_next)",
                            loop_key, (long long)loop, rtcfg_source(cfg, loop_key), slots, depth, loop_min, loop_min);
    /* Caches that rays wait on: a probe is all-or-nothing (cache.h), so a
     * waiting ray needs every line of its node (triangle) present at once.
     * When the cache cannot hold the lines of every ray that may wait on it
     * at the same time, the rays' fills evict each other's lines for ever
     * (found by tb_accel_random_configs: an 8-line node L1, 7-line nodes, 3
     * rays). Waiting on a node L1: the rays of its TRV (trv.slots); on the
     * primitive cache: the rays the IST holds, at most its test pipeline + 1
     * (accel_config.c, IST loop). */
    if (rtcfg_has(cfg, "node_l1.size")) {
        int64_t line = memsys_line_bytes(cfg, "node_l1");
        int64_t lines = memsys_lines_touched(memsys_node_bytes(cfg), line);
        int64_t need = (int64_t)slots * lines;
        if (rtcfg_int(cfg, "node_l1.size") / line < need)
            return rtcfg_errorf(err, errlen,
                                "node_l1.size = %lld holds %lld lines, but the trv.slots = %u rays of a TRV may each "
                                "wait for a node of up to %lld lines of node_l1.line = %lld B: node_l1.size must be >= "
                                "%lld (or lower trv.slots)",
                                (long long)rtcfg_int(cfg, "node_l1.size"), (long long)(rtcfg_int(cfg, "node_l1.size") / line),
                                slots, (long long)lines, (long long)line, (long long)(need * line));
    }
    if (rtcfg_has(cfg, "prim.size")) {
        int64_t line = rtcfg_int(cfg, "prim.line");
        int64_t lines = memsys_lines_touched(RT_TRI_BYTES, line);
        int64_t rays = rtcfg_int(cfg, "ist.latency") + rtcfg_int(cfg, "prim.hit_latency") + 2;
        int64_t need = rays * lines;
        if (rtcfg_int(cfg, "prim.size") / line < need)
            return rtcfg_errorf(err, errlen,
                                "prim.size = %lld holds %lld lines, but the %lld rays the IST may hold (ist.latency + "
                                "prim.hit_latency + 2) may each wait for a triangle of up to %lld lines of prim.line = "
                                "%lld B: prim.size must be >= %lld",
                                (long long)rtcfg_int(cfg, "prim.size"), (long long)(rtcfg_int(cfg, "prim.size") / line),
                                (long long)rays, (long long)lines, (long long)line, (long long)(need * line));
    }
    const char *leaf_key = accel_ray_fifos[ACCEL_FIFO_LEAF].key, *ret_key = accel_ray_fifos[ACCEL_FIFO_RETURN].key;
    int64_t leaf = rtcfg_int(cfg, leaf_key), ret = rtcfg_int(cfg, ret_key);
    uint32_t lr_min = accel_leaf_return_min(cfg);
    if (leaf + ret < lr_min)
        return rtcfg_errorf(err, errlen,
                            "%s + %s = %lld + %lld can deadlock the TRV-IST loop: with "
                            "trv.slots = %u and a %u-stage TRV pipeline their sum must be >= %u (each 1..65536)",
                            leaf_key, ret_key, (long long)leaf, (long long)ret, slots, depth, lr_min);
    return 0;
}
