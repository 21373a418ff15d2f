/* rtsim — runs the cycle-level accelerator model on a scene (docs/design.md
 * "Command-line conventions"): builds the scene's BVH for the machine's
 * width, feeds primary (or diffuse path) rays through the model and prints
 * cycles, MRPS, utilization, cache hit rates, DRAM traffic and rays in flight.
 * Exit status: 0 success, 1 simulation failure (deadlock, stack overflow),
 * 2 bad usage or input, 130/143 interrupted (Ctrl-C/SIGTERM: the VCD ends at
 * the last complete time step, the JSON holds the statistics so far marked
 * "partial"). Every output path is planned before the run through the output
 * layer (kernel/out_file.h: temporary name and rename for files, in place for
 * stdout "-", devices and pipes; two outputs naming one file are refused). */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "frame/frame.h"
#include "fidelity/cost_estimate.h"
#include "fidelity/fidelity.h"
#include "fidelity/fidelity_params.h"
#include "kernel/fork_pool.h"
#include "kernel/interrupt.h"
#include "kernel/stats.h"
#include "model/accel_config.h"
#include "model/accel_top.h"
#include "config/config.h"
#include "model/mem/memsys_config.h"
#include "tracer/bvh/bvh.h"
#include "tracer/io/image.h"
#include "tracer/io/scene.h"

#include "cli/options.h"
#include "cli/output_path.h"
#include "cli/progress.h"
#include "cli/run_info.h"
#include "cli/version.h"

/* ---- options ---- */

typedef struct options {
    const char *scene, *view, *views, *machine, *res, *json, *vcd, *vcd_filter, *heatmap, *autosize, *help_module;
    const char *series;        /* --series FILE, NULL: none */
    uint64_t series_interval;  /* --series-interval N, cycles */
    bool series_interval_given;
    cli_list sets;
    int rays;                  /* index in ray_kinds */
    bool diffuse, occlusion;   /* --rays diffuse, occlusion (AO rays of the primary hits, docs/accel.md) */
    uint64_t bounces, seed;
    struct vcd_window {
        uint64_t a, b;         /* cycles [a, b) */
    } vcd_window;
    bool vcd_window_given, quiet, exhaustive, progress;
    int level;                 /* fid_level */
    double accuracy, sample_rate;   /* 0: not given */
    uint64_t jobs;             /* worker processes at once (--jobs, RTSIM_JOBS, else the CPUs) */
    uint64_t windows;          /* --windows, 0: not given */
} options;

/* Most worker processes --jobs and RTSIM_JOBS accept: a sanity bound (a
 * fidelity run has at most a handful of independent pieces, docs/fidelity.md). */
#define RTSIM_MAX_JOBS 1024

enum { RAYS_PRIMARY, RAYS_DIFFUSE, RAYS_OCCLUSION };
static const char *const ray_kinds[] = {"primary", "diffuse", "occlusion", NULL};

/* --vcd-window A:B, cycles, A < B */
static bool parse_vcd_window(const char *text, void *to, char *err, size_t errlen)
{
    (void)err, (void)errlen;
    struct vcd_window *w = to;
    char a[32] = "";
    const char *colon = strchr(text, ':');
    if (!colon || (size_t)(colon - text) >= sizeof a)
        return false;
    memcpy(a, text, (size_t)(colon - text));
    return cli_parse_u64(a, 0, UINT64_MAX / 4, &w->a) && cli_parse_u64(colon + 1, 1, UINT64_MAX / 4, &w->b) &&
           w->b > w->a;
}

/* --accuracy P%: fidelity.h */
static bool parse_accuracy(const char *text, void *to, char *err, size_t errlen)
{
    (void)err, (void)errlen;
    return fid_accuracy_parse(text, to);
}

/* Reads argv into o and checks the combinations: CLI_GO_ON to run (or to
 * answer --help-module), else the exit status (0 after --help or
 * --version, 2 with a message naming the option). */
