/* tb_kernel_vcd — the VCD writer: exact text for a small scenario (scopes,
 * bit/integer/enumerated values, FIFO occupancy and signal traced
 * automatically, change-only with glitches removed, $timescale), a time
 * window, a name filter, bad arguments, and a real VCD consumer (vcd2fst
 * from GTKWave) reading the files; skipped when vcd2fst is not installed. */
#include <stdlib.h>
#include <string.h>

#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/signal.h"
#include "kernel/sim.h"
#include "kernel/vcd.h"
#include "testbench/tb.h"

static const char *const states[] = {"IDLE", "BUSY", "DONE"};

typedef struct scen {
    ks_vcd_var *valid, *count, *state;
    ks_fifo *q;
    ks_signal *sig;
} scen;

static int scen_step(void *u, uint64_t cycle)
{
    scen *s = u;
    uint32_t item = 9;
    switch (cycle) {
    case 0:
        ks_vcd_set(s->valid, 1);
        ks_vcd_set(s->count, 3);
        ks_vcd_set(s->state, 1);
        ks_fifo_write(s->q, &item);
        ks_signal_write(s->sig, 5);
        return 1;
    case 1:
        ks_vcd_set(s->count, 3);  /* no change */
        ks_vcd_set(s->state, 0);  /* glitch: back to BUSY in the same time */
        ks_vcd_set(s->state, 1);
        ks_vcd_set(s->valid, 0);
        ks_fifo_read(s->q, &item);
        return 1;
    case 2:
        ks_vcd_set(s->count, 200);
        return 1;
    case 3:
        ks_vcd_set(s->state, 2);
        ks_vcd_set(s->valid, 1);
        return 1;
    default:
        return 0;
    }
}


static void tmp_path(char *buf, size_t cap, const char *name)
{
    const char *dir = getenv("RTSIM_TMP");
    tb_pathf(buf, cap, "%s/%s", dir && *dir ? dir : "/tmp", name);
}

static int run_scenario(const char *path, ks_time wb, ks_time we, const char *filter,
                        unsigned *nvars)
{
    ks_sim *sim = ks_sim_create();
    ks_vcd *vcd = ks_vcd_open(sim, path, "1ns", wb, we, filter);
    if (!vcd) {
        ks_sim_destroy(sim);
        return -1;
    }
    ks_clock *clk = ks_clock_create(sim, "clk", 0);
    scen s;
    s.valid = ks_vcd_var_bit(vcd, "top.unit.valid", 0);
    s.count = ks_vcd_var_int(vcd, "top.unit.count", 8, 0);
    s.state = ks_vcd_var_enum(vcd, "top.unit.state", states, 3, 0);
    s.q = ks_fifo_create(sim, "top.q", sizeof(uint32_t), 4, 1, clk);
    s.sig = ks_signal_create(sim, "top.sig", 4, 0);
    ks_clocked_create(clk, "top.unit", scen_step, &s);
    ks_sim_run(sim, KS_TIME_MAX);
    /* declarations after the first value are refused */
    TB_CHECK(ks_vcd_var_bit(vcd, "top.late", 0) == NULL, "late declaration accepted");
    *nvars = ks_vcd_var_count(vcd);
    int rc = ks_vcd_close(vcd);
    ks_sim_destroy(sim);
    return rc;
}

static const char *header_full =
    "$version rtsim kernel VCD writer $end\n"
    "$timescale 1ns $end\n"
    "$scope module top $end\n"
    "$var reg 4 % sig $end\n"
    "$scope module q $end\n"
    "$var reg 32 $ occupancy $end\n"
    "$upscope $end\n"
    "$scope module unit $end\n"
    "$var wire 1 ! valid $end\n"
    "$var reg 8 \" count $end\n"
    "$var string 1 # state $end\n"
    "$upscope $end\n"
    "$upscope $end\n"
    "$enddefinitions $end\n";

static int have_vcd2fst(void) { return system("command -v vcd2fst >/dev/null 2>&1") == 0; }

/* vcd2fst must accept the file and fst2vcd must give back our variables. */
static void check_with_gtkwave(const char *vcd, const char *must_contain)
{
    char fst[TB_PATH_MAX], back[TB_PATH_MAX];
    tb_pathf(fst, sizeof fst, "%s.fst", vcd);
    tb_pathf(back, sizeof back, "%s.back.vcd", vcd);
    TB_CHECK(tb_system_args("vcd2fst \"$TB_ARG1\" \"$TB_ARG2\" >/dev/null 2>&1", vcd, fst) == 0, "vcd2fst failed on %s",
             vcd);
    TB_CHECK(tb_system_args("fst2vcd \"$TB_ARG1\" >\"$TB_ARG2\" 2>/dev/null", fst, back) == 0, "fst2vcd failed on %s",
             fst);
    char *t = tb_read_file(back, NULL);
    TB_CHECK(t && strstr(t, must_contain), "round trip through FST lost '%s'", must_contain);
    free(t);
    remove(fst);
    remove(back);
}

