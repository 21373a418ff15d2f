/* tb_energy — the energy and area model (model/energy/energy_table.h, model/energy/energy.h):
 * table loading and its errors (file:line, key), the figure-matching rule
 * (exact rows, the scaling laws, node-sized words of index-addressed caches,
 * structures with no figure refused), and
 * energy/power/area arithmetic on a small machine computed by hand here. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/accel_top.h"
#include "model/energy/energy.h"
#include "model/energy/energy_table.h"
#include "testbench/tb.h"

static char tmpdir[TB_PATH_MAX];

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        perror(path);
        exit(2);
    }
    fputs(text, f);
    fclose(f);
}

static bool near(double a, double b) { return fabs(a - b) <= 1e-12 * (fabs(a) + fabs(b)) + 1e-15; }
#define TB_NEAR(a, b) TB_CHECK(near((a), (b)), "%s = %.15g, expected %s = %.15g", #a, (double)(a), #b, (double)(b))

/* A small table: one cache row, one RAM row, FPU figures; numbers chosen so
 * that the hand computation below is easy to follow. */
static const char *small_sram =
    "; test table\n"
    "[c16k]\n"
    "kind = cache\nsize = 16384\nways = 4\nline = 64\nports = 1rw\n"
    "area = 0.1\nread = 0.02\nwrite = 0.03\nleak = 10\n"
    "[r1k]\n"
    "kind = ram\nsize = 1024\nline = 32\nports = 1r1w\n"
    "area = 0.01\nread = 0.004\nwrite = 0.005\nleak = 1\n";
static const char *small_fpu = "[fpu]\nenergy_pj_per_flop = 2\narea_mm2_per_flop_unit = 0.001\nleak_mw_per_flop_unit = 0.1\n";

static int load_small(energy_table *t, char *err, size_t errlen)
{
    char s[TB_PATH_MAX], f[TB_PATH_MAX];
    tb_pathf(s, sizeof s, "%s/sram.ini", tmpdir);
    tb_pathf(f, sizeof f, "%s/fpu.ini", tmpdir);
    write_file(s, small_sram);
    write_file(f, small_fpu);
    return energy_table_load(t, s, f, err, errlen);
}

static void test_load_and_exact(void)
{
    tb_begin("energy_table_load_exact_row");
    static energy_table t;
    char err[TB_ERR_MAX];
    TB_EQ_INT(load_small(&t, err, sizeof err), 0);
    TB_EQ_INT(t.nrows, 2);
    energy_sram fig;
    energy_sram_req req = {"l1", ENERGY_CACHE, ENERGY_1RW, 16384, 4, 64, 0};
    TB_EQ_INT(energy_sram_figure(&t, &req, &fig, err, sizeof err), 0);
    TB_CHECK(!strcmp(fig.name, "c16k"), "row %s", fig.name);
    TB_NEAR(fig.area_mm2, 0.1);
    TB_NEAR(fig.read_nj, 0.02);
    TB_NEAR(fig.write_nj, 0.03);
    TB_NEAR(fig.leak_mw, 10);
    TB_NEAR(t.fpu.energy_pj_per_flop, 2);
    tb_end();
}