static int parse_options(int argc, char **argv, options *o)
{
    const char *levels[FID_LEVEL_COUNT + 1] = {NULL};
    for (int i = 0; i < FID_LEVEL_COUNT; i++)
        levels[i] = fid_level_name((fid_level)i);
    /* the plan's default comes from the fidelity parameters, not a copy of it */
    char windows_help[96];
    snprintf(windows_help, sizeof windows_help, "windowed: windows of consecutive pixels ({range}; default %d)",
             fid_params_get()->win_snap_count);
    const cli_opt table[] = {
        {.name = "view", .kind = CLI_STRING, .to.str = &o->view, .arg = "NAME"},
        {.name = "views", .kind = CLI_STRING, .to.str = &o->views, .arg = "FILE"},
        {.name = "machine", .kind = CLI_STRING, .to.str = &o->machine, .arg = "bvh2|mbvh4|FILE.ini", .def = "mbvh4"},
        {.name = "rays", .kind = CLI_CHOICE, .to.choice = &o->rays, .choices = ray_kinds, .def = "primary"},
        {.name = "res", .kind = CLI_STRING, .to.str = &o->res, .arg = "WxH",   /* checked once the machine is read */
         .def = CLI_STR(RT_DEFAULT_WIDTH) "x" CLI_STR(RT_DEFAULT_HEIGHT)},
        {.name = "bounces", .kind = CLI_UINT, .to.u = &o->bounces, .arg = "N", .min = 0, .max = 64,
         .def = CLI_STR(RT_MAX_BOUNCES_DEFAULT)},
        {.name = "seed", .kind = CLI_UINT, .to.u = &o->seed, .arg = "N", .min = 0, .max = UINT64_MAX, .def = "1",
         .what = "expected a non-negative integer"},
        {.name = "set", .kind = CLI_LIST, .to.list = &o->sets, .arg = "KEY=VALUE",
         .help = "override a machine key (e.g. trv.count=8, or a key of the DRAM\n"
                 "standard file: dram.timing.nCL=14); see --help-module"},
        {.name = "json", .kind = CLI_STRING, .to.str = &o->json, .arg = "FILE",
         .help = "every statistic (with units and descriptions) as JSON"},
        {.name = "vcd", .kind = CLI_STRING, .to.str = &o->vcd, .arg = "FILE",
         .help = "waveforms of all units; --vcd-window A:B limits them to cycles\n"
                 "[A, B), --vcd-filter a comma-separated list of globs"},
        {.name = "vcd-window", .kind = CLI_CUSTOM, .to.custom = &o->vcd_window, .parse = parse_vcd_window, .arg = "A:B",
         .given = &o->vcd_window_given, .what = "expected A:B (cycles, A < B)"},
        {.name = "vcd-filter", .kind = CLI_STRING, .to.str = &o->vcd_filter, .arg = "GLOB"},
        {.name = "heatmap", .kind = CLI_STRING, .to.str = &o->heatmap, .arg = "FILE",
         .help = "simulated cycles per pixel (.png or .exr)"},
        {.name = "series", .kind = CLI_STRING, .to.str = &o->series, .arg = "FILE",
         .help = "interval statistics as CSV: a row every --series-interval\n"
                 "cycles (throughput, utilization, hit rates, DRAM, power per\n"
                 "unit; docs/results.md)"},
        {.name = "series-interval", .kind = CLI_UINT, .to.u = &o->series_interval, .arg = "N", .min = 1,
         .max = 1000000000000ull, .def = "10000", .given = &o->series_interval_given,
         .help = "cycles per row of --series ({range})"},
        {.name = "autosize-fifos", .kind = CLI_STRING, .to.str = &o->autosize, .arg = "OUT.ini",
         .help = "run, then write the machine with every FIFO shrunk to the\n"
                 "first power of two above its maximum occupancy (paper sec. 3)"},
        {.name = "help-module", .kind = CLI_STRING, .to.str = &o->help_module, .arg = "NAME", .stops = true,
         .help = "parameters, ports and statistics of a module (trv, ist, sched,\n"
                 "cache, arbiter, fixed_mem, dram, ...) and the keys of its\n"
                 "configuration section (node_l1, node_l2, prim, memory, fifo, machine,\n"
                 "dram)"},
        {.name = "quiet", .kind = CLI_FLAG, .to.flag = &o->quiet},
        {.name = "progress", .kind = CLI_FLAG, .to.flag = &o->progress,
         .help = "print the run-time estimate first and, when stderr is not a\n"
                 "terminal, a progress line every few seconds (a terminal\n"
                 "gets a progress bar anyway); runs estimated to take more\n"
                 "than a minute print the estimate in any case"},
        {.name = "exhaustive", .kind = CLI_FLAG, .to.flag = &o->exhaustive,
         .help = "step every unit every cycle (no idle skipping; reference mode)"},
        {.name = "help", .kind = CLI_HELP},
        {.name = "version", .kind = CLI_VERSION},
        {.name = "fidelity", .kind = CLI_CHOICE, .to.choice = &o->level, .choices = levels, .arg = "LEVEL",
         .def = "full",
         .help = "full (default), fixed-mem, functional, sampled or windowed: cheaper\n"
                 "models, each result with its error estimate and flag (docs/fidelity.md)"},
        {.name = "accuracy", .kind = CLI_CUSTOM, .to.custom = &o->accuracy, .parse = parse_accuracy, .arg = "P%",
         .what = "expected a percentage in (0, 100], e.g. 2%%",
         .help = "pick the cheapest level expected within P% (falls back to full)"},
        {.name = "sample-rate", .kind = CLI_REAL, .to.real = &o->sample_rate, .arg = "R", .lo = 0, .lo_open = true,
         .hi = 1, .help = "sampled, windowed: fraction of the pixels modelled\n"
                          "({range}; default 1/16 sampled, 1/8 windowed)"},
        {.name = "windows", .kind = CLI_UINT, .to.u = &o->windows, .arg = "N", .min = 2, .max = 4096,
         .help = windows_help},
        {.name = "jobs", .kind = CLI_UINT, .to.u = &o->jobs, .arg = "N", .min = 1, .max = RTSIM_MAX_JOBS,
         .help = "fidelity levels: run independent pieces (sample groups, the\n"
                 "functional pass, pilots) in up to N worker processes at once\n"
                 "({range}; default RTSIM_JOBS, else the CPUs this process may\n"
                 "use); the figures are the same whatever N"},
        {0}};
    const cli_tool tool = {
        .name = "rtsim", .opts = table, .synopsis = "usage: rtsim [SCENE]", .width = 93, .indent = 0, .column = 20,
        .about = "SCENE: a built-in scene (interior, hairball, city, forest; default interior) or an\n"
                 "       .obj/.ply(.gz)/.scene file. Defaults: 1280x720, mbvh4, primary rays,\n"
                 "       4 bounces, seed 1. Occlusion rays: 4 ambient-occlusion rays per primary hit.\n",
        .bad_value = "%s %s: %s", .uint_what = "allowed range %s", .real_what = "allowed range %s",
        .choice_what = "allowed values are %s", .unknown = "unknown option or missing value: %s",
        .hint = "(see rtsim --help)", .unknown_shows_usage = true,
    };
    memset(o, 0, sizeof *o);
    int args, rc = cli_parse(&tool, argc, argv, &args);
    if (rc != CLI_GO_ON || o->help_module)   /* --help-module: answered alone */
        return rc;
    o->scene = args < argc ? argv[args++] : "interior";
    if (args < argc)
        return cli_usage_error(&tool, "unexpected argument %s (one SCENE only)", argv[args]);
    o->diffuse = o->rays == RAYS_DIFFUSE;
    o->occlusion = o->rays == RAYS_OCCLUSION;
    if (!o->vcd && (o->vcd_window_given || o->vcd_filter))
        return cli_usage_error(&tool, "%s: only with --vcd FILE (no waveform is written without it)",
                               o->vcd_window_given ? "--vcd-window" : "--vcd-filter");
    if (!o->series && o->series_interval_given)
        return cli_usage_error(&tool, "--series-interval: only with --series FILE (no series is written without it)");
    if (o->series && (o->accuracy > 0 || o->level == FID_FUNCTIONAL))
        return cli_usage_error(&tool, "--series needs a level that simulates cycles: full, fixed-mem, sampled or "
                                      "windowed (%s asked)",
                               o->accuracy > 0 ? "--accuracy" : "functional");
    const char *cheaper = o->accuracy > 0 ? "--accuracy" : o->level != FID_FULL ? fid_level_name(o->level) : NULL;
    if (cheaper && o->occlusion)
        return cli_usage_error(&tool, "--rays occlusion needs --fidelity full (%s asked)", cheaper);
    if (cheaper && (o->vcd || o->heatmap || o->autosize || o->exhaustive))
        return cli_usage_error(&tool, "--vcd, --heatmap, --autosize-fifos and --exhaustive need --fidelity full "
                                      "(%s asked)",
                               cheaper);
    if (o->heatmap && !rt_image_format_supported(o->heatmap))
        return cli_usage_error(&tool, "--heatmap %s: the file must end in .png or .exr", o->heatmap);
    if (!o->jobs) {   /* not given: RTSIM_JOBS, else every CPU this process may run on */
        const char *env = getenv("RTSIM_JOBS");
        if (env && !cli_parse_u64(env, 1, RTSIM_MAX_JOBS, &o->jobs))
            return cli_usage_error(&tool, "RTSIM_JOBS=%s: allowed range 1..%d", env, RTSIM_MAX_JOBS);
        if (!env)
            o->jobs = (uint64_t)ks_pool_cpus();
    }
    return CLI_GO_ON;
}

