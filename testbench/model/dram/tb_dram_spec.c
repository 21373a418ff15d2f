/* tb_dram_spec — the standard as data: parameter file loading, overrides and their
 * error messages, the address mapping, and the DRAMPower-method energy against
 * the figures of ../shared/ref/dram/drampower_lpddr3_1600_idd.txt (per-command
 * energies) and one row of drampower_results.csv (a_seq, channel 0), copied here
 * as expected values. */
#include "testbench/tb.h"

#include <math.h>
#include <unistd.h>

#include "model/dram/dram_addrmap.h"
#include "model/dram/dram_energy.h"
#include "model/dram/dram_timing.h"

static const char *CFG = "model/data/lpddr3_1600.ini";

static int load_with(const char *const *sets, int n, char *err, size_t errlen)
{
    static dram_spec s;
    return dram_spec_load(&s, CFG, sets, n, err, errlen);
}

static void expect_error(const char *name, const char *set, const char *want1, const char *want2)
{
    tb_begin(name);
    char err[TB_ERR_MAX];
    int rc = load_with(&set, 1, err, sizeof err);
    TB_CHECK(rc != 0, "--set %s accepted", set);
    TB_CHECK(strstr(err, want1) != NULL, "message '%s' lacks '%s'", err, want1);
    TB_CHECK(want2 == NULL || strstr(err, want2) != NULL, "message '%s' lacks '%s'", err, want2);
    tb_end();
}

/* Writes text to a temporary file; returns its path (static buffer). */
static const char *temp_file(const char *text)
{
    static char path[TB_PATH_MAX];
    const char *dir = getenv("RTSIM_TMP") ? getenv("RTSIM_TMP") : "/tmp";
    tb_pathf(path, sizeof path, "%s/tb_dram_spec_XXXXXX", dir);
    int fd = mkstemp(path);
    if (fd < 0)
        return NULL;
    FILE *f = fdopen(fd, "w");
    fputs(text, f);
    fclose(f);
    return path;
}

static void expect_file_error(const char *name, const char *text, const char *want1, const char *want2)
{
    tb_begin(name);
    const char *p = temp_file(text);
    TB_CHECK(p != NULL, "cannot create a temporary file");
    if (p) {
        dram_spec s;
        char err[TB_ERR_MAX];
        TB_CHECK(dram_spec_load(&s, p, NULL, 0, err, sizeof err) != 0, "accepted");
        TB_CHECK(strstr(err, want1) != NULL, "message '%s' lacks '%s'", err, want1);
        TB_CHECK(want2 == NULL || strstr(err, want2) != NULL, "message '%s' lacks '%s'", err, want2);
        unlink(p);
    }
    tb_end();
}

static const char *MINI_HEAD =
    "[organization]\nchannels = 2\nranks = 1\nbanks = 8\nrows = 16384\ncolumns = 1024\ndq_bits = 32\nprefetch = 8\n"
    "tck_ps = 1250\n[timing]\nnCL = 12\n";
static const char *MINI_TAIL =
    "[controller]\nread_queue = 32\nwrite_queue = 32\nrow_hit_cap = 16\nwrite_high_pct = 80\nwrite_low_pct = 20\n"
    "read_latency = nCL + 6\nrefresh_interval = 3120\nmax_postponed_refresh = 8\nmapping = RoBaRaCoCh\n";

static char *mini(const char *middle)
{
    static char buf[2048];
    snprintf(buf, sizeof buf, "%s%s%s", MINI_HEAD, middle, MINI_TAIL);
    return buf;
}

