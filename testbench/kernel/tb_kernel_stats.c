/* tb_kernel_stats — the statistics registry (counters, reals, histograms,
 * formulas; JSON parsed back by python3, CSV, summary) and module
 * description tables (printing, lookup, validation). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kernel/module_desc.h"
#include "kernel/stats.h"
#include "testbench/tb.h"

static double hit_rate(const ks_stats *reg, void *user)
{
    (void)user;
    double h = 0, a = 0;
    ks_stats_value(reg, "l1.hits", &h);
    ks_stats_value(reg, "l1.accesses", &a);
    return a ? h / a : 0;
}


static ks_stats *make_registry(uint64_t *owned)
{
    ks_stats *r = ks_stats_create();
    uint64_t *acc = ks_stat_counter(r, "l1.accesses", "accesses", "node L1 accesses");
    uint64_t *hits = ks_stat_counter(r, "l1.hits", "accesses", "node L1 hits");
    *acc = 1000;
    *hits = 750;
    ks_stat_counter_ref(r, "trv0.node_visits", "visits", "nodes visited by TRV 0", owned);
    double *e = ks_stat_real(r, "energy", "mJ", "energy \"per\" frame");
    *e = 0.1;
    ks_histogram *h = ks_stat_histogram(r, "mem.latency", "cycles", "DRAM read latency", 0, 100, 4);
    ks_histogram_add(h, 10);
    ks_histogram_add(h, 30);
    ks_histogram_add(h, 30);
    ks_histogram_add(h, 99.5);
    ks_histogram_add(h, 250); /* overflow */
    ks_histogram_add(h, -1);  /* underflow */
    ks_stat_formula(r, "l1.hit_rate", "", "hits per access", hit_rate, NULL);
    ks_stat_ratio(r, "trv0.visits_per_access", "visits/access", "visits per L1 access",
                  "trv0.node_visits", "l1.accesses");
    return r;
}

static void test_registry(void)
{
    tb_begin("stats_values_and_formulas");
    uint64_t owned = 500;
    ks_stats *r = make_registry(&owned);
    TB_EQ_INT(ks_stats_count(r), 7);
    double v = -1;
    TB_EQ_INT(ks_stats_value(r, "l1.hit_rate", &v), 0);
    TB_CHECK(v == 0.75, "hit rate %g", v);
    owned = 250;
    ks_stats_value(r, "trv0.visits_per_access", &v);
    TB_CHECK(v == 0.25, "ratio %g (must follow the referenced storage)", v);
    ks_stats_value(r, "mem.latency", &v);
    TB_CHECK(fabs(v - (10 + 30 + 30 + 99.5 + 250 - 1) / 6.0) < 1e-12, "histogram mean %g", v);
    TB_EQ_INT(ks_stats_value(r, "nope", &v), -1);
    /* duplicates: counters hand back the same storage, others are refused */
    uint64_t *again = ks_stat_counter(r, "l1.hits", "accesses", "node L1 hits");
    TB_CHECK(again && *again == 750, "duplicate counter lost its storage");
    TB_CHECK(ks_stat_histogram(r, "mem.latency", "cycles", "x", 0, 1, 1) == NULL, "duplicate histogram");
    TB_CHECK(strstr(ks_stats_error(r), "mem.latency"), "error: %s", ks_stats_error(r));
    TB_CHECK(ks_stat_histogram(r, "bad.h", "cycles", "x", 5, 5, 4) == NULL, "empty range accepted");
    TB_CHECK(ks_stat_counter(r, "bad,name", "x", "y") == NULL, "comma in name accepted");
    TB_EQ_INT(ks_stats_count(r), 7);
    ks_stats_destroy(r);
    tb_end();
}

static int have_python(void) { return system("command -v python3 >/dev/null 2>&1") == 0; }