static void test_scaling(void)
{
    tb_begin("energy_sram_figure_scaling_laws");
    static energy_table t;
    char err[TB_ERR_MAX];
    TB_EQ_INT(load_small(&t, err, sizeof err), 0);
    energy_sram fig;
    /* a 32 KB cache: s = 2 -> area, leakage x2; energies x sqrt(2) */
    energy_sram_req req = {"l1", ENERGY_CACHE, ENERGY_1RW, 32768, 4, 64, 0};
    TB_EQ_INT(energy_sram_figure(&t, &req, &fig, err, sizeof err), 0);
    TB_NEAR(fig.area_mm2, 0.2);
    TB_NEAR(fig.leak_mw, 20);
    TB_NEAR(fig.read_nj, 0.02 * sqrt(2.0));
    TB_NEAR(fig.write_nj, 0.03 * sqrt(2.0));
    /* a RAM of 64 entries x 16 B: s = 1, w = 1/2 -> area x1, energy x sqrt(1/2) */
    energy_sram_req ram = {"fifo", ENERGY_RAM, ENERGY_1R1W, 1024, 0, 16, 0};
    TB_EQ_INT(energy_sram_figure(&t, &ram, &fig, err, sizeof err), 0);
    TB_NEAR(fig.area_mm2, 0.01);
    TB_NEAR(fig.read_nj, 0.004 * sqrt(0.5));
    /* a tiny RAM (2 entries x 32 B): any smaller RAM is allowed, s = 1/16 */
    energy_sram_req tiny = {"fifo", ENERGY_RAM, ENERGY_1R1W, 64, 0, 32, 0};
    TB_EQ_INT(energy_sram_figure(&t, &tiny, &fig, err, sizeof err), 0);
    TB_NEAR(fig.area_mm2, 0.01 / 16);
    TB_NEAR(fig.read_nj, 0.004 / 4);
    tb_end();
}

static void test_no_figure(void)
{
    tb_begin("energy_sram_figure_refuses_uncovered_structures");
    static energy_table t;
    char err[TB_ERR_MAX];
    TB_EQ_INT(load_small(&t, err, sizeof err), 0);
    energy_sram fig;
    /* another line size: no row */
    energy_sram_req line32 = {"node_l1 (node_l1.size / node_l1.banks)", ENERGY_CACHE, ENERGY_1RW, 16384, 4, 32, 0};
    TB_EQ_INT(energy_sram_figure(&t, &line32, &fig, err, sizeof err), -1);
    TB_CHECK(strstr(err, "node_l1") && strstr(err, "no SRAM figure") && strstr(err, "32-byte line"), "%s", err);
    /* more than 4x the row's size */
    energy_sram_req big = {"node_l2", ENERGY_CACHE, ENERGY_1RW, 131072, 4, 64, 0};
    TB_EQ_INT(energy_sram_figure(&t, &big, &fig, err, sizeof err), -1);
    TB_CHECK(strstr(err, "[c16k]") && strstr(err, "within 4x"), "%s", err);
    /* a smaller cache than 1/4 of the row */
    energy_sram_req small = {"node_l1", ENERGY_CACHE, ENERGY_1RW, 2048, 4, 64, 0};
    TB_EQ_INT(energy_sram_figure(&t, &small, &fig, err, sizeof err), -1);
    /* other ports */
    energy_sram_req ports = {"stack", ENERGY_RAM, ENERGY_1RW, 1024, 0, 32, 0};
    TB_EQ_INT(energy_sram_figure(&t, &ports, &fig, err, sizeof err), -1);
    TB_CHECK(strstr(err, "none"), "%s", err);
    /* a word 8x wider than any row */
    energy_sram_req wide = {"fifo", ENERGY_RAM, ENERGY_1R1W, 8192, 0, 256, 0};
    TB_EQ_INT(energy_sram_figure(&t, &wide, &fig, err, sizeof err), -1);
    tb_end();
}