static rtcfg *make_cfg(char *err, size_t errlen)
{
    rtcfg *cfg = rtcfg_create();
    if (!cfg) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    if (memsys_add_schemas(cfg, err, errlen) || accel_add_schemas(cfg, err, errlen)) {
        rtcfg_destroy(cfg);
        return NULL;
    }
    return cfg;
}

static int help_module(const char *name)
{
    char err[4096 + 512];   /* a message with a whole path (PATH_MAX) in it */
    rtcfg *cfg = make_cfg(err, sizeof err);
    /* finished, so that the deferred [dram] keys (the DRAM standard file's) are listed */
    if (!cfg || rtcfg_finish(cfg, err, sizeof err)) {
        fprintf(stderr, "rtsim: %s\n", err);
        if (cfg)
            rtcfg_destroy(cfg);
        return 2;
    }
    int found = 0;
    const ks_module_desc *d = accel_module_desc(name);
    if (!d && !strcmp(name, fid_module_desc.name))
        d = &fid_module_desc;   /* fidelity/ is above the model: not in its list */
    if (d) {
        ks_module_desc_print(d, stdout);
        found = 1;
    }
    /* a module's parameters are the keys of the configuration sections its
     * description names: their schemas (in the unit's own file) are the only
     * place a key's type, default, range, unit and source are written */
    for (int i = 0; d && i < rtcfg_schema_count(cfg); i++) {
        const rtcfg_schema *s = rtcfg_schema_at(cfg, i);
        if (ks_module_desc_names_section(d, s->section)) {
            printf("\nConfiguration keys [%s]:\n", s->section);
            rtcfg_print_schema(stdout, s, NULL);
        }
    }
    /* a configuration section asked for by its own name ("machine", "fifo") */
    for (int i = 0; !d && i < rtcfg_schema_count(cfg); i++)
        if (!strcmp(rtcfg_schema_at(cfg, i)->section, name)) {
            printf("%sConfiguration keys [%s]:\n", found ? "\n" : "", name);
            rtcfg_print_schema(stdout, rtcfg_schema_at(cfg, i), NULL);
            found = 1;
        }
    rtcfg_destroy(cfg);
    if (!found) {
        fprintf(stderr, "rtsim: --help-module %s: no such module; modules: ", name);
        accel_module_list(stderr);
        fprintf(stderr, "; configuration sections: node_l1, node_l2, prim, memory, fifo, machine, trv, ist, sched, dram\n");
        return 2;
    }
    return 0;
}