int main(void)
{
    dram_spec spec;
    char err[TB_ERR_MAX];
    tb_begin("dram_spec_default_values");
    if (TB_CHECK(dram_spec_load(&spec, CFG, NULL, 0, err, sizeof err) == 0, "%s", err)) {
        TB_EQ_INT(spec.channels, 2);
        TB_EQ_INT(spec.tx_bytes, 32);
        TB_EQ_INT(spec.read_latency, 18);
        TB_EQ_INT(spec.refresh_interval, 3120);
        TB_EQ_INT(dram_spec_param(&spec, "nRFCab"), 104);
        /* derived constraint rows evaluate to lpddr3_1600_timing.txt:34-37 */
        int rd_wr = -1, wr_rd = -1, wr_pre = -1, faw = -1;
        for (int i = 0; i < spec.nconstraints; i++) {
            const dram_constraint *c = &spec.constraint[i];
            if (c->scope == DRAM_SCOPE_RANK && c->from == DRAM_RD && c->to == DRAM_WR)
                rd_wr = c->cycles;
            if (c->scope == DRAM_SCOPE_RANK && c->from == DRAM_WR && c->to == DRAM_RD)
                wr_rd = c->cycles;
            if (c->scope == DRAM_SCOPE_BANK && c->from == DRAM_WR && c->to == DRAM_PRE)
                wr_pre = c->cycles;
            if (c->window == 4)
                faw = c->cycles;
        }
        TB_EQ_INT(rd_wr, 13);
        TB_EQ_INT(wr_rd, 17);
        TB_EQ_INT(wr_pre, 22);
        TB_EQ_INT(faw, 40);
    }
    tb_end();

    tb_begin("dram_spec_override_propagates");
    {
        const char *sets[] = {"timing.nCL=14"};
        TB_CHECK(dram_spec_load(&spec, CFG, sets, 1, err, sizeof err) == 0, "%s", err);
        TB_EQ_INT(spec.read_latency, 20); /* nCL + nDQSCK + nBL */
        int rd_wr = -1;
        for (int i = 0; i < spec.nconstraints; i++)
            if (spec.constraint[i].scope == DRAM_SCOPE_RANK && spec.constraint[i].from == DRAM_RD &&
                spec.constraint[i].to == DRAM_WR)
                rd_wr = spec.constraint[i].cycles;
        TB_EQ_INT(rd_wr, 15);
    }
    tb_end();

    expect_error("dram_spec_unknown_set_key", "timing.nFOO=3", "unknown key 'timing.nFOO'", "nCL");
    expect_error("dram_spec_unknown_set_section", "bogus.x=3", "unknown key 'bogus.x'", NULL);
    expect_error("dram_spec_set_out_of_range", "controller.read_queue=0", "read_queue", "allowed 1..4096");
    expect_error("dram_spec_set_channels_range", "organization.channels=99", "channels", "allowed 1..16");
    expect_error("dram_spec_set_bad_expression", "timing.nCL=12+", "nCL", "expected a number");
    expect_error("dram_spec_set_negative_timing", "timing.nRCD=-3", "nRCD", "allowed 1..");
    /* JEDEC latencies are at least one clock (nCL=0, nBL=0 were once accepted) */
    expect_error("dram_spec_set_zero_cl", "timing.nCL=0", "nCL", "allowed 1..");
    expect_error("dram_spec_set_zero_bl", "timing.nBL=0", "nBL", "allowed 1..");
    expect_error("dram_spec_set_no_equals", "timing.nCL", "expected section.key=value", NULL);
    expect_error("dram_spec_set_non_pow2_banks", "organization.banks=6", "powers of two", NULL);
    expect_error("dram_spec_set_bad_mapping", "controller.mapping=RoBaCoCh", "mapping", NULL);
    /* longer than the spec's 32-byte fields: cut when copied, rejected all the same */
    expect_error("dram_spec_set_overlong_mapping", "controller.mapping=RoBaRaCoChRoBaRaCoChRoBaRaCoChRoBaRaCoCh",
                 "mapping", "invalid");

    expect_file_error("dram_spec_file_syntax_error", mini("this line is not ini\n"), ":12:", "syntax");
    expect_file_error("dram_spec_file_unknown_key", mini("[controller]\nbogus_key = 1\n"), ":13:", "bogus_key");
    /* the shared INI reader (config/ini_file.h) refuses a key given twice */
    expect_file_error("dram_spec_file_key_twice", mini("[timing]\nnCL = 14\n"), ":13: timing.nCL given twice",
                      "(first at line 11)");
    expect_file_error("dram_spec_file_bad_constraint", mini("[constraints]\nrank RD => WR = 13\n"), ":13:",
                      "expected '<scope> <FROM> -> <TO>");
    expect_file_error("dram_spec_file_unknown_command", mini("[constraints]\nrank RD -> XX = 13\n"), ":13:",
                      "unknown command 'XX'");
    expect_file_error("dram_spec_file_bank_window", mini("[constraints]\nbank ACT -> ACT window 2 = 9\n"), ":13:",
                      "window > 1");
    expect_file_error("dram_spec_file_unknown_name", mini("[constraints]\nrank RD -> WR = nXYZ + 1\n"), ":13:",
                      "unknown name 'nXYZ'");
    expect_file_error("dram_spec_file_missing_key", MINI_HEAD, "missing key", "[controller]");
    /* sscanf's %d wrapped it (2^32 + 4 -> 4) */
    expect_file_error("dram_spec_file_window_beyond_int", mini("[constraints]\nrank ACT -> ACT window 4294967300 = 9\n"),
                      ":13:", "window 4294967300 out of range");
    expect_file_error("dram_spec_file_window_zero", mini("[constraints]\nrank ACT -> ACT window 0 = 9\n"), ":13:",
                      "allowed 1..");
    expect_file_error("dram_spec_file_window_not_number", mini("[constraints]\nrank ACT -> ACT window x4 = 9\n"),
                      ":13:", "only 'window N'");
    expect_file_error("dram_spec_file_overlong_name", mini("nABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 = 3\n"), ":12:",
                      "must be an identifier");

    tb_begin("dram_addrmap_robaracoch");
    if (TB_CHECK(dram_spec_load(&spec, CFG, NULL, 0, err, sizeof err) == 0, "%s", err)) {
        dram_addrmap m;
        TB_CHECK(dram_addrmap_init(&m, &spec, err, sizeof err) == 0, "%s", err);
        dram_addr a;
        /* lpddr3_1600_timing.txt:54: [5]=channel, [12:6]=column, [15:13]=bank, [29:16]=row */
        dram_addrmap_decode(&m, 0x20, &a);
        TB_CHECK(a.channel == 1 && a.column == 0 && a.bank == 0 && a.row == 0, "0x20 -> ch %u", a.channel);
        dram_addrmap_decode(&m, 0x40, &a);
        TB_CHECK(a.channel == 0 && a.column == 1, "0x40 -> col %u", a.column);
        dram_addrmap_decode(&m, 0x2000, &a);
        TB_CHECK(a.bank == 1 && a.column == 0, "0x2000 -> bank %u", a.bank);
        dram_addrmap_decode(&m, 0x10000, &a);
        TB_CHECK(a.row == 1 && a.bank == 0, "0x10000 -> row %u", a.row);
        dram_addrmap_decode(&m, 0x3fffffe0, &a);
        TB_CHECK(a.channel == 1 && a.column == 127 && a.bank == 7 && a.row == 16383, "top address");
        for (uint64_t x = 0; x < (1u << 30); x += 0x1234560)
            dram_addrmap_decode(&m, x & ~31ull, &a), TB_CHECK(dram_addrmap_encode(&m, &a) == (x & ~31ull),
                                                              "roundtrip 0x%llx", (unsigned long long)x);
    }
    tb_end();

    tb_begin("dram_addrmap_other_order");
    {
        const char *sets[] = {"controller.mapping=ChRaBaRoCo"};
        if (TB_CHECK(dram_spec_load(&spec, CFG, sets, 1, err, sizeof err) == 0, "%s", err)) {
            dram_addrmap m;
            dram_addrmap_init(&m, &spec, err, sizeof err);
            dram_addr a;
            dram_addrmap_decode(&m, 0x20, &a);
            TB_CHECK(a.column == 1 && a.channel == 0, "Co lowest: 0x20 -> col %u ch %u", a.column, a.channel);
            dram_addrmap_decode(&m, 1ull << 29, &a);
            TB_CHECK(a.channel == 1, "Ch highest: bit 29 -> ch %u", a.channel);
        }
    }
    tb_end();

    tb_begin("dram_energy_per_command");
    dram_power_spec p;
    if (TB_CHECK(dram_power_spec_load(&p, "model/data/lpddr3_1600_idd.ini", err, sizeof err) == 0, "%s", err)) {
        /* drampower_lpddr3_1600_idd.txt:18-23 */
        TB_CHECK(fabs(dram_energy_per_act(&p) - 2943.0) < 1e-6, "E_ACT %f", dram_energy_per_act(&p));
        TB_CHECK(fabs(dram_energy_per_pre(&p) - 1107.0) < 1e-6, "E_PRE %f", dram_energy_per_pre(&p));
        TB_CHECK(fabs(dram_energy_per_rd(&p) - 1317.0) < 1e-6, "E_RD %f", dram_energy_per_rd(&p));
        TB_CHECK(fabs(dram_energy_per_wr(&p) - 1506.0) < 1e-6, "E_WR %f", dram_energy_per_wr(&p));
        TB_CHECK(fabs(dram_energy_per_ref(&p) - 26832.0) < 1e-6, "E_REF %f", dram_energy_per_ref(&p));
    }
    tb_end();

    tb_begin("dram_energy_drampower_row_a_seq_ch0");
    {
        /* drampower_results.csv, A_x32_2ch_il32,a_seq,channel 0: n_ACT 9319, n_RD 1e6, n_PRE_banks 9313,
         * n_REF 1341, act_cycles 4146218, pre_cycles 42913, E_total 1691883865.5 pJ. Our input is the
         * cycles with an open bank; DRAMPower adds tRFC - tRP = 89 active cycles per REF. */
        dram_energy_in in = {9319, 9313, 1000000, 0, 1341, 4146218 - 1341 * 89, 4146218 + 42913};
        dram_energy e;
        dram_energy_compute(&p, &in, &e);
        TB_EQ_INT(e.act_cycles, 4146218);
        TB_EQ_INT(e.pre_cycles, 42913);
        TB_CHECK(fabs(e.total_pJ - 1691883865.5) < 1.0, "E_total %.1f, DRAMPower 1691883865.5", e.total_pJ);
        TB_CHECK(fabs(e.act_stby_pJ - 298527696.0) < 1.0, "E_act_stdby %.1f", e.act_stby_pJ);
    }
    tb_end();

    tb_begin("dram_power_spec_bad_value");
    {
        const char *path = temp_file("[memspec]\nclk_mhz = 800\nvdd1 = abc\n");
        dram_power_spec q;
        TB_CHECK(path && dram_power_spec_load(&q, path, err, sizeof err) != 0, "accepted");
        TB_CHECK(strstr(err, ":3:") && strstr(err, "vdd1") && strstr(err, "allowed"), "message '%s'", err);
        if (path)
            unlink(path);
    }
    tb_end();

    tb_begin("dram_power_spec_unknown_key_lists_allowed");
    {
        const char *path = temp_file("[memspec]\nclk_mhz = 800\nvdd3 = 1.8\n");
        dram_power_spec q;
        TB_CHECK(path && dram_power_spec_load(&q, path, err, sizeof err) != 0, "accepted");
        TB_CHECK(strstr(err, ":3: unknown key 'vdd3' in [memspec] (allowed clk_mhz, vdd1, vdd2, "), "message '%s'", err);
        if (path)
            unlink(path);
    }
    tb_end();

    /* NaN is not below nor above any range: it used to pass the range check
     * (found by cppcheck; energy then printed "nan uJ") */
    tb_begin("dram_power_spec_rejects_nan");
    {
        static const char *const texts[] = {"[memspec]\nclk_mhz = 800\nvdd1 = nan\n",
                                            "[memspec]\nclk_mhz = 800\nidd0 = -NaN\n",
                                            "[memspec]\nclk_mhz = 800\nnRAS = nan\n"};
        static const char *const keys[] = {"vdd1", "idd0", "nRAS"};
        for (int i = 0; i < 3; i++) {
            const char *path = temp_file(texts[i]);
            dram_power_spec q;
            TB_CHECK(path && dram_power_spec_load(&q, path, err, sizeof err) != 0, "%s accepted", keys[i]);
            TB_CHECK(strstr(err, ":3:") && strstr(err, keys[i]) && strstr(err, "allowed"), "message '%s'", err);
            if (path)
                unlink(path);
        }
    }
    tb_end();

    tb_begin("dram_spec_missing_file");
    TB_CHECK(dram_spec_load(&spec, "no/such/file.ini", NULL, 0, err, sizeof err) != 0, "accepted");
    TB_CHECK(strstr(err, "no/such/file.ini") != NULL, "message '%s'", err);
    tb_end();
    return tb_finish();
}