static void test_load_errors(void)
{
    static energy_table t;
    char err[TB_ERR_MAX], s[TB_PATH_MAX], f[TB_PATH_MAX];
    tb_pathf(s, sizeof s, "%s/bad_sram.ini", tmpdir);
    tb_pathf(f, sizeof f, "%s/fpu.ini", tmpdir);
    write_file(f, small_fpu);

    tb_begin("energy_table_bad_value_names_file_line_key");
    write_file(s, "[a]\nkind = cache\nsize = -5\n");
    TB_EQ_INT(energy_table_load(&t, s, f, err, sizeof err), -1);
    TB_CHECK(strstr(err, "bad_sram.ini:3:") && strstr(err, "size = '-5'") && strstr(err, "> 0"), "%s", err);
    tb_end();

    tb_begin("energy_table_missing_key_named");
    write_file(s, "[a]\nkind = ram\nsize = 1024\nline = 32\nports = 1r1w\narea = 0.1\nread = 0.1\nwrite = 0.1\n");
    TB_EQ_INT(energy_table_load(&t, s, f, err, sizeof err), -1);
    TB_CHECK(strstr(err, "[a] lacks key leak"), "%s", err);
    tb_end();

    tb_begin("energy_table_unknown_key_and_kind");
    write_file(s, "[a]\nkind = dram\n");
    TB_EQ_INT(energy_table_load(&t, s, f, err, sizeof err), -1);
    TB_CHECK(strstr(err, ":2:") && strstr(err, "cache|ram"), "%s", err);
    write_file(s, "[a]\ncolour = red\n");
    TB_EQ_INT(energy_table_load(&t, s, f, err, sizeof err), -1);
    TB_CHECK(strstr(err, "unknown key 'colour' in [a] (allowed kind, size,"), "%s", err);
    tb_end();

    /* the shared INI reader (config/ini_file.h): a key given twice, a folder */
    tb_begin("energy_table_key_twice_and_folder");
    write_file(s, "[a]\nkind = ram\nsize = 1024\nkind = cache\n");
    TB_EQ_INT(energy_table_load(&t, s, f, err, sizeof err), -1);
    TB_CHECK(strstr(err, "bad_sram.ini:4: a.kind given twice (first at line 2)"), "%s", err);
    TB_EQ_INT(energy_table_load(&t, tmpdir, f, err, sizeof err), -1);
    TB_CHECK(strstr(err, "is a folder, not an SRAM energy table (.ini) file"), "%s", err);
    tb_end();

    tb_begin("energy_table_fpu_missing_key");
    write_file(s, small_sram);
    write_file(f, "[fpu]\nenergy_pj_per_flop = 2\n");
    TB_EQ_INT(energy_table_load(&t, s, f, err, sizeof err), -1);
    TB_CHECK(strstr(err, "area_mm2_per_flop_unit"), "%s", err);
    tb_end();

    tb_begin("energy_table_missing_file");
    tb_pathf(s, sizeof s, "%s/none.ini", tmpdir);
    TB_EQ_INT(energy_table_load(&t, s, f, err, sizeof err), -1);
    TB_CHECK(strstr(err, "none.ini: cannot open"), "%s", err);
    tb_end();
}

/* One TRV (10 FLOP units), an IST (5), one stack bank (32 x 8 entries of
 * 4 B = 1 KB... as a 1 KB RAM of 4-byte words: w = 1/8), one 16 KB cache,
 * one FIFO of 32 x 32 B; the DRAM from the LPDDR3 figures. */
static void small_machine(energy_machine *m)
{
    memset(m, 0, sizeof *m);
    m->trv_count = 1;
    m->trv_flop_units = 10;
    m->ist_flop_units = 5;
    m->stack_slots = 32;
    m->stack_depth = 8;
    m->stack_banks = 1;
    m->stack_entry_bytes = 8;   /* 32 x 8 x 8 B = 2 KB: s = 2, w = 1/4 */
    m->ncache = 1;
    m->cache[0].name = "node_l1";
    m->cache[0].count = 1;
    m->cache[0].size = 16384;
    m->cache[0].line = 64;
    m->cache[0].ways = 4;
    m->cache[0].ports = 1;
    m->cache[0].banks = 1;
    m->nfifo = 1;
    m->fifo[0].key = "fifo.ray_new";
    m->fifo[0].count = 2;
    m->fifo[0].entries = 32;
    m->fifo[0].width_bytes = 32;
    m->dram_modeled = 1;
}

