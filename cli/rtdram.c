/* rtdram — runs a DRAM request trace through the LPDDR3 controller model.
 *   rtdram TRACE [--config FILE] [--power FILE] [--set KEY=VALUE]... [--json]
 *                [--cmd-trace FILE] [--check] [--exhaustive] [--kernel] [--help] [--version]
 * Exit: 0 ok, 1 timing violations found by --check, 2 bad usage or input,
 * 130/143 interrupted (Ctrl-C/SIGTERM: the statistics so far, marked partial;
 * the command trace ends with a "# partial" line). The --cmd-trace path is
 * planned before the run through the output layer (kernel/out_file.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli/options.h"
#include "cli/output_path.h"
#include "kernel/interrupt.h"
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

/* The options (cli/options.h); their defaults are the table's. */
typedef struct options {
    const char *config, *power, *cmd_trace, *trace;
    cli_list sets;
    bool json, check, exhaustive, kernel;
} options;

/* Reads argv into o: 0 or 2 when the tool is done (--help, bad usage),
 * CLI_GO_ON to run. */
static int parse_options(int argc, char **argv, options *o)
{
    const cli_opt table[] = {
        {.name = "config", .kind = CLI_STRING, .to.str = &o->config, .arg = "FILE",
         .help = "standard/controller parameter file (default " RTSIM_DATA_DIR "/lpddr3_1600.ini,\n"
                 "directory overridable with RTSIM_DATA_DIR)"},
        {.name = "power", .kind = CLI_STRING, .to.str = &o->power, .arg = "FILE",
         .help = "currents/voltages for energy (default lpddr3_1600_idd.ini beside it)"},
        {.name = "set", .kind = CLI_LIST, .to.list = &o->sets, .arg = "KEY=VALUE",
         .help = "override a parameter, KEY = section.name (e.g. timing.nCL=14,\n"
                 "controller.row_hit_cap=4, organization.channels=1); repeatable"},
        {.name = "json", .kind = CLI_FLAG, .to.flag = &o->json,
         .help = "print one JSON object instead of the text summary"},
        {.name = "cmd-trace", .kind = CLI_STRING, .to.str = &o->cmd_trace, .arg = "FILE",
         .help = "write the command stream (cycle,channel,rank,bank,CMD,row)"},
        {.name = "check", .kind = CLI_FLAG, .to.flag = &o->check,
         .help = "run the timing checker on the command stream (exit 1 on violation)"},
        {.name = "exhaustive", .kind = CLI_FLAG, .to.flag = &o->exhaustive,
         .help = "run the scheduler every cycle, no idle skipping (slow reference mode)"},
        {.name = "kernel", .kind = CLI_FLAG, .to.flag = &o->kernel,
         .help = "run the trace through the kernel module (request/response FIFOs,\n"
                 "DRAM clock) instead of the direct loop: same results, slower"},
        {.name = "help", .kind = CLI_HELP, .help = ""},
        {.name = "version", .kind = CLI_VERSION},
        {0}};
    const cli_tool tool = {
        .name = "rtdram", .opts = table, .indent = 2, .column = 20,
        .about = "usage: rtdram TRACE [options]\n"
                 "Simulates a DRAM request trace ('0x<hex addr> R|W' per line) on the command-level\n"
                 "LPDDR3 controller model with Ramulator's trace injection policy.\n",
        /* no .unknown: getopt's messages, then the usage */
    };
    int args, rc = cli_parse(&tool, argc, argv, &args);
    if (rc != CLI_GO_ON)
        return rc;
    if (args != argc - 1)
        return cli_usage_error(&tool, "expected exactly one TRACE argument");
    o->trace = argv[args];
    return CLI_GO_ON;
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

/* One run: its inputs, the controller and what it gives. */
typedef struct job {
    const options *o;
    cli_run_info *run;
    const char *config, *power;     /* as given, or the defaults */
    char cfg_buf[4200], pow_buf[4200];   /* PATH_MAX (4096) and more: a cut path names another file */
    dram_spec spec;
    dram_power_spec pspec;
    cli_output outs[1];             /* --cmd-trace */
    dram_ctrl *ctrl;                /* the direct loop's (NULL with --kernel) */
    sink sk;
    dram_trace_result res;
    dram_summary s;
    double host_s;
    int sig;                        /* the signal that interrupted the run, or 0 */
    char reason[200];
    char err[4096 + 512];   /* a message with a whole path (PATH_MAX) in it */
} job;

/* The output path, the standard and power files (defaults beside each
 * other in RTSIM_DATA_DIR); 0 or 2 with the message said. */
static int load_spec(job *j)
{
    const options *o = j->o;
    /* the output path first: a bad one fails before the run, not after it */
    j->outs[0] = (cli_output){"--cmd-trace", o->cmd_trace, NULL};
    if (!cli_plan_outputs(j->outs, 1, j->err, sizeof j->err)) {
        fprintf(stderr, "rtdram: %s\n", j->err);
        return 2;
    }
    const char *dir = getenv("RTSIM_DATA_DIR") ? getenv("RTSIM_DATA_DIR") : RTSIM_DATA_DIR;
    j->config = o->config;
    if (!j->config) {
        if (snprintf(j->cfg_buf, sizeof j->cfg_buf, "%s/lpddr3_1600.ini", dir) >= (int)sizeof j->cfg_buf) {
            fprintf(stderr, "rtdram: RTSIM_DATA_DIR %s: path too long (%zu characters)\n", dir, strlen(dir));
            return 2;
        }
        j->config = j->cfg_buf;
    }
    j->power = o->power;
    if (!j->power) {
        const char *slash = strrchr(j->config, '/');
        int n = slash ? (int)(slash - j->config) : 1;
        if (snprintf(j->pow_buf, sizeof j->pow_buf, "%.*s/lpddr3_1600_idd.ini", n, slash ? j->config : ".") >=
            (int)sizeof j->pow_buf) {
            fprintf(stderr, "rtdram: --config %s: path too long (%zu characters)\n", j->config, strlen(j->config));
            return 2;
        }
        j->power = j->pow_buf;
    }
    if (dram_spec_load(&j->spec, j->config, o->sets.v, o->sets.n, j->err, sizeof j->err) ||
        dram_power_spec_load(&j->pspec, j->power, j->err, sizeof j->err)) {
        fprintf(stderr, "rtdram: %s\n", j->err);
        return 2;
    }
    j->run->machine = j->config;
    j->run->has_config_hash = cli_run_dram_hash(j->config, o->sets.v, o->sets.n, j->power, &j->run->config_hash);
    return 0;
}

/* Runs the trace (the direct loop, or the kernel module with --kernel),
 * feeding the command trace and the checker; 0, or the exit status with
 * the message said. An interruption is not an error here (j->sig). */
static int run_trace(job *j)
{
    const options *o = j->o;
    FILE *tf = fopen(o->trace, "r");
    if (!tf) {
        fprintf(stderr, "rtdram: %s: cannot open\n", o->trace);
        return 2;
    }
    j->ctrl = o->kernel ? NULL : dram_ctrl_create(&j->spec, NULL, NULL, j->err, sizeof j->err);
    if (!o->kernel && !j->ctrl) {
        fprintf(stderr, "rtdram: %s\n", j->err);
        fclose(tf);
        return 2;
    }
    if (j->ctrl)
        dram_set_exhaustive(j->ctrl, o->exhaustive);
    if (j->outs[0].out) {
        j->sk.f = ks_out_begin(j->outs[0].out, j->err, sizeof j->err);
        if (!j->sk.f) {
            fprintf(stderr, "rtdram: %s\n", j->err);
            fclose(tf);
            return 2;
        }
        fprintf(j->sk.f, "# cycle,channel,rank,bank,cmd,row  (rtdram %s, trace %s)\n", RTSIM_VERSION, o->trace);
    }
    if (o->check)
        j->sk.checker = dram_checker_create(&j->spec, stderr, 20);
    if (j->ctrl && (j->sk.f || j->sk.checker))
        dram_set_cmd_sink(j->ctrl, on_cmd, &j->sk);
    const double t0 = cli_run_clock(CLOCK_MONOTONIC), cpu0 = cli_run_clock(CLOCK_PROCESS_CPUTIME_ID);
    ks_interrupt_polling(true);   /* both run loops check ks_interrupted() */
    dram_trace_set_stop_check(ks_interrupted);
    int rc = o->kernel ? dram_port_trace_run(&j->spec, &j->pspec, tf, o->trace,
                                             j->sk.f || j->sk.checker ? on_cmd : NULL, &j->sk, o->exhaustive,
                                             &j->res, &j->s, j->err, sizeof j->err)
                       : dram_trace_run(j->ctrl, tf, o->trace, &j->res, j->err, sizeof j->err);
    j->host_s = cli_run_clock(CLOCK_MONOTONIC) - t0;
    j->run->has_sim = true, j->run->sim_cpu_s = cli_run_clock(CLOCK_PROCESS_CPUTIME_ID) - cpu0;
    j->run->sim_wall_s = j->host_s;
    fclose(tf);
    j->sig = rc == 3 ? ks_interrupted() : 0;
    if (rc && !j->sig) {
        fprintf(stderr, "rtdram: %s\n", j->err);
        ks_out_discard_all();
        return rc;
    }
    if (j->sig)
        snprintf(j->reason, sizeof j->reason, "interrupted by %s after %llu requests", ks_interrupt_name(j->sig),
                 (unsigned long long)j->res.requests);
    return 0;
}

/* The command trace (committed), the checker's verdict and the summary,
 * text or JSON; the exit status. */
static int report(job *j)
{
    const options *o = j->o;
    if (j->sig && j->sk.f)
        fprintf(j->sk.f, "# partial: %s\n", j->reason);
    if (j->sk.f && ks_out_commit(j->outs[0].out, j->err, sizeof j->err) != 0) {
        fprintf(stderr, "rtdram: %s\n", j->err);
        return 2;
    }
    dram_summary *s = &j->s;
    if (j->ctrl)
        dram_summary_compute(j->ctrl, &j->pspec, s);
    int status = 0;
    uint64_t viol = 0;
    if (j->sk.checker && !j->sig) {   /* an interrupted stream ends mid-way: nothing to check at its end */
        viol = dram_checker_finish(j->sk.checker, s->dram_cycles);
        if (viol)
            status = 1;
    }
    if (o->json) {
        j->run->trace = o->trace;
        j->run->has_cycles = true, j->run->cycles = (uint64_t)s->dram_cycles;
        /* the run object first, then "partial" in front when interrupted */
        char *text = NULL;
        size_t len = 0;
        FILE *mf = open_memstream(&text, &len);
        int jrc = mf ? json_with_run(s, j->run, mf) : -1;
        if (mf)
            jrc |= fclose(mf);
        if (jrc) {
            fprintf(stderr, "rtdram: --json: write error\n");
            status = 2;
        } else {
            cli_json_put(stdout, text, j->sig ? j->reason : NULL);
        }
        free(text);
    } else {
        if (j->sig)
            printf("PARTIAL              %s\n", j->reason);
        printf("trace                %s (%llu requests: %llu reads, %llu writes)\n", o->trace,
               (unsigned long long)j->res.requests, (unsigned long long)j->res.reads,
               (unsigned long long)j->res.writes);
        printf("config               %s\n", j->spec.source);
        dram_summary_text(s, stdout);
        if (j->sk.checker)
            printf("timing checker       %llu commands, %llu violations\n",
                   (unsigned long long)dram_checker_commands(j->sk.checker), (unsigned long long)viol);
        printf("host time            %.3f s (%.2f M requests/s)\n", j->host_s,
               j->host_s > 0 ? (double)j->res.requests / j->host_s / 1e6 : 0.0);
    }
    if (j->sig) {
        fflush(stdout);
        fprintf(stderr, "rtdram: %s: statistics so far, marked partial%s\n", j->reason,
                o->cmd_trace ? "; the command trace ends with a '# partial' line" : "");
        return ks_interrupt_exit_status();
    }
    return status;
}

int main(int argc, char **argv)
{
    static cli_run_info run;   /* provenance of the JSON (docs/results.md) */
    cli_run_init(&run, "rtdram", argc, argv);
    ks_interrupt_install("rtdram");
    options o;
    int rc = parse_options(argc, argv, &o);
    if (rc == CLI_GO_ON) {
        static job j;   /* the standard's tables are large: not on the stack */
        j.o = &o, j.run = &run;
        rc = load_spec(&j);
        if (!rc)
            rc = run_trace(&j);
        if (!rc)
            rc = report(&j);
        dram_checker_destroy(j.sk.checker);
        dram_ctrl_destroy(j.ctrl);
    }
    free(o.sets.v);
    return rc;
}