typedef struct progress_state {
    bool on;                      /* a progress bar (stderr is a terminal) */
    bool lines;                   /* --progress with stderr not a terminal: a line every `every` s */
    double every, last, est_cycles;
    uint64_t total;               /* primary rays */
    double t0;
    const accel_source *src;
} progress_state;

static double wall(void) { return cli_run_clock(CLOCK_MONOTONIC); }

static void progress_cb(void *user, uint64_t cycle, uint64_t done, uint64_t admitted)
{
    progress_state *p = user;
    if (p->lines) {
        double now = wall();
        if (now - p->last >= p->every) {
            p->last = now;
            char of_est[48] = "";   /* a cheaper level's full run has no estimate */
            if (p->est_cycles > 0)
                snprintf(of_est, sizeof of_est, " (~%.0f%% of the estimate)", 100.0 * (double)cycle / p->est_cycles);
            fprintf(stderr, "rtsim: progress: cycle %llu%s, %llu rays done, %llu/%llu primaries admitted, %.0f s\n",
                    (unsigned long long)cycle, of_est, (unsigned long long)done, (unsigned long long)(admitted < p->total ? admitted : p->total),
                    (unsigned long long)p->total, now - p->t0);
            fflush(stderr);
        }
        return;
    }
    if (!p->on)
        return;
    (void)done;
    double frac = p->total ? (double)(admitted < p->total ? admitted : p->total) / (double)p->total : 1.0;
    double el = wall() - p->t0;
    double eta = frac > 0.01 ? el * (1.0 - frac) / frac : 0.0;
    char bar[CLI_PROGRESS_CELLS + 1];
    cli_progress_bar((int)(frac * CLI_PROGRESS_CELLS), bar);
    /* The fraction is rays admitted over the primary-ray count: the number
     * of bounce rays is only known once every path has ended, so past 100%
     * the remaining time is unknown and no ETA is claimed. */
    if (admitted >= p->total)
        fprintf(stderr, "\r[%s] %3.0f%%  cycle %llu  rays %llu  finishing paths, ETA unknown   ", bar, 100.0 * frac,
                (unsigned long long)cycle, (unsigned long long)done);
    else
        fprintf(stderr, "\r[%s] %3.0f%%  cycle %llu  rays %llu  ETA %.0fs   ", bar, 100.0 * frac,
                (unsigned long long)cycle, (unsigned long long)done, eta);
    fflush(stderr);
}

/* Progress of a cheaper level's independent pieces (kernel/fork_pool.h):
 * the bar, or with --progress off a terminal a line every few seconds. */
static void pieces_cb(void *user, int done, int total)
{
    progress_state *p = user;
    double now = wall();
    if (p->lines) {
        if (now - p->last >= p->every || done == total) {
            p->last = now;
            fprintf(stderr, "rtsim: progress: %d of %d pieces done (windows, groups, passes), %.0f s\n", done,
                    total, now - p->t0);
            fflush(stderr);
        }
        return;
    }
    if (!p->on)
        return;
    char bar[CLI_PROGRESS_CELLS + 1];
    cli_progress_bar(total > 0 ? done * CLI_PROGRESS_CELLS / total : CLI_PROGRESS_CELLS, bar);
    fprintf(stderr, "\r[%s] %d/%d pieces  %.0fs   ", bar, done, total, now - p->t0);
    fflush(stderr);
}

/* The statistics with the run object (cli/run_info.h) as their first member,
 * then `head` (JSON members: the fidelity strings, fidelity.h; may be NULL). */
static int write_stats_run(ks_stats *st, const cli_run_info *ri, const char *head, FILE *f)
{
    char *buf = NULL, *full = NULL;
    size_t len = 0, flen = 0;
    FILE *m = open_memstream(&buf, &len);
    if (!m)
        return -1;
    int rc = ks_stats_write_json(st, m);
    rc |= fclose(m);
    if (!rc && head && *head && len >= 2 && !strncmp(buf, "{\n", 2)) {
        /* head's members right after the opening brace */
        FILE *h = open_memstream(&full, &flen);
        rc = !h || fputs("{\n", h) < 0 || fputs(head, h) < 0 || fputs(buf + 2, h) < 0;
        if (h)
            rc |= fclose(h);
    }
    if (!rc)
        rc = full ? cli_run_splice(f, ri, full, flen, false) : cli_run_splice(f, ri, buf, len, false);
    free(buf);
    free(full);
    return rc ? -1 : 0;
}

/* The statistics with the run object first (then head), marked partial
 * (reason) when the run was interrupted. */
static int write_json(ks_stats *st, const cli_run_info *ri, const char *head, ks_out *out, const char *reason,
                      char *err, size_t errlen)
{
    char *text = NULL;
    size_t len = 0;
    FILE *mf = open_memstream(&text, &len);
    if (!mf) {
        snprintf(err, errlen, "--json: out of memory");
        return -1;
    }
    int rc = write_stats_run(st, ri, head, mf);
    rc |= fclose(mf);
    if (rc) {
        free(text);
        snprintf(err, errlen, "--json: out of memory");
        return -1;
    }
    rc = cli_write_json(out, text, reason, err, errlen);
    free(text);
    return rc;
}