static void test_arithmetic(void)
{
    tb_begin("energy_compute_small_machine_by_hand");
    static energy_table t;
    char err[TB_ERR_MAX];
    TB_EQ_INT(load_small(&t, err, sizeof err), 0);
    energy_machine m;
    small_machine(&m);
    energy_model *em = energy_model_create_with(&t, &m, err, sizeof err);
    TB_CHECK(em != NULL, "%s", err);
    if (!em) {
        tb_end();
        return;
    }
    energy_activity a = {0};
    a.seconds = 1e-3;           /* 1 ms frame */
    a.trv_flops = 1e6;          /* 1e6 x 2 pJ = 2e-3 mJ */
    a.ist_flops = 5e5;          /* 1e-3 mJ */
    a.stack_reads = 1000;
    a.stack_writes = 2000;
    a.cache_reads[0] = 10000;
    a.cache_writes[0] = 100;
    a.fifo_reads[0] = 300;
    a.fifo_writes[0] = 400;
    a.dram_dynamic_nj = 5e6;    /* 5 mJ */
    a.dram_static_nj = 1e6;     /* 1 mJ */
    energy_compute(em, &a, 50.0);
    const energy_result *r = &em->r;
    /* TRV: 1e6 FLOP x 2 pJ; leakage 10 units x 0.1 mW x 1 ms; area 10 x 0.001 */
    TB_NEAR(r->dynamic_mj[EU_TRV], 2e-3);
    TB_NEAR(r->static_mj[EU_TRV], 1e-3);
    TB_NEAR(r->area_mm2[EU_TRV], 0.01);
    TB_NEAR(r->dynamic_mj[EU_IST], 1e-3);
    TB_NEAR(r->static_mj[EU_IST], 0.5e-3);
    TB_NEAR(r->area_mm2[EU_IST], 0.005);
    /* stack bank: 2 KB of 8-byte words from the 1 KB / 32 B row: s = 2,
     * w = 1/4: area 0.02, leak 2 mW, energies x sqrt(1/2) */
    double e = sqrt(0.5);
    TB_NEAR(r->dynamic_mj[EU_STACK], (1000 * 0.004 * e + 2000 * 0.005 * e) / 1e6);
    TB_NEAR(r->static_mj[EU_STACK], 2 * 1e-3);
    TB_NEAR(r->area_mm2[EU_STACK], 0.02);
    /* cache: exact row */
    TB_NEAR(r->dynamic_mj[EU_CACHE], (10000 * 0.02 + 100 * 0.03) / 1e6);
    TB_NEAR(r->static_mj[EU_CACHE], 10 * 1e-3);
    TB_NEAR(r->area_mm2[EU_CACHE], 0.1);
    /* FIFOs: two instances of the exact RAM row */
    TB_NEAR(r->dynamic_mj[EU_FIFO], (300 * 0.004 + 400 * 0.005) / 1e6);
    TB_NEAR(r->static_mj[EU_FIFO], 2 * 1 * 1e-3);
    TB_NEAR(r->area_mm2[EU_FIFO], 0.02);
    TB_NEAR(r->dynamic_mj[EU_DRAM], 5.0);
    TB_NEAR(r->static_mj[EU_DRAM], 1.0);
    TB_NEAR(r->area_mm2[EU_DRAM], 0.0);
    double total = 0, area = 0;
    for (int u = 0; u < EU_COUNT; u++) {
        TB_NEAR(r->energy_mj[u], r->dynamic_mj[u] + r->static_mj[u]);
        TB_NEAR(r->power_mw[u], r->energy_mj[u] / 1e-3);
        total += r->energy_mj[u];
        area += r->area_mm2[u];
    }
    TB_NEAR(r->total_energy_mj, total);
    TB_NEAR(r->total_area_mm2, area);
    TB_NEAR(r->total_power_mw, total / 1e-3);
    TB_NEAR(r->mrps_per_mm2, 50.0 / area);
    /* idle (clock-gated): no activity -> static energy only */
    energy_activity idle = {0};
    idle.seconds = 1e-3;
    energy_compute(em, &idle, 0);
    TB_NEAR(r->dynamic_mj[EU_TRV] + r->dynamic_mj[EU_CACHE] + r->dynamic_mj[EU_FIFO], 0.0);
    TB_NEAR(r->static_mj[EU_CACHE], 10 * 1e-3);
    energy_model_destroy(em);
    tb_end();

    tb_begin("energy_fixed_memory_per_byte");
    small_machine(&m);
    m.dram_modeled = 0;
    m.fixed_mem_pj_per_byte = 100;
    em = energy_model_create_with(&t, &m, err, sizeof err);
    TB_CHECK(em != NULL, "%s", err);
    if (em) {
        energy_activity b = {0};
        b.seconds = 1e-3;
        b.dram_bytes = 1e6;     /* 1e6 B x 100 pJ = 0.1 mJ */
        energy_compute(em, &b, 1);
        TB_NEAR(em->r.energy_mj[EU_DRAM], 0.1);
        energy_model_destroy(em);
    }
    tb_end();

    tb_begin("energy_model_refuses_part_without_figure");
    small_machine(&m);
    m.cache[0].line = 128;  /* the small table has no 128-byte-line cache_core */
    em = energy_model_create_with(&t, &m, err, sizeof err);
    TB_CHECK(em == NULL && strstr(err, "node_l1") && strstr(err, "128-byte line"), "%s", em ? "accepted" : err);
    energy_model_destroy(em);
    small_machine(&m);
    m.cache[0].ports = 2;   /* the small table has no [multiport] law */
    em = energy_model_create_with(&t, &m, err, sizeof err);
    TB_CHECK(em == NULL && strstr(err, "node_l1.ports") && strstr(err, "no [multiport]"), "%s", em ? "accepted" : err);
    energy_model_destroy(em);
    tb_end();

    tb_begin("energy_multiport_law");
    {
        static energy_table t2;
        char s[TB_PATH_MAX], f[TB_PATH_MAX];
        tb_pathf(s, sizeof s, "%s/sram_mp.ini", tmpdir);
        tb_pathf(f, sizeof f, "%s/fpu.ini", tmpdir);
        char text[2048];
        snprintf(text, sizeof text, "%s[multiport]\nports = 4\narea = 4\nread = 2\nwrite = 2\nleak = 16\n", small_sram);
        write_file(s, text);
        write_file(f, small_fpu);
        TB_EQ_INT(energy_table_load(&t2, s, f, err, sizeof err), 0);
        energy_sram fig = {.area_mm2 = 0.1, .read_nj = 0.02, .write_nj = 0.03, .leak_mw = 10};
        /* 2 ports: ratio^(ln 2 / ln 4) = sqrt(ratio) */
        TB_EQ_INT(energy_sram_ports(&t2, "node_l1.ports", 2, &fig, err, sizeof err), 0);
        TB_NEAR(fig.area_mm2, 0.2);
        TB_NEAR(fig.read_nj, 0.02 * sqrt(2.0));
        TB_NEAR(fig.leak_mw, 40);
        energy_sram one = {.area_mm2 = 0.1};
        TB_EQ_INT(energy_sram_ports(&t2, "x", 1, &one, err, sizeof err), 0);
        TB_NEAR(one.area_mm2, 0.1);
    }
    tb_end();
}