int main(void)
{
    char path[TB_PATH_MAX];
    unsigned nvars = 0;

    tb_begin("vcd_text_of_a_small_scenario");
    tmp_path(path, sizeof path, "kernel_full.vcd");
    TB_EQ_INT(run_scenario(path, 0, KS_TIME_MAX, NULL, &nvars), 0);
    TB_EQ_INT(nvars, 5);
    char *txt = tb_read_file(path, NULL);
    char expect[4096];
    snprintf(expect, sizeof expect, "%s%s", header_full,
             "#0\n$dumpvars\n1!\nb11 \"\nsBUSY #\nb1 $\nb101 %\n$end\n"
             "#2\n0!\nb0 $\n"
             "#4\nb11001000 \"\n"
             "#6\nsDONE #\n1!\n"
             "#8\n");
    TB_CHECK(txt && !strcmp(txt, expect), "VCD text differs; got:\n%s", txt ? txt : "(no file)");
    if (txt && strcmp(txt, expect))
        fprintf(stderr, "expected:\n%s", expect);
    free(txt);
    /* written under a temporary name and renamed */
    char tmp[TB_PATH_MAX];
    tb_pathf(tmp, sizeof tmp, "%s.tmp", path);
    TB_CHECK(tb_read_file(tmp, NULL) == NULL, "temporary file left behind");
    tb_end();

    if (have_vcd2fst()) {
        tb_begin("vcd_opened_by_gtkwave_vcd2fst");
        check_with_gtkwave(path, "count");
        tb_end();
    } else {
        tb_skip("vcd_opened_by_gtkwave_vcd2fst", "vcd2fst not installed (Debian package gtkwave)");
    }

    tb_begin("vcd_time_window");
    tmp_path(path, sizeof path, "kernel_window.vcd");
    TB_EQ_INT(run_scenario(path, KS_NS(4), KS_NS(7), NULL, &nvars), 0);
    txt = tb_read_file(path, NULL);
    snprintf(expect, sizeof expect, "%s%s", header_full,
             "#4\n$dumpvars\n0!\nb11001000 \"\nsBUSY #\nb0 $\nb101 %\n$end\n"
             "#6\nsDONE #\n1!\n"
             "#7\n");
    TB_CHECK(txt && !strcmp(txt, expect), "windowed VCD differs; got:\n%s", txt ? txt : "(no file)");
    free(txt);
    tb_end();

    tb_begin("vcd_name_filter");
    tmp_path(path, sizeof path, "kernel_filter.vcd");
    TB_EQ_INT(run_scenario(path, 0, KS_TIME_MAX, "top.unit.c*, *.occupancy", &nvars), 0);
    TB_EQ_INT(nvars, 2);
    txt = tb_read_file(path, NULL);
    TB_CHECK(txt && strstr(txt, " count $end") && strstr(txt, " occupancy $end"), "kept vars missing");
    TB_CHECK(txt && !strstr(txt, "valid") && !strstr(txt, "state") && !strstr(txt, " sig "),
             "filtered vars present:\n%s", txt ? txt : "");
    TB_CHECK(txt && strstr(txt, "#4\nb11001000 !\n"), "count changes missing:\n%s", txt ? txt : "");
    free(txt);
    tb_end();
    if (have_vcd2fst()) {
        tb_begin("vcd_filtered_opened_by_gtkwave_vcd2fst");
        check_with_gtkwave(path, "occupancy");
        tb_end();
    }

    tb_begin("vcd_bad_arguments");
    ks_sim *sim = ks_sim_create();
    tmp_path(path, sizeof path, "kernel_bad.vcd");
    TB_CHECK(!ks_vcd_open(sim, path, "3ns", 0, KS_TIME_MAX, NULL), "timescale 3ns accepted");
    TB_CHECK(strstr(ks_sim_error(sim), "timescale"), "error: %s", ks_sim_error(sim));
    TB_CHECK(!ks_vcd_open(sim, path, "1fs", 0, KS_TIME_MAX, NULL), "timescale 1fs accepted");
    TB_CHECK(!ks_vcd_open(sim, path, "1ps", 10, 5, NULL), "empty window accepted");
    TB_CHECK(!ks_vcd_open(sim, "/nonexistent-dir/x.vcd", "1ps", 0, KS_TIME_MAX, NULL),
             "unwritable path accepted");
    TB_CHECK(strstr(ks_sim_error(sim), "/nonexistent-dir/x.vcd"), "error: %s", ks_sim_error(sim));
    ks_vcd *v = ks_vcd_open(sim, path, "10ps", 0, KS_TIME_MAX, NULL);
    TB_CHECK(v != NULL, "valid open failed: %s", ks_sim_error(sim));
    TB_CHECK(!ks_vcd_var_int(v, "x", 65, 0), "65-bit integer accepted");
    TB_CHECK(!ks_vcd_var_bit(v, "has space", 0), "name with a space accepted");
    TB_CHECK(ks_vcd_open(sim, path, "1ps", 0, KS_TIME_MAX, NULL) == NULL, "second writer accepted");
    ks_sim_destroy(sim); /* closes the writer */
    txt = tb_read_file(path, NULL);
    TB_CHECK(txt && strstr(txt, "$timescale 10ps $end") && strstr(txt, "$enddefinitions"),
             "writer not closed by ks_sim_destroy");
    free(txt);
    tb_end();
    return tb_finish();
}