/* ---- the run ---- */

/* One run: the machine, the scene and its BVH, the rays, the model. */
typedef struct job {
    const options *o;
    cli_run_info *run;         /* provenance of the JSON (cli/run_info.h) */
    rtcfg *cfg;
    uint32_t w, h;
    cli_output outs[5];        /* --json, --vcd, --heatmap, --autosize-fifos, --series */
    rt_scene sc;
    const rt_view *view;
    rt_bvh_image img;
    rtsim_frame frame;
    accel_source src;
    accel_top *top;
    accel_series *series;      /* --series with the full model */
    char err[8192];
} job;

/* The machine (preset or file, then --set) and the frame size; false with
 * the message in j->err. */
static bool load_machine(job *j)
{
    const options *o = j->o;
    j->cfg = make_cfg(j->err, sizeof j->err);
    if (!j->cfg || rtcfg_load(j->cfg, o->machine, j->err, sizeof j->err))
        return false;
    for (int i = 0; i < o->sets.n; i++)
        if (rtcfg_set(j->cfg, o->sets.v[i], j->err, sizeof j->err))
            return false;
    return !rtcfg_finish(j->cfg, j->err, sizeof j->err) &&
           rt_parse_resolution(o->res, &j->w, &j->h, j->err, sizeof j->err);
}

/* Every output before the scene is loaded (the VCD writer finds its plan
 * by path, kernel/vcd.h). */
static bool plan_outputs(job *j)
{
    const options *o = j->o;
    j->outs[0] = (cli_output){"--json", o->json, NULL};
    j->outs[1] = (cli_output){"--vcd", o->vcd, NULL};
    j->outs[2] = (cli_output){"--heatmap", o->heatmap, NULL};
    j->outs[3] = (cli_output){"--autosize-fifos", o->autosize, NULL};
    j->outs[4] = (cli_output){"--series", o->series, NULL};
    return cli_plan_outputs(j->outs, 5, j->err, sizeof j->err);
}

/* The scene and its view, the BVH for the machine's width and the rays of
 * the frame (camera, diffuse paths or occlusion rays); false with j->err. */
static bool load_scene(job *j)
{
    const options *o = j->o;
    if (!rt_scene_load(o->scene, &j->sc, j->err, sizeof j->err) ||
        (o->views && !rt_scene_set_views_file(&j->sc, o->views, j->err, sizeof j->err)))
        return false;
    j->view = rt_scene_view(&j->sc, o->view, j->err, sizeof j->err);
    if (!j->view)
        return false;
    rt_bvh_params bp;
    rtsim_bvh_params(j->cfg, &bp);
    if (!rt_bvh_build(&j->sc.mesh, &bp, &j->img, NULL, j->err, sizeof j->err))
        return false;
    if (!rtsim_frame_init(&j->frame, j->cfg, &j->sc.mesh, j->view, j->w, j->h, o->diffuse, (uint32_t)o->bounces, o->seed,
                          o->heatmap != NULL, &j->src, j->err, sizeof j->err))
        return false;
    return !o->occlusion ||
           rtsim_frame_occlusion(&j->frame, &j->img, RT_AO_SAMPLES_DEFAULT, &j->src, j->err, sizeof j->err);
}

/* The provenance of a run (docs/results.md) that the options and the scene give. */
static void fill_run(job *j)
{
    const options *o = j->o;
    cli_run_info *run = j->run;
    run->scene = o->scene, run->views_file = o->views, run->view = j->view->name;
    run->has_mesh_hash = true, run->mesh_hash = rt_mesh_hash(&j->sc.mesh);
    run->machine = o->machine;
    run->has_config_hash = cli_run_config_hash(j->cfg, &run->config_hash);
    run->width = j->w, run->height = j->h, run->rays = o->diffuse ? "diffuse" : "primary";
    run->has_bounces = o->diffuse, run->bounces = (uint32_t)o->bounces;
    run->has_seed = o->diffuse, run->seed = o->seed;
}

/* --series with a cheaper level: a scratch folder for the rows of each
 * piece's run (fid_job.series_dir); false with j->err. */
static bool series_dir_make(job *j, char *dir, size_t cap)
{
    const char *tmp = getenv("TMPDIR");
    const int len = snprintf(dir, cap, "%s/rtsim-series-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (len < 0 || (size_t)len >= cap) {   /* refused, never cut (docs/kernel.md) */
        snprintf(j->err, sizeof j->err, "--series: TMPDIR %s is longer than %zu characters", tmp, cap - 24);
        return false;
    }
    if (!mkdtemp(dir)) {
        snprintf(j->err, sizeof j->err, "--series: cannot make a scratch folder %s", dir);
        return false;
    }
    return true;
}

static int series_file_filter(const struct dirent *e) { return strstr(e->d_name, ".csv") != NULL; }

/* Joins the pieces' rows (in name order: piece order) under one header
 * into the --series output, when write; then removes the folder. 0, or -1
 * with j->err. */