/* Loads the project's SRAM and FPU tables (RTSIM_DATA_DIR, else model/data). */
static int load_project_tables(energy_table *t, char *err, size_t errlen)
{
    char s[TB_PATH_MAX], f[TB_PATH_MAX];
    const char *dir = getenv("RTSIM_DATA_DIR");
    tb_pathf(s, sizeof s, "%s/energy/sram_45nm.ini", dir && *dir ? dir : "model/data");
    tb_pathf(f, sizeof f, "%s/energy/fpu_45nm.ini", dir && *dir ? dir : "model/data");
    return energy_table_load(t, s, f, err, errlen);
}

/* The project's own tables cover both preset machines exactly. */
static void test_project_tables(void)
{
    tb_begin("energy_project_tables_load");
    static energy_table t;
    char err[TB_ERR_MAX];
    TB_EQ_INT(load_project_tables(&t, err, sizeof err), 0);
    energy_sram fig;
    energy_sram_req l1 = {"node_l1", ENERGY_CACHE, ENERGY_1RW, 16384, 4, 128, 0};
    TB_EQ_INT(energy_sram_figure(&t, &l1, &fig, err, sizeof err), 0);
    TB_CHECK(!strcmp(fig.name, "l1node_mbvh4"), "%s", fig.name);
    energy_sram_req prim = {"prim", ENERGY_CACHE, ENERGY_1RW, 65536, 4, 64, 0};
    TB_EQ_INT(energy_sram_figure(&t, &prim, &fig, err, sizeof err), 0);
    TB_CHECK(!strcmp(fig.name, "prim_bank64k"), "%s", fig.name);
    energy_sram_req stack = {"stack", ENERGY_RAM, ENERGY_1R1W, 8192, 0, 4, 0};
    TB_EQ_INT(energy_sram_figure(&t, &stack, &fig, err, sizeof err), 0);
    TB_CHECK(!strcmp(fig.name, "stack_bvh_1r1w"), "%s", fig.name);
    tb_end();
}

