/* accel_config.c — ray-side schemas (see accel_config.h). Numbers not in the
 * paper are marked "ours" in the descriptions and the presets. */
#include "model/accel_config.h"

#include "model/energy/energy.h"

#include <string.h>

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
const rtcfg_schema accel_schema_trv = {"trv", "traversal units (sort stages = sorting network depth, sort_net.h)",
                                       trv_params_tab, 9, NULL};

static const rtcfg_param ist_params_tab[] = {
    {"latency", RTCFG_INT, "16", 1, 256, 0, NULL, "cycles",
     "Wald test pipeline depth after the primitive cache access (ours)"},
    {"flops_per_test", RTCFG_INT, "39", 1, 256, 0, NULL, "FLOP",
     "FLOPs per Wald test, division = 11 (paper sec. 3.2): 28 + 11"},
};
const rtcfg_schema accel_schema_ist = {"ist", "intersection unit", ist_params_tab, 2, NULL};

static const rtcfg_param sched_params_tab[] = {
    {"admit_per_cycle", RTCFG_INT, "1", 1, 64, 0, NULL, "rays/cycle", "rays the scheduler admits per cycle (ours)"},
    {"shade_latency", RTCFG_INT, "0", 0, 1000000, 0, NULL, "cycles",
     "completion to bounce-ray ready: shading outside the accelerator (ours)"},
    {"watchdog_cycles", RTCFG_INT, "2000000", 0, 1e12, 0, NULL, "cycles",
     "stop with a report when no ray completes for this long (0 = off)"},
};
const rtcfg_schema accel_schema_sched = {"sched", "ray scheduler", sched_params_tab, 3, NULL};

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
const rtcfg_schema accel_schema_fifo = {"fifo", "ray-side FIFOs", fifo_params_tab, 7, NULL};

static const char *const fifo_keys[] = {"fifo.ray_new",      "fifo.ray_leaf",     "fifo.ray_return",
                                        "fifo.ray_done",     "fifo.ray_trv_loop", "fifo.ray_ist_loop"};

unsigned accel_fifo_key_count(void) { return 6; }
const char *accel_fifo_key(unsigned i) { return i < 6 ? fifo_keys[i] : NULL; }

int accel_add_schemas(rtcfg *cfg, char *err, size_t errlen)
{
    const rtcfg_schema *all[] = {&accel_schema_trv, &accel_schema_ist, &accel_schema_sched, &accel_schema_fifo,
                                 &energy_schema};
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
    o->fifo_new = I("fifo.ray_new");
    o->fifo_leaf = I("fifo.ray_leaf");
    o->fifo_return = I("fifo.ray_return");
    o->fifo_done = I("fifo.ray_done");
    o->fifo_trv_loop = I("fifo.ray_trv_loop");
    o->fifo_ist_loop = I("fifo.ray_ist_loop");
    o->fifo_latency = I("fifo.ray_latency");
#undef I
}
