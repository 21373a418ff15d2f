/* rtdram — runs a DRAM request trace through the LPDDR3 controller model.
 *   rtdram TRACE [--config FILE] [--power FILE] [--set KEY=VALUE]... [--json]
 *                [--cmd-trace FILE] [--check] [--exhaustive] [--kernel] [--help] [--version]
 * Exit: 0 ok, 1 timing violations found by --check, 2 bad usage or input,
 * 130/143 interrupted (Ctrl-C/SIGTERM: the statistics so far, marked partial;
 * the command trace ends with a "# partial" line). The --cmd-trace path is
 * planned before the run through the output layer (kernel/out_file.h). */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli/output_path.h"
#include "model/dram/dram_checker.h"
#include "model/dram/dram_ctrl.h"
#include "model/dram/dram_energy.h"
#include "model/dram/dram_port_trace.h"
#include "model/dram/dram_report.h"
#include "model/dram/dram_timing.h"
#include "model/dram/dram_trace.h"

#ifndef RTSIM_DATA_DIR
#define RTSIM_DATA_DIR "model/data"
#endif
#include "cli/run_info.h"
#include "cli/version.h"

static void usage(FILE *o)
{
    fprintf(o,
            "usage: rtdram TRACE [options]\n"
            "Simulates a DRAM request trace ('0x<hex addr> R|W' per line) on the command-level\n"
            "LPDDR3 controller model with Ramulator's trace injection policy.\n"
            "  --config FILE     standard/controller parameter file (default %s/lpddr3_1600.ini,\n"
            "                    directory overridable with RTSIM_DATA_DIR)\n"
            "  --power FILE      currents/voltages for energy (default lpddr3_1600_idd.ini beside it)\n"
            "  --set KEY=VALUE   override a parameter, KEY = section.name (e.g. timing.nCL=14,\n"
            "                    controller.row_hit_cap=4, organization.channels=1); repeatable\n"
            "  --json            print one JSON object instead of the text summary\n"
            "  --cmd-trace FILE  write the command stream (cycle,channel,rank,bank,CMD,row)\n"
            "  --check           run the timing checker on the command stream (exit 1 on violation)\n"
            "  --exhaustive      run the scheduler every cycle, no idle skipping (slow reference mode)\n"
            "  --kernel          run the trace through the kernel module (request/response FIFOs,\n"
            "                    DRAM clock) instead of the direct loop: same results, slower\n"
            "  --help, --version\n",
            RTSIM_DATA_DIR);
}

typedef struct sink {
    FILE *f;
    dram_checker *checker;
} sink;

static void on_cmd(void *user, const dram_cmd_rec *r)
{
    sink *s = user;
    if (s->f) {
        char line[96];
        dram_cmd_format(r, line, sizeof line);
        fputs(line, s->f);
    }
    if (s->checker)
        dram_checker_feed(s->checker, r);
}

/* The summary JSON, one line, with the run object first (cli/run_info.h). */
static int json_with_run(const dram_summary *s, const cli_run_info *ri, FILE *out)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    if (!m)
        return -1;
    dram_summary_json(s, m);
    int rc = fclose(m);
    if (!rc)
        rc = cli_run_splice(out, ri, buf, len, true);
    free(buf);
    return rc;
}