/* The node-word rule (energy_table.h): an index-addressed node cache's word
 * of N x 32 B interpolated (or extrapolated) linearly in the line width
 * between the 64 and 128 B rows of model/data/energy/sram_45nm.ini; the
 * expected numbers are those rows' figures, combined by hand. */
static void test_node_word(void)
{
    tb_begin("energy_node_word_interpolated_in_line_width");
    static energy_table t;
    char err[TB_ERR_MAX];
    TB_EQ_INT(load_project_tables(&t, err, sizeof err), 0);
    energy_sram fig;
    /* MBVH3 L1: 16 KB, 4-way, 96 B words: the mean of [l1node_bvh] (64 B:
     * 0.0827 mm2, 0.03352 / 0.04420 nJ, 21.439 mW) and [l1node_mbvh4]
     * (128 B: 0.1524, 0.04241 / 0.05143, 19.431) */
    energy_sram_req w96 = {"node_l1", ENERGY_CACHE, ENERGY_1RW, 16384, 4, 96, 1};
    TB_EQ_INT(energy_sram_figure(&t, &w96, &fig, err, sizeof err), 0);
    TB_NEAR(fig.area_mm2, 0.11755);
    TB_NEAR(fig.read_nj, 0.037965);
    TB_NEAR(fig.write_nj, 0.047815);
    TB_NEAR(fig.leak_mw, 20.435);
    TB_NEAR(fig.line, 96);
    /* MBVH5: 160 B lies beyond the rows: extrapolated from 64 and 128 B,
     * fraction (160 - 64) / 64 = 1.5 */
    energy_sram_req w160 = {"node_l1", ENERGY_CACHE, ENERGY_1RW, 16384, 4, 160, 1};
    TB_EQ_INT(energy_sram_figure(&t, &w160, &fig, err, sizeof err), 0);
    TB_NEAR(fig.area_mm2, 0.0827 + 1.5 * (0.1524 - 0.0827));
    TB_NEAR(fig.read_nj, 0.046855);
    TB_NEAR(fig.write_nj, 0.055045);
    TB_NEAR(fig.leak_mw, 18.427);
    /* MBVH8: 256 B = 2x the widest row, the reach limit: 0.0827 + 3 x 0.0697 */
    energy_sram_req w256 = {"node_l1", ENERGY_CACHE, ENERGY_1RW, 16384, 4, 256, 1};
    TB_EQ_INT(energy_sram_figure(&t, &w256, &fig, err, sizeof err), 0);
    TB_NEAR(fig.area_mm2, 0.2918);
    /* the capacity an index-addressed 16 KB cache of 96 B words really has,
     * 42 sets x 4 ways x 96 B = 16128 B: both rows first scaled by the size
     * law (area x s, energies x sqrt(s)), then interpolated */
    energy_sram_req cap = {"node_l1", ENERGY_CACHE, ENERGY_1RW, 16128, 4, 96, 1};
    TB_EQ_INT(energy_sram_figure(&t, &cap, &fig, err, sizeof err), 0);
    TB_NEAR(fig.area_mm2, 0.11755 * (16128.0 / 16384));
    TB_NEAR(fig.read_nj, 0.037965 * sqrt(16128.0 / 16384));
    /* the L2: 128 KB rows [l2node_bvh] 0.5088 and [l2node_mbvh4] 0.5084 mm2 */
    energy_sram_req l2 = {"node_l2", ENERGY_CACHE, ENERGY_1RW, 131072, 4, 96, 1};
    TB_EQ_INT(energy_sram_figure(&t, &l2, &fig, err, sizeof err), 0);
    TB_NEAR(fig.area_mm2, 0.5086);
    TB_NEAR(fig.read_nj, (0.12338 + 0.19867) / 2);
    /* a word the table has: the row itself */
    energy_sram_req w128 = {"node_l1", ENERGY_CACHE, ENERGY_1RW, 16384, 4, 128, 1};
    TB_EQ_INT(energy_sram_figure(&t, &w128, &fig, err, sizeof err), 0);
    TB_CHECK(!strcmp(fig.name, "l1node_mbvh4") && fig.area_mm2 == 0.1524, "%s %g", fig.name, fig.area_mm2);
    /* refused: a byte-addressed 96 B line (no rule), a word beyond the reach */
    energy_sram_req byte96 = {"node_l1", ENERGY_CACHE, ENERGY_1RW, 16384, 4, 96, 0};
    TB_EQ_INT(energy_sram_figure(&t, &byte96, &fig, err, sizeof err), -1);
    TB_CHECK(strstr(err, "no SRAM figure") && strstr(err, "96-byte line"), "%s", err);
    energy_sram_req w288 = {"node_l1", ENERGY_CACHE, ENERGY_1RW, 16384, 4, 288, 1};
    TB_EQ_INT(energy_sram_figure(&t, &w288, &fig, err, sizeof err), -1);
    TB_CHECK(strstr(err, "node_l1") && strstr(err, "node-sized word") && strstr(err, "2x"), "%s", err);
    /* a table with one cache line width cannot interpolate */
    static energy_table one;
    TB_EQ_INT(load_small(&one, err, sizeof err), 0);
    TB_EQ_INT(energy_sram_figure(&one, &w96, &fig, err, sizeof err), -1);
    TB_CHECK(strstr(err, "1 such row width"), "%s", err);
    tb_end();
}