static int series_dir_join(job *j, const char *dir, bool write)
{
    struct dirent **names = NULL;
    int n = scandir(dir, &names, series_file_filter, alphasort), rc = 0;
    FILE *out = write && n >= 0 ? ks_out_begin(j->outs[4].out, j->err, sizeof j->err) : NULL;
    if (write && !out)
        rc = -1;
    if (out)
        accel_series_write_header(out, (uint32_t)rtcfg_int(j->cfg, "trv.count"));
    for (int i = 0; i < n; i++) {
        char path[RTCFG_PATH_MAX + 2 + sizeof names[i]->d_name];   /* dir fits RTCFG_PATH_MAX */
        snprintf(path, sizeof path, "%s/%s", dir, names[i]->d_name);
        FILE *in = out ? fopen(path, "r") : NULL;
        if (out && !in) {
            snprintf(j->err, sizeof j->err, "--series: cannot read %s", path);
            rc = -1;
        }
        char buf[65536];
        for (size_t k; in && (k = fread(buf, 1, sizeof buf, in)) > 0;)
            fwrite(buf, 1, k, out);
        if (in)
            fclose(in);
        remove(path);
        free(names[i]);
    }
    free(names);
    rmdir(dir);
    if (out && rc == 0 && ks_out_commit(j->outs[4].out, j->err, sizeof j->err))
        rc = -1;
    return rc;
}

/* A cheaper fidelity level or --accuracy (fidelity.h): runs, prints the
 * summary and writes the JSON. Returns the exit status. */
static int run_fidelity(job *j)
{
    const options *o = j->o;
    /* progress: of the pieces (pieces_cb), and of a whole-frame run of the
     * model (fixed-mem's last run, --accuracy's fallback to full) */
    progress_state ps = {!o->quiet && isatty(2), o->progress && !isatty(2), 0, 0, 0, (uint64_t)j->w * j->h, wall(),
                         NULL};
    fid_cost_params ep;
    char eerr[RTCFG_PATH_MAX + 256];
    if (fid_cost_load(&ep, eerr, sizeof eerr))
        ps.every = ep.progress_s;
    else if (ps.lines) {
        fprintf(stderr, "rtsim: warning: no progress lines: %s\n", eerr);
        ps.lines = false;
    }
    ps.last = ps.t0;
    fid_job job = {j->cfg, &j->sc.mesh, j->view, &j->img, j->w, j->h, o->diffuse, (uint32_t)o->bounces, o->seed,
                   o->sample_rate, progress_cb, &ps, (int)o->jobs, (uint32_t)o->windows, NULL, 0};
    char series_dir[RTCFG_PATH_MAX] = "";
    if (o->series) {
        if (!series_dir_make(j, series_dir, sizeof series_dir)) {
            fprintf(stderr, "rtsim: %s\n", j->err);
            return 2;
        }
        job.series_dir = series_dir;
        job.series_interval = o->series_interval;
    }
    fid_outcome fo;
    fill_run(j);
    double t0 = wall(), c0 = ks_pool_process_cpu_s(), w0 = ks_pool_children_cpu_s();
    uint64_t forked0 = ks_pool_workers_forked();
    ks_pool_set_progress(pieces_cb, &ps);
    int rc = fid_run(&job, (fid_level)o->level, o->accuracy, &fo, j->err, sizeof j->err);
    ks_pool_set_progress(NULL, NULL);
    if (ps.on)
        fprintf(stderr, "\r%70s\r", "");
    double host_s = wall() - t0, cpu_s = ks_pool_process_cpu_s() - c0, worker_s = ks_pool_children_cpu_s() - w0;
    uint64_t workers = ks_pool_workers_forked() - forked0;
    if (o->series && series_dir_join(j, series_dir, rc == 0 && !ks_interrupted())) {
        fprintf(stderr, "rtsim: --series %s: %s\n", o->series, j->err);
        rc = rc ? rc : 2;
    }
    if (rc && ks_interrupted()) {
        /* Ctrl-C while worker processes ran: they are stopped; nothing is written */
        fprintf(stderr, "rtsim: %s; no output written\n", j->err);
        fid_outcome_free(&fo);
        return ks_interrupt_exit_status();
    }
    if (rc)
        fprintf(stderr, "rtsim: %s\n", j->err);
    if (!o->quiet && (rc == 0 || fo.top)) {
        printf("scene       %s, view %s, %ux%u, %s rays\n", j->sc.name, j->view->name, j->w, j->h,
               o->diffuse ? "diffuse" : "primary");
        printf("BVH         %u nodes x %u B, %u triangles\n", j->img.nnodes, j->img.node_bytes, j->img.ntris);
        fid_outcome_print(&fo, stdout);
        fid_print_summary(&fo.res, stdout);
        printf("host        %.3f s CPU (%.3f s wall), %.0f K rays/s (CPU)\n", cpu_s, host_s,
               cpu_s > 0 ? fo.rays / cpu_s / 1e3 : 0.0);
        if (workers)   /* the CPU above is this process's and its workers': say how it splits */
            printf("workers     %llu processes, up to %llu at once (--jobs): %.3f s of the CPU above, "
                   "%.2fx the wall time\n",
                   (unsigned long long)workers, (unsigned long long)o->jobs, worker_s,
                   host_s > 0 ? cpu_s / host_s : 0.0);
        fid_print_steps(&fo.res, stdout);
    }
    if (o->json && (rc == 0 || fo.top)) {
        char jhead[4096];
        fid_json_strings(&fo.res, jhead, sizeof jhead);
        j->run->has_sim = true, j->run->sim_cpu_s = cpu_s, j->run->sim_wall_s = host_s;
        j->run->has_workers = true, j->run->jobs = o->jobs, j->run->workers = workers, j->run->worker_cpu_s = worker_s;
        for (int i = 0; i < fo.res.nsteps && i < CLI_RUN_MAX_STEPS; i++)
            j->run->step_name[i] = fo.res.steps[i].name, j->run->step_cpu_s[i] = fo.res.steps[i].cpu_s;
        j->run->nsteps = fo.res.nsteps < CLI_RUN_MAX_STEPS ? fo.res.nsteps : CLI_RUN_MAX_STEPS;
        if (write_json(fid_outcome_stats(&fo), j->run, jhead, j->outs[0].out, NULL, j->err, sizeof j->err)) {
            fprintf(stderr, "rtsim: %s\n", j->err);
            rc = rc ? rc : 2;
        }
    }
    fid_outcome_free(&fo);
    return rc;
}