static void test_outputs(void)
{
    const char *dir = getenv("RTSIM_TMP");
    char json[TB_PATH_MAX], csv[TB_PATH_MAX];
    tb_pathf(json, sizeof json, "%s/kernel_stats.json", dir && *dir ? dir : "/tmp");
    tb_pathf(csv, sizeof csv, "%s/kernel_stats.csv", dir && *dir ? dir : "/tmp");
    uint64_t owned = 500;
    ks_stats *r = make_registry(&owned);

    tb_begin("stats_json_parses_back");
    FILE *f = fopen(json, "w");
    TB_EQ_INT(ks_stats_write_json(r, f), 0);
    fclose(f);
    if (have_python()) {
        TB_CHECK(tb_system_args("python3 -c 'import json,sys; d=json.load(open(sys.argv[1]));"
                 "assert d[\"l1.accesses\"]==1000 and d[\"l1.hits\"]==750;"
                 "assert d[\"trv0.node_visits\"]==500 and d[\"energy\"]==0.1;"
                 "assert d[\"l1.hit_rate\"]==0.75 and d[\"trv0.visits_per_access\"]==0.5;"
                 "h=d[\"mem.latency\"]; assert h[\"count\"]==6 and h[\"bins\"]==[1,2,0,1];"
                 "assert h[\"underflow\"]==1 and h[\"overflow\"]==1 and h[\"max\"]==250;"
                 "assert d[\"_units\"][\"energy\"]==\"mJ\";"
                 "assert d[\"_descriptions\"][\"energy\"]==\"energy \\\"per\\\" frame\"' \"$TB_ARG1\"",
                 json, NULL) == 0, "python3 rejected or misread %s", json);
    } else {
        char *t = tb_read_file(json, NULL);
        TB_CHECK(t && strstr(t, "\"l1.accesses\": 1000,"), "JSON lacks a counter");
        free(t);
    }
    tb_end();

    tb_begin("stats_csv_and_summary");
    f = fopen(csv, "w");
    TB_EQ_INT(ks_stats_write_csv(r, f), 0);
    fclose(f);
    char *t = tb_read_file(csv, NULL);
    TB_CHECK(t && !strncmp(t, "name,value,unit,description\nl1.accesses,1000,accesses,node L1 accesses\n", 70),
             "CSV start:\n%s", t ? t : "");
    TB_CHECK(t && strstr(t, "\nenergy,0.1,mJ,\"energy \"\"per\"\" frame\"\n"), "CSV quoting:\n%s", t ? t : "");
    TB_CHECK(t && strstr(t, "\nl1.hit_rate,0.75,,hits per access\n"), "CSV formula:\n%s", t ? t : "");
    free(t);
    f = fopen(csv, "w");
    TB_EQ_INT(ks_stats_write_summary(r, f), 0);
    fclose(f);
    t = tb_read_file(csv, NULL);
    TB_CHECK(t && strstr(t, "trv0.node_visits") && strstr(t, "n=6 mean=") && strstr(t, "nodes visited by TRV 0"),
             "summary:\n%s", t ? t : "");
    free(t);
    remove(csv);
    remove(json);
    tb_end();
    ks_stats_destroy(r);
}

static const ks_desc_item trv_items[] = {
    {KS_DESC_PARAM, "ray_slots", "int", "32", "1..1024", "rays in flight per TRV"},
    {KS_DESC_PARAM, "stack_depth", "int", "64", "power of two", "entries of the full traversal stack"},
    {KS_DESC_PORT, "node_req", "out fifo<node_req>", "", "", "requests to the node L1"},
    {KS_DESC_STAT, "node_visits", "visits", "", "", "nodes visited"},
    {KS_DESC_END, 0, 0, 0, 0, 0}};
static const ks_module_desc trv_desc = {"trv", "BVH traversal unit", trv_items, NULL};

static const ks_desc_item bad_items[] = {
    {KS_DESC_PARAM, "a", "int", "1", "", "first"},
    {KS_DESC_PARAM, "a", "int", "1", "", "again"},
    {KS_DESC_END, 0, 0, 0, 0, 0}};
static const ks_desc_item nodef_items[] = {
    {KS_DESC_PARAM, "b", "int", "", "", "no default"},
    {KS_DESC_END, 0, 0, 0, 0, 0}};