int main(int argc, char **argv)
{
    static cli_run_info run;   /* provenance of the JSON (docs/results.md) */
    cli_run_init(&run, "rtdram", argc, argv);
    ks_interrupt_install("rtdram");
    static const struct option opts[] = {
        {"config", required_argument, 0, 'c'}, {"power", required_argument, 0, 'p'},
        {"set", required_argument, 0, 's'},    {"json", no_argument, 0, 'j'},
        {"cmd-trace", required_argument, 0, 't'}, {"check", no_argument, 0, 'k'},
        {"exhaustive", no_argument, 0, 'x'},   {"kernel", no_argument, 0, 'K'},
        {"help", no_argument, 0, 'h'},         {"version", no_argument, 0, 'v'},
        {0, 0, 0, 0}};
    const char *config = NULL, *power = NULL, *cmd_trace = NULL;
    const char **sets = calloc((size_t)argc, sizeof *sets);
    if (!sets) {
        fprintf(stderr, "rtdram: out of memory\n");
        return 1;
    }
    int nsets = 0, json = 0, check = 0, exhaustive = 0, kernel = 0, o;
    while ((o = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        switch (o) {
        case 'c': config = optarg; break;
        case 'p': power = optarg; break;
        case 's': sets[nsets++] = optarg; break;
        case 'j': json = 1; break;
        case 't': cmd_trace = optarg; break;
        case 'k': check = 1; break;
        case 'x': exhaustive = 1; break;
        case 'K': kernel = 1; break;
        case 'h': usage(stdout); free(sets); return 0;
        case 'v': printf("rtdram %s (git %s)\n", RTSIM_VERSION, RTSIM_GIT); free(sets); return 0;
        default: usage(stderr); free(sets); return 2;
        }
    }
    if (optind != argc - 1) {
        fprintf(stderr, "rtdram: expected exactly one TRACE argument\n");
        usage(stderr);
        free(sets);
        return 2;
    }
    const char *trace = argv[optind];
    char err[600];
    /* the output path first: a bad one fails before the run, not after it */
    cli_output outs[1] = {{"--cmd-trace", cmd_trace, NULL}};
    if (!cli_plan_outputs(outs, 1, err, sizeof err)) {
        fprintf(stderr, "rtdram: %s\n", err);
        free(sets);
        return 2;
    }
    const char *dir = getenv("RTSIM_DATA_DIR") ? getenv("RTSIM_DATA_DIR") : RTSIM_DATA_DIR;
    /* PATH_MAX (4096) and more: a cut default path would name another file */
    char cfg_buf[4200], pow_buf[4200];
    if (!config) {
        if (snprintf(cfg_buf, sizeof cfg_buf, "%s/lpddr3_1600.ini", dir) >= (int)sizeof cfg_buf) {
            fprintf(stderr, "rtdram: RTSIM_DATA_DIR %.64s...: path too long\n", dir);
            free(sets);
            return 2;
        }
        config = cfg_buf;
    }
    if (!power) {
        const char *slash = strrchr(config, '/');
        int n = slash ? (int)(slash - config) : 1;
        if (snprintf(pow_buf, sizeof pow_buf, "%.*s/lpddr3_1600_idd.ini", n, slash ? config : ".") >=
            (int)sizeof pow_buf) {
            fprintf(stderr, "rtdram: --config %.64s...: path too long\n", config);
            free(sets);
            return 2;
        }
        power = pow_buf;
    }
    static dram_spec spec;
    dram_power_spec pspec;
    if (dram_spec_load(&spec, config, sets, nsets, err, sizeof err) ||
        dram_power_spec_load(&pspec, power, err, sizeof err)) {
        fprintf(stderr, "rtdram: %s\n", err);
        free(sets);
        return 2;
    }
    run.machine = config;
    run.has_config_hash = cli_run_dram_hash(config, sets, nsets, power, &run.config_hash);
    free(sets);
    FILE *tf = fopen(trace, "r");
    if (!tf) {
        fprintf(stderr, "rtdram: %s: cannot open\n", trace);
        return 2;
    }
    dram_ctrl *c = kernel ? NULL : dram_ctrl_create(&spec, NULL, NULL, err, sizeof err);
    if (!kernel && !c) {
        fprintf(stderr, "rtdram: %s\n", err);
        fclose(tf);
        return 2;
    }
    if (c)
        dram_set_exhaustive(c, exhaustive);
    sink sk = {0};
    if (outs[0].out) {
        sk.f = ks_out_begin(outs[0].out, err, sizeof err);
        if (!sk.f) {
            fprintf(stderr, "rtdram: %s\n", err);
            fclose(tf);
            dram_ctrl_destroy(c);
            return 2;
        }
        fprintf(sk.f, "# cycle,channel,rank,bank,cmd,row  (rtdram %s, trace %s)\n", RTSIM_VERSION, trace);
    }
    if (check)
        sk.checker = dram_checker_create(&spec, stderr, 20);
    if (c && (sk.f || sk.checker))
        dram_set_cmd_sink(c, on_cmd, &sk);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    double cpu0 = cli_run_clock(CLOCK_PROCESS_CPUTIME_ID);
    ks_interrupt_polling(true);   /* both run loops check ks_interrupted() */
    dram_trace_set_stop_check(ks_interrupted);
    dram_trace_result res;
    dram_summary s;
    int rc = kernel ? dram_port_trace_run(&spec, &pspec, tf, trace, sk.f || sk.checker ? on_cmd : NULL, &sk, exhaustive,
                                          &res, &s, err, sizeof err)
                    : dram_trace_run(c, tf, trace, &res, err, sizeof err);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    run.has_sim = true, run.sim_cpu_s = cli_run_clock(CLOCK_PROCESS_CPUTIME_ID) - cpu0;
    run.sim_wall_s = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    fclose(tf);
    const int sig = rc == 3 ? ks_interrupted() : 0;
    if (rc && !sig) {
        fprintf(stderr, "rtdram: %s\n", err);
        ks_out_discard_all();
        dram_checker_destroy(sk.checker);
        dram_ctrl_destroy(c);
        return rc;
    }
    char reason[200] = "";
    if (sig) {
        snprintf(reason, sizeof reason, "interrupted by %s after %llu requests", ks_interrupt_name(sig),
                 (unsigned long long)res.requests);
        if (sk.f)
            fprintf(sk.f, "# partial: %s\n", reason);
    }
    if (sk.f && ks_out_commit(outs[0].out, err, sizeof err) != 0) {
        fprintf(stderr, "rtdram: %s\n", err);
        dram_checker_destroy(sk.checker);
        dram_ctrl_destroy(c);
        return 2;
    }
    if (c)
        dram_summary_compute(c, &pspec, &s);
    int status = 0;
    uint64_t viol = 0;
    if (sk.checker && !sig) {   /* an interrupted stream ends mid-way: nothing to check at its end */
        viol = dram_checker_finish(sk.checker, s.dram_cycles);
        if (viol)
            status = 1;
    }
    if (json) {
        run.trace = trace;
        run.has_cycles = true, run.cycles = (uint64_t)s.dram_cycles;
        /* the run object first, then "partial" in front when interrupted */
        char *text = NULL;
        size_t len = 0;
        FILE *mf = open_memstream(&text, &len);
        int jrc = mf ? json_with_run(&s, &run, mf) : -1;
        if (mf)
            jrc |= fclose(mf);
        if (jrc) {
            fprintf(stderr, "rtdram: --json: write error\n");
            status = 2;
        } else {
            cli_json_put(stdout, text, sig ? reason : NULL);
        }
        free(text);
    } else {
        if (sig)
            printf("PARTIAL              %s\n", reason);
        double host = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
        printf("trace                %s (%llu requests: %llu reads, %llu writes)\n", trace,
               (unsigned long long)res.requests, (unsigned long long)res.reads, (unsigned long long)res.writes);
        printf("config               %s\n", spec.source);
        dram_summary_text(&s, stdout);
        if (sk.checker)
            printf("timing checker       %llu commands, %llu violations\n",
                   (unsigned long long)dram_checker_commands(sk.checker), (unsigned long long)viol);
        printf("host time            %.3f s (%.2f M requests/s)\n", host,
               host > 0 ? (double)res.requests / host / 1e6 : 0.0);
    }
    dram_checker_destroy(sk.checker);
    dram_ctrl_destroy(c);
    if (sig) {
        fflush(stdout);
        fprintf(stderr, "rtdram: %s: statistics so far, marked partial%s\n", reason,
                cmd_trace ? "; the command trace ends with a '# partial' line" : "");
        return ks_interrupt_exit_status();
    }
    return status;
}