/* Both directions: every part the model builds is declared in its unit's
 * description, and every declared part is one the model builds. */
static void test_parts_declared(void)
{
    tb_begin("energy_parts_declared_in_unit_descriptions");
    static const char *const modules[] = {"trv", "ist", "sched", "fifo", "cache", "arbiter", "fixed_mem",
                                          "dram_adapter", "dram"};
    for (int k = 0; k < energy_part_kind_count; k++) {
        const ks_module_desc *d = accel_module_desc(energy_part_kinds[k].module);
        TB_CHECK(d && ks_module_desc_find(d, KS_DESC_PART, energy_part_kinds[k].decl), "%s.%s not declared",
                 energy_part_kinds[k].module, energy_part_kinds[k].decl);
    }
    int declared = 0;
    for (size_t i = 0; i < sizeof modules / sizeof modules[0]; i++) {
        const ks_module_desc *d = accel_module_desc(modules[i]);
        TB_CHECK(d != NULL, "no description of %s", modules[i]);
        if (!d)
            continue;
        char err[TB_ERR_MAX];
        TB_CHECK(ks_module_desc_check(d, err, sizeof err) == 0, "%s", err);
        for (const ks_desc_item *it = d->items; it->kind != KS_DESC_END; it++) {
            if (it->kind != KS_DESC_PART)
                continue;
            declared++;
            bool known = false;
            for (int k = 0; k < energy_part_kind_count; k++)
                known |= !strcmp(energy_part_kinds[k].module, d->name) && !strcmp(energy_part_kinds[k].decl, it->name);
            TB_CHECK(known, "%s declares part %s that the energy model does not build", d->name, it->name);
        }
    }
    TB_EQ_INT(declared, energy_part_kind_count);
    tb_end();
}

int main(void)
{
    const char *base = getenv("RTSIM_TMP");
    tb_pathf(tmpdir, sizeof tmpdir, "%s/tb_energy", base && *base ? base : "/tmp");
    if (tb_system_args("mkdir -p \"$TB_ARG1\"", tmpdir, NULL) != 0)
        return 2;
    test_load_and_exact();
    test_scaling();
    test_no_figure();
    test_load_errors();
    test_arithmetic();
    test_project_tables();
    test_node_word();
    test_parts_declared();
    return tb_finish();
}