static void test_module_desc(void)
{
    tb_begin("module_description_table");
    char err[TB_ERR_MAX] = "";
    TB_EQ_INT(ks_module_desc_check(&trv_desc, err, sizeof err), 0);
    TB_EQ_INT(ks_module_desc_count(&trv_desc, KS_DESC_PARAM), 2);
    TB_EQ_INT(ks_module_desc_count(&trv_desc, KS_DESC_STAT), 1);
    const ks_desc_item *it = ks_module_desc_find(&trv_desc, KS_DESC_PARAM, "stack_depth");
    TB_CHECK(it && !strcmp(it->def, "64"), "find");
    TB_CHECK(!ks_module_desc_find(&trv_desc, KS_DESC_STAT, "stack_depth"), "kind ignored by find");
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    ks_module_desc_print(&trv_desc, m);
    fclose(m);
    TB_CHECK(strstr(buf, "trv — BVH traversal unit\n"), "title:\n%s", buf);
    TB_CHECK(strstr(buf, "    ray_slots    int   rays in flight per TRV (default 32; range 1..1024)\n"),
             "param line:\n%s", buf);
    TB_CHECK(strstr(buf, "  Ports:\n    node_req  out fifo<node_req>  requests to the node L1\n"), "ports:\n%s", buf);
    TB_CHECK(strstr(buf, "  Statistics (name, unit, meaning):\n    node_visits  visits  nodes visited\n"),
             "stats:\n%s", buf);
    free(buf);
    ks_module_desc bad = {"bad", "broken", bad_items, NULL};
    TB_EQ_INT(ks_module_desc_check(&bad, err, sizeof err), -1);
    TB_CHECK(strstr(err, "bad: a declared twice"), "err: %s", err);
    ks_module_desc nodef = {"nd", "broken", nodef_items, NULL};
    TB_EQ_INT(ks_module_desc_check(&nodef, err, sizeof err), -1);
    TB_CHECK(strstr(err, "parameter b has no default"), "err: %s", err);
    tb_end();
}

/* Declared registration: the unit and text come from the description, an
 * undeclared name is refused, wildcards match and fill per-instance text. */
static void test_declared(void)
{
    static const ks_desc_item items[] = {
        {KS_DESC_STAT, "hits", "accesses", "", "", "accesses that hit"},
        {KS_DESC_STAT, "grants_#", "requests", "", "", "requests granted to input #"},
        {KS_DESC_STAT, "energy.*_dynamic_mj", "mJ", "", "", "dynamic energy of the *"},
        {KS_DESC_STAT, "energy.*_mj", "mJ", "", "", "energy of the *"},
        {KS_DESC_STAT, "never", "things", "", "", "declared, never registered"},
        {KS_DESC_END, 0, 0, 0, 0, 0}};
    static const ks_module_desc m = {"unit", "a test unit", items, NULL};
    tb_begin("stats_declared_registration");
    ks_stats *r = ks_stats_create();
    uint64_t h = 3, g = 4;
    double e = 1.5, dyn = 0.5;
    TB_EQ_INT(ks_stat_decl_counter(r, &m, "u0", "hits", &h), 0);
    TB_EQ_INT(ks_stat_decl_counter(r, &m, "u0", "grants_12", &g), 0);
    TB_EQ_INT(ks_stat_decl_real(r, &m, NULL, "energy.trv_dynamic_mj", &dyn), 0);
    TB_EQ_INT(ks_stat_decl_real(r, &m, NULL, "energy.trv_mj", &e), 0);
    /* undeclared: refused with the module named, nothing registered */
    TB_EQ_INT(ks_stat_decl_counter(r, &m, "u0", "misses", &h), -1);
    TB_CHECK(strstr(ks_stats_error(r), "u0.misses") && strstr(ks_stats_error(r), "module unit"), "%s",
             ks_stats_error(r));
    TB_EQ_INT(ks_stat_decl_counter(r, &m, "u0", "grants_x", &g), -1);
    double v = 0;
    TB_EQ_INT(ks_stats_value(r, "u0.misses", &v), -1);
    TB_EQ_INT(ks_stats_value(r, "u0.grants_12", &v), 0);
    TB_CHECK(v == 4, "grants_12 = %g", v);
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    ks_stats_write_json(r, f);
    fclose(f);
    TB_CHECK(strstr(buf, "\"u0.hits\": \"accesses\"") && strstr(buf, "requests granted to input 12") &&
                 strstr(buf, "\"energy.trv_dynamic_mj\": \"dynamic energy of the trv\"") &&
                 strstr(buf, "\"energy.trv_mj\": \"energy of the trv\""),
             "%s", buf);
    free(buf);
    TB_CHECK(ks_stats_registered_from(r, &m, &items[0]) && ks_stats_registered_from(r, &m, &items[1]) &&
                 !ks_stats_registered_from(r, &m, &items[4]),
             "registered_from");
    ks_stats_destroy(r);
    tb_end();
}

int main(void)
{
    test_registry();
    test_outputs();
    test_module_desc();
    test_declared();
    return tb_finish();
}