/* The run-time estimate: said before a long run starts, and with
 * --progress; sets up the progress lines. */
static void announce(job *j, progress_state *ps)
{
    const options *o = j->o;
    fid_cost_params ep;
    char eerr[RTCFG_PATH_MAX + 256];
    if (!fid_cost_load(&ep, eerr, sizeof eerr)) {
        fprintf(stderr, "rtsim: warning: no run-time estimate: %s\n", eerr);
        return;
    }
    const accel_params *ap = accel_top_params(j->top);
    rt_trv_params tp;
    rtsim_trv_params(ap, j->img.width, &tp);
    fid_cost est;
    fid_cost_frame(&ep, &j->frame, &j->img, &tp, ap->trv_count, o->exhaustive, &est);
    if (o->progress || est.host_s >= ep.announce_s) {
        char d[32];
        fid_cost_duration(est.host_s, d, sizeof d);
        fprintf(stderr, "rtsim: estimate: ~%.0f rays, ~%.3g simulated cycles, ~%s of host time (%s%s)%s\n", est.rays,
                est.cycles, d, o->diffuse ? "diffuse" : "primary", o->exhaustive ? ", exhaustive" : "",
                est.host_s >= ep.announce_s && !o->progress ? "; --progress prints progress lines" : "");
    }
    ps->lines = o->progress && !isatty(2);
    ps->every = ep.progress_s;
    ps->last = ps->t0;
    ps->est_cycles = est.cycles;
}

/* After the run: the heatmap (not from a cut run: an image cannot say it is
 * partial) and the autosized machine (only from a run that finished: one
 * cut short would size for part of the frame); the exit status so far, or
 * 2 when one fails. */
static int write_images(job *j, int rc, bool cut, bool finished)
{
    const options *o = j->o;
    if (o->heatmap && !cut) {
        float lo, hi;
        rt_image_value_range(j->frame.pixel_cycles, (size_t)j->w * j->h, &lo, &hi);
        const char *stage = ks_out_stage(j->outs[2].out, j->err, sizeof j->err);
        if (!stage ||
            !rt_image_write_heatmap(stage, j->frame.pixel_cycles, j->w, j->h, lo, hi, RT_COLORMAP_VIRIDIS, j->err,
                                    sizeof j->err) ||
            ks_out_commit(j->outs[2].out, j->err, sizeof j->err)) {
            fprintf(stderr, "rtsim: --heatmap %s: %s\n", o->heatmap, j->err);
            ks_out_discard(j->outs[2].out);
            rc = rc ? rc : 2;
        }
    }
    if (o->autosize && finished) {
        FILE *af = NULL;
        if (accel_top_autosize(j->top, j->cfg, j->err, sizeof j->err) ||
            !(af = ks_out_begin(j->outs[3].out, j->err, sizeof j->err)) ||
            (rtcfg_write_ini_file(j->cfg, af), ks_out_commit(j->outs[3].out, j->err, sizeof j->err))) {
            fprintf(stderr, "rtsim: --autosize-fifos %s\n", j->err);
            ks_out_discard(j->outs[3].out);
            rc = rc ? rc : 2;
        } else if (!o->quiet) {
            printf("FIFOs       sized configuration written to %s\n", o->autosize);
        }
    }
    return rc;
}

/* The full model: builds it, runs the frame, prints the summary and writes
 * the outputs. Returns the exit status. */
