/* tb_ray_unit_tables.c — the ray-side units' description tables
 * (model/ray/trv.h, ist.h, scheduler.h): every table valid, each unit's
 * section is its schema, the FIFO table names schema keys, and the TRV's
 * pipeline depth (trv_pipeline_depth, the one formula every caller uses). */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/accel_config.h"
#include "model/mem/memsys_config.h"
#include "model/ray/ist.h"
#include "model/ray/scheduler.h"
#include "model/ray/trv.h"
#include "testbench/tb.h"

/* The ray-side FIFO table names each FIFO's key; the [fifo] schema defines
 * it: every key the table names must be one the schema registers. */
static void test_ray_fifo_table_keys(void)
{
    tb_begin("ray_fifo_table_keys_are_schema_keys");
    char err[300];
    rtcfg *cfg = rtcfg_create();
    TB_CHECK(cfg && memsys_add_schemas(cfg, err, sizeof err) == 0 && accel_add_schemas(cfg, err, sizeof err) == 0,
             "schemas: %s", err);
    for (int i = 0; cfg && i < ACCEL_FIFO_COUNT; i++)
        TB_CHECK(rtcfg_has(cfg, accel_ray_fifos[i].key), "%s: key %s not in the [fifo] schema",
                 accel_ray_fifos[i].name, accel_ray_fifos[i].key);
    rtcfg_destroy(cfg);
    tb_end();
}

static void test_module_tables(void)
{
    tb_begin("module_description_tables_valid");
    const ks_module_desc *descs[] = {&trv_module_desc, &ist_module_desc, &sched_module_desc};
    char err[300];
    for (int i = 0; i < 3; i++) {
        TB_CHECK(ks_module_desc_check(descs[i], err, sizeof err) == 0, "%s", err);
        /* parameters: the unit's configuration section, not rows of its own */
        TB_CHECK(descs[i]->config_sections && !strcmp(descs[i]->config_sections, descs[i]->name) &&
                     ks_module_desc_count(descs[i], KS_DESC_PARAM) == 0 &&
                     ks_module_desc_count(descs[i], KS_DESC_PORT) > 0 && ks_module_desc_count(descs[i], KS_DESC_STAT) > 0,
                 "%s documents its section, ports and statistics", descs[i]->name);
    }
    /* the section the description names is the schema the unit declares */
    TB_CHECK(!strcmp(trv_schema.section, "trv") && !strcmp(ist_schema.section, "ist") &&
                 !strcmp(sched_schema.section, "sched"),
             "schema sections");
    /* depth: fetch 1 + box 3 + sort layers + stack 1 + next 1; MBVH4 is 2 deeper than BVH2 (paper 3.1) */
    trv_params p = {{2, false, 32, 64, 1}, 1, 3, 1, 1, 12};
    uint32_t d2 = trv_pipeline_depth(&p);
    p.core.width = 4;
    TB_EQ_INT(trv_pipeline_depth(&p), d2 + 2);
    tb_end();
}

int main(void)
{
    test_ray_fifo_table_keys();
    test_module_tables();
    return tb_finish();
}