static int run_full(job *j)
{
    const options *o = j->o;
    accel_image aimg = rtsim_image(&j->img);
    accel_top_opts to = {0};
    to.vcd_path = o->vcd;
    to.vcd_begin_cycle = o->vcd_window.a;
    to.vcd_end_cycle = o->vcd_window.b;
    to.vcd_filter = o->vcd_filter;
    to.exhaustive = o->exhaustive;
    FILE *series_f = NULL;
    if (o->series && (!(series_f = ks_out_begin(j->outs[4].out, j->err, sizeof j->err)) ||
                      !(to.series = accel_series_create(series_f, o->series_interval, true)))) {
        fprintf(stderr, "rtsim: --series %s: %s\n", o->series, series_f ? "out of memory" : j->err);
        return 2;
    }
    j->series = to.series;
    j->top = accel_top_create(j->cfg, &aimg, &j->src, &to, j->err, sizeof j->err);
    if (!j->top) {
        fprintf(stderr, "rtsim: %s\n", j->err);
        return 2;
    }
    fid_result fres;
    fid_result_full(&fres);
    if (fid_register_stats(&fres, accel_top_stats(j->top))) {
        fprintf(stderr, "rtsim: fidelity statistics: %s\n", ks_stats_error(accel_top_stats(j->top)));
        return 2;
    }
    progress_state ps = {!o->quiet && isatty(2), false, 0, 0, 0, j->src.primary_count, wall(), &j->src};
    announce(j, &ps);
    double t0 = wall(), c0 = ks_pool_process_cpu_s();
    ks_interrupt_polling(true);   /* accel_top_run checks ks_interrupted() every slice */
    int run_rc = accel_top_run(j->top, progress_cb, &ps, j->err, sizeof j->err);
    double host_s = wall() - t0, cpu_s = ks_pool_process_cpu_s() - c0;
    if (ps.on)
        fprintf(stderr, "\r%70s\r", "");
    const int sig = ks_interrupted();
    char reason[160] = "";
    if (sig)
        snprintf(reason, sizeof reason, "interrupted by %s at cycle %llu", ks_interrupt_name(sig),
                 (unsigned long long)accel_top_cycles(j->top));
    int rc = run_rc ? 1 : 0;
    if (run_rc && !sig)
        fprintf(stderr, "rtsim: %s\n", j->err);
    if (!o->quiet) {
        printf("scene       %s, view %s, %ux%u, %s rays\n", j->sc.name, j->view->name, j->w, j->h,
               o->diffuse ? "diffuse" : o->occlusion ? "occlusion" : "primary");
        printf("BVH         %u nodes x %u B, %u triangles\n", j->img.nnodes, j->img.node_bytes, j->img.ntris);
        if (sig)
            printf("PARTIAL     %s: the figures cover the run until then\n", reason);
        accel_top_print_summary(j->top, stdout);
        fid_print_summary(&fres, stdout);
        printf("host        %.3f s CPU (%.3f s wall), %.2f M simulated cycles/s, %.0f K rays/s (CPU)\n", cpu_s, host_s,
               cpu_s > 0 ? (double)accel_top_cycles(j->top) / cpu_s / 1e6 : 0.0,
               cpu_s > 0 ? (double)accel_top_rays(j->top) / cpu_s / 1e3 : 0.0);
    }
    char jhead[4096];
    fid_json_strings(&fres, jhead, sizeof jhead);
    fill_run(j);
    j->run->rays = o->occlusion ? "occlusion" : j->run->rays;
    j->run->has_sim = true, j->run->sim_cpu_s = cpu_s, j->run->sim_wall_s = host_s;
    j->run->has_workers = true, j->run->jobs = o->jobs;   /* the full model: one process */
    j->run->has_cycles = true, j->run->cycles = accel_top_cycles(j->top);
    if (o->json &&
        write_json(accel_top_stats(j->top), j->run, jhead, j->outs[0].out, sig ? reason : NULL, j->err, sizeof j->err)) {
        fprintf(stderr, "rtsim: %s\n", j->err);
        rc = rc ? rc : 2;
    }
    rc = write_images(j, rc, sig != 0, run_rc == 0);
    /* the series, like the heatmap, only from a run that was not cut short */
    if (o->series && !sig && ks_out_commit(j->outs[4].out, j->err, sizeof j->err)) {
        fprintf(stderr, "rtsim: --series %s: %s\n", o->series, j->err);
        rc = rc ? rc : 2;
    }
    if (sig) {
        fflush(stdout);
        fprintf(stderr, "rtsim: %s; %s%s%s%s%s\n", reason, o->vcd ? "the VCD ends there, " : "",
                o->json ? "the JSON statistics are marked partial" : "statistics above are partial",
                o->autosize ? ", no --autosize-fifos file written" : "", o->heatmap ? ", no heatmap written" : "",
                o->series ? ", no series written" : "");
        rc = ks_interrupt_exit_status();
    }
    return rc;
}

/* Loads, runs (full model or a cheaper level) and writes; the exit status. */
static int simulate(const options *o, cli_run_info *run)
{
    static job j;   /* zero: what a step did not fill is freed as empty */
    j.o = o, j.run = run;
    int rc;
    if (!load_machine(&j) || !plan_outputs(&j) || !load_scene(&j)) {
        fprintf(stderr, "rtsim: %s\n", j.err);
        rc = 2;
    } else if (o->level != FID_FULL || o->accuracy > 0) {
        rc = run_fidelity(&j);   /* a cheaper level or the automatic choice: fidelity/ runs it */
    } else {
        rc = run_full(&j);
    }
    ks_out_discard_all();   /* outputs not committed (failure, interruption): no temporaries left */
    accel_top_destroy(j.top);
    accel_series_destroy(j.series);
    rtsim_frame_free(&j.frame);
    rt_bvh_image_free(&j.img);
    rt_scene_free(&j.sc);
    if (j.cfg)
        rtcfg_destroy(j.cfg);
    return rc;
}

int main(int argc, char **argv)
{
    static cli_run_info run;   /* provenance of the JSON (cli/run_info.h) */
    cli_run_init(&run, "rtsim", argc, argv);
    ks_interrupt_install("rtsim");
    options o;
    int rc = parse_options(argc, argv, &o);
    if (rc == CLI_GO_ON)
        rc = o.help_module ? help_module(o.help_module) : simulate(&o, &run);
    free(o.sets.v);
    return rc;
}
