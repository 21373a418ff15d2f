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
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli/rtsim_estimate.h"
#include "frame/frame.h"
#include "fidelity/fidelity.h"
#include "kernel/stats.h"
#include "model/accel_config.h"
#include "model/accel_top.h"
#include "config/config.h"
#include "model/mem/memsys_config.h"
#include "tracer/bvh.h"
#include "tracer/image.h"
#include "tracer/scene.h"

#include "cli/output_path.h"
#include "cli/run_info.h"
#include "cli/version.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: rtsim [SCENE] [--view NAME] [--views FILE] [--machine bvh2|mbvh4|FILE.ini]\n"
            "             [--rays primary|diffuse|occlusion] [--res WxH] [--bounces N] [--seed N]\n"
            "             [--set KEY=VALUE]... [--json FILE] [--vcd FILE] [--vcd-window A:B]\n"
            "             [--vcd-filter GLOB] [--heatmap FILE] [--autosize-fifos OUT.ini]\n"
            "             [--help-module NAME] [--quiet] [--progress] [--exhaustive] [--help] [--version]\n"
            "             [--fidelity full|fixed-mem|functional|sampled] [--accuracy P%%]\n"
            "             [--sample-rate R]\n"
            "SCENE: a built-in scene (interior, hairball, city, forest; default interior) or an\n"
            "       .obj/.ply(.gz)/.scene file. Defaults: 1280x720, mbvh4, primary rays,\n"
            "       4 bounces, seed 1. Occlusion rays: 4 ambient-occlusion rays per primary hit.\n"
            "--set KEY=VALUE     override a machine key (e.g. trv.count=8, or a key of the DRAM\n"
            "                    standard file: dram.timing.nCL=14); see --help-module\n"
            "--json FILE         every statistic (with units and descriptions) as JSON\n"
            "--vcd FILE          waveforms of all units; --vcd-window A:B limits them to cycles\n"
            "                    [A, B), --vcd-filter a comma-separated list of globs\n"
            "--heatmap FILE      simulated cycles per pixel (.png or .exr)\n"
            "--autosize-fifos F  run, then write the machine with every FIFO shrunk to the\n"
            "                    first power of two above its maximum occupancy (paper sec. 3)\n"
            "--exhaustive        step every unit every cycle (no idle skipping; reference mode)\n"
            "--progress          print the run-time estimate first and, when stderr is not a\n"
            "                    terminal, a progress line every few seconds (a terminal\n"
            "                    gets a progress bar anyway); runs estimated to take more\n"
            "                    than a minute print the estimate in any case\n"
            "--fidelity LEVEL    full (default), fixed-mem, functional or sampled: cheaper models,\n"
            "                    each result with its error estimate and flag (docs/fidelity.md)\n"
            "--accuracy P%%       pick the cheapest level expected within P%% (falls back to full)\n"
            "--sample-rate R     sampled: fraction of the pixels modelled (0 < R <= 1; default 1/16)\n"
"--help-module NAME  parameters, ports and statistics of a module (trv, ist, sched,\n"
            "                    cache, arbiter, fixed_mem, dram, ...) and the keys of its\n"
            "                    configuration section (node_l1, node_l2, prim, memory, fifo, machine,\n"
            "                    dram)\n");
}

static int bad(const char *fmt, const char *a, const char *b)
{
    fprintf(stderr, "rtsim: ");
    fprintf(stderr, fmt, a, b);
    fprintf(stderr, "\n(see rtsim --help)\n");
    return 2;
}

static bool parse_u64(const char *s, uint64_t lo, uint64_t hi, uint64_t *out)
{
    if (!s || !*s || *s == '-')
        return false;
    char *end;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (errno || *end || v < lo || v > hi)
        return false;
    *out = v;
    return true;
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
    char err[512];
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
    for (int i = 0; d && d->config_sections && i < rtcfg_schema_count(cfg); i++) {
        const rtcfg_schema *s = rtcfg_schema_at(cfg, i);
        size_t n = strlen(s->section);
        for (const char *c = d->config_sections; c; c = strchr(c, ',') ? strchr(c, ',') + 1 : NULL)
            if (!strncmp(c, s->section, n) && (c[n] == ',' || c[n] == 0)) {
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

static double wall(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU time of this process: the run's cost on one core, even on a loaded host. */
static double cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void progress_cb(void *user, uint64_t cycle, uint64_t done, uint64_t admitted)
{
    progress_state *p = user;
    if (p->lines) {
        double now = wall();
        if (now - p->last >= p->every) {
            p->last = now;
            fprintf(stderr, "rtsim: progress: cycle %llu (~%.0f%% of the estimate), %llu rays done, %llu/%llu "
                            "primaries admitted, %.0f s\n",
                    (unsigned long long)cycle, p->est_cycles > 0 ? 100.0 * (double)cycle / p->est_cycles : 0.0,
                    (unsigned long long)done, (unsigned long long)(admitted < p->total ? admitted : p->total),
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
    int bars = (int)(frac * 30.0);
    char bar[31];
    for (int i = 0; i < 30; i++)
        bar[i] = i < bars ? '#' : '.';
    bar[30] = 0;
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

/* The provenance of a run (docs/results.md) that the options and the scene give. */
static void fill_run(cli_run_info *run, const char *scene_name, const char *views_file, const rt_view *view,
                     const rt_scene *sc, const char *machine, const rtcfg *cfg, uint32_t w, uint32_t h, bool diffuse,
                     long bounces, uint64_t seed)
{
    run->scene = scene_name, run->views_file = views_file, run->view = view->name;
    run->has_mesh_hash = true, run->mesh_hash = rt_mesh_hash(&sc->mesh);
    run->machine = machine;
    run->has_config_hash = cli_run_config_hash(cfg, &run->config_hash);
    run->width = w, run->height = h, run->rays = diffuse ? "diffuse" : "primary";
    run->has_bounces = diffuse, run->bounces = (uint32_t)bounces;
    run->has_seed = diffuse, run->seed = seed;
}

/* A cheaper fidelity level or --accuracy (fidelity.h): runs, prints the
 * summary and writes the JSON. Returns the exit status. */
static int run_fidelity(rtcfg *cfg, const rt_scene *sc, const rt_view *view, const rt_bvh_image *img, uint32_t w,
                        uint32_t h, bool diffuse, uint32_t bounces, uint64_t seed, fid_level level, double accuracy,
                        double sample_rate, bool quiet, cli_run_info *run, ks_out *json)
{
    char err[8192];
    fid_job job = {cfg, &sc->mesh, view, img, w, h, diffuse, bounces, seed, sample_rate, NULL, NULL};
    fid_outcome fo;
    double t0 = wall(), c0 = cpu();
    int rc = fid_run(&job, level, accuracy, &fo, err, sizeof err);
    double host_s = wall() - t0, cpu_s = cpu() - c0;
    if (rc)
        fprintf(stderr, "rtsim: %s\n", err);
    if (!quiet && (rc == 0 || fo.top)) {
        printf("scene       %s, view %s, %ux%u, %s rays\n", sc->name, view->name, w, h, diffuse ? "diffuse" : "primary");
        printf("BVH         %u nodes x %u B, %u triangles\n", img->nnodes, img->node_bytes, img->ntris);
        fid_outcome_print(&fo, stdout);
        fid_print_summary(&fo.res, stdout);
        printf("host        %.3f s CPU (%.3f s wall), %.0f K rays/s (CPU)\n", cpu_s, host_s,
               cpu_s > 0 ? fo.rays / cpu_s / 1e3 : 0.0);
    }
    if (json && (rc == 0 || fo.top)) {
        char jhead[4096];
        fid_json_strings(&fo.res, jhead, sizeof jhead);
        run->has_sim = true, run->sim_cpu_s = cpu_s, run->sim_wall_s = host_s;
        if (write_json(fid_outcome_stats(&fo), run, jhead, json, NULL, err, sizeof err)) {
            fprintf(stderr, "rtsim: %s\n", err);
            rc = rc ? rc : 2;
        }
    }
    fid_outcome_free(&fo);
    return rc;
}

/* Bad usage inside main: free the --set list, print, exit 2. */
#define USAGE_ERR(...)                                                                                                 \
    do {                                                                                                               \
        free(sets);                                                                                                    \
        return bad(__VA_ARGS__);                                                                                       \
    } while (0)

int main(int argc, char **argv)
{
    static cli_run_info run;   /* provenance of the JSON (cli/run_info.h) */
    cli_run_init(&run, "rtsim", argc, argv);
    const char *scene_name = "interior", *view_name = NULL, *views_file = NULL, *machine = "mbvh4";
    const char *json = NULL, *vcd = NULL, *vcd_filter = NULL, *heatmap = NULL, *autosize = NULL;
    const char *res = "1280x720";
    bool diffuse = false, occlusion = false, quiet = false, exhaustive = false, progress = false;
    fid_level level = FID_FULL;
    double accuracy = 0, sample_rate = 0;
    uint64_t bounces = 4, seed = 1, vcd_a = 0, vcd_b = 0;
    const char **sets = calloc((size_t)argc, sizeof *sets);
    int nsets = 0;
    bool vcd_window = false;
    ks_interrupt_install("rtsim");
    enum { O_VIEW = 256, O_VIEWS, O_MACHINE, O_RAYS, O_RES, O_BOUNCES, O_SEED, O_SET, O_JSON, O_VCD, O_VCDW, O_VCDF,
           O_HEAT, O_AUTO, O_HELPMOD, O_QUIET, O_EXHAUSTIVE, O_HELP, O_VERSION, O_PROGRESS,
           O_FIDELITY, O_ACCURACY, O_SAMPLE };
    static const struct option opts[] = {
        {"view", required_argument, 0, O_VIEW},        {"views", required_argument, 0, O_VIEWS},
        {"machine", required_argument, 0, O_MACHINE},  {"rays", required_argument, 0, O_RAYS},
        {"res", required_argument, 0, O_RES},          {"bounces", required_argument, 0, O_BOUNCES},
        {"seed", required_argument, 0, O_SEED},        {"set", required_argument, 0, O_SET},
        {"json", required_argument, 0, O_JSON},        {"vcd", required_argument, 0, O_VCD},
        {"vcd-window", required_argument, 0, O_VCDW},  {"vcd-filter", required_argument, 0, O_VCDF},
        {"heatmap", required_argument, 0, O_HEAT},     {"autosize-fifos", required_argument, 0, O_AUTO},
        {"help-module", required_argument, 0, O_HELPMOD}, {"quiet", no_argument, 0, O_QUIET}, {"exhaustive", no_argument, 0, O_EXHAUSTIVE},
        {"help", no_argument, 0, O_HELP},              {"version", no_argument, 0, O_VERSION},
        {"progress", no_argument, 0, O_PROGRESS},
        {"fidelity", required_argument, 0, O_FIDELITY}, {"accuracy", required_argument, 0, O_ACCURACY},
        {"sample-rate", required_argument, 0, O_SAMPLE},
        {0, 0, 0, 0}};
    if (!sets)
        return 2;
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        switch (c) {
        case O_VIEW: view_name = optarg; break;
        case O_VIEWS: views_file = optarg; break;
        case O_MACHINE: machine = optarg; break;
        case O_RAYS:
            diffuse = !strcmp(optarg, "diffuse");
            occlusion = !strcmp(optarg, "occlusion");   /* AO rays of the primary hits (docs/accel.md) */
            if (strcmp(optarg, "primary") && !diffuse && !occlusion)
                USAGE_ERR("--rays %s: allowed values are primary, diffuse, occlusion%s", optarg, "");
            break;
        case O_RES: res = optarg; break;
        case O_BOUNCES:
            if (!parse_u64(optarg, 0, 64, &bounces))
                USAGE_ERR("--bounces %s: allowed range 0..64%s", optarg, "");
            break;
        case O_SEED:
            if (!parse_u64(optarg, 0, UINT64_MAX, &seed))
                USAGE_ERR("--seed %s: expected a non-negative integer%s", optarg, "");
            break;
        case O_SET: sets[nsets++] = optarg; break;
        case O_JSON: json = optarg; break;
        case O_VCD: vcd = optarg; break;
        case O_VCDW: {
            char a[32] = "", *colon = strchr(optarg, ':');
            if (!colon || (size_t)(colon - optarg) >= sizeof a)
                USAGE_ERR("--vcd-window %s: expected A:B (cycles, A < B)%s", optarg, "");
            memcpy(a, optarg, (size_t)(colon - optarg));
            a[colon - optarg] = 0;
            if (!parse_u64(a, 0, UINT64_MAX / 4, &vcd_a) || !parse_u64(colon + 1, 1, UINT64_MAX / 4, &vcd_b) ||
                vcd_b <= vcd_a)
                USAGE_ERR("--vcd-window %s: expected A:B (cycles, A < B)%s", optarg, "");
            vcd_window = true;
            break;
        }
        case O_VCDF: vcd_filter = optarg; break;
        case O_HEAT: heatmap = optarg; break;
        case O_AUTO: autosize = optarg; break;
        case O_HELPMOD: free(sets); return help_module(optarg);
        case O_QUIET: quiet = true; break;
        case O_EXHAUSTIVE: exhaustive = true; break;
        case O_PROGRESS: progress = true; break;
        case O_FIDELITY:
            if (!fid_level_parse(optarg, &level))
                USAGE_ERR("--fidelity %s: allowed values are full, fixed-mem, functional, sampled%s", optarg, "");
            break;
        case O_ACCURACY:
            if (!fid_accuracy_parse(optarg, &accuracy))
                USAGE_ERR("--accuracy %s: expected a percentage in (0, 100], e.g. 2%%%s", optarg, "");
            break;
        case O_SAMPLE: {
            char *end;
            sample_rate = strtod(optarg, &end);
            if (end == optarg || *end || !(sample_rate > 0) || sample_rate > 1)
                USAGE_ERR("--sample-rate %s: allowed range 0 < R <= 1%s", optarg, "");
            break;
        }
        case O_HELP: usage(stdout); free(sets); return 0;
        case O_VERSION: printf("rtsim %s (git %s)\n", RTSIM_VERSION, RTSIM_GIT); free(sets); return 0;
        case '?':
        default:
            free(sets);
            /* a long option's optopt is its code (>= 256), not a character */
            if (optopt && optopt < 256)
                fprintf(stderr, "rtsim: option needs a value or is unknown: -%c\n", optopt);
            else
                fprintf(stderr, "rtsim: unknown option or missing value: %s\n", argv[optind - 1]);
            usage(stderr);
            return 2;
        }
    }
    if (optind < argc)
        scene_name = argv[optind++];
    if (optind < argc) {
        USAGE_ERR("unexpected argument %s (one SCENE only)%s", argv[optind], "");
    }
    if (!vcd && (vcd_window || vcd_filter)) {
        USAGE_ERR("%s: only with --vcd FILE (no waveform is written without it)%s",
                  vcd_window ? "--vcd-window" : "--vcd-filter", "");
    }
    if ((level != FID_FULL || accuracy > 0) && occlusion) {
        USAGE_ERR("--rays occlusion needs --fidelity full (%s asked)%s",
                  accuracy > 0 ? "--accuracy" : fid_level_name(level), "");
    }
    if ((level != FID_FULL || accuracy > 0) && (vcd || heatmap || autosize || exhaustive)) {
        USAGE_ERR("--vcd, --heatmap, --autosize-fifos and --exhaustive need --fidelity full (%s asked)%s",
                  accuracy > 0 ? "--accuracy" : fid_level_name(level), "");
    }
    if (heatmap && !rt_image_format_supported(heatmap)) {
        USAGE_ERR("--heatmap %s: the file must end in .png or .exr%s", heatmap, "");
    }

    char err[8192];
    int rc = 2;
    rtcfg *cfg = make_cfg(err, sizeof err);
    rt_scene sc;
    memset(&sc, 0, sizeof sc);
    rt_bvh_image img;
    memset(&img, 0, sizeof img);
    rtsim_frame frame;
    memset(&frame, 0, sizeof frame);
    accel_top *top = NULL;
    uint32_t w = 0, h = 0;
    if (!cfg)
        goto fail;
    if (rtcfg_load(cfg, machine, err, sizeof err))
        goto fail;
    for (int i = 0; i < nsets; i++)
        if (rtcfg_set(cfg, sets[i], err, sizeof err))
            goto fail;
    if (rtcfg_finish(cfg, err, sizeof err))
        goto fail;
    if (!rt_parse_resolution(res, &w, &h, err, sizeof err))
        goto fail;
    /* every output before the scene is loaded: the VCD writer finds its
     * plan by path (kernel/vcd.h) */
    cli_output outs[4] = {{"--json", json, NULL}, {"--vcd", vcd, NULL}, {"--heatmap", heatmap, NULL},
                          {"--autosize-fifos", autosize, NULL}};
    if (!cli_plan_outputs(outs, 4, err, sizeof err))
        goto fail;
    if (!rt_scene_load(scene_name, &sc, err, sizeof err))
        goto fail;
    if (views_file && !rt_scene_set_views_file(&sc, views_file, err, sizeof err))
        goto fail;
    const rt_view *view = rt_scene_view(&sc, view_name, err, sizeof err);
    if (!view)
        goto fail;
    rt_bvh_params bp;
    rt_bvh_params_default(&bp);
    bp.width = (int)rtcfg_int(cfg, "machine.branching");
    if (!rt_bvh_build(&sc.mesh, &bp, &img, NULL, err, sizeof err))
        goto fail;
    accel_source src;
    if (!rtsim_frame_init(&frame, &sc.mesh, view, w, h, diffuse, (uint32_t)bounces, seed, heatmap != NULL, &src, err,
                          sizeof err))
        goto fail;
    if (occlusion && !rtsim_frame_occlusion(&frame, &img, RT_AO_SAMPLES_DEFAULT, &src, err, sizeof err))
        goto fail;
    if (level != FID_FULL || accuracy > 0) {
        /* a cheaper level or the automatic choice: fidelity/ runs it */
        fill_run(&run, scene_name, views_file, view, &sc, machine, cfg, w, h, diffuse, bounces, seed);
        rc = run_fidelity(cfg, &sc, view, &img, w, h, diffuse, (uint32_t)bounces, seed, level, accuracy, sample_rate,
                          quiet, &run, json ? outs[0].out : NULL);
        goto done;
    }
    accel_image aimg = rtsim_image(&img);
    accel_top_opts o = {0};
    o.vcd_path = vcd;
    o.vcd_begin_cycle = vcd_a;
    o.vcd_end_cycle = vcd_b;
    o.vcd_filter = vcd_filter;
    o.exhaustive = exhaustive;
    top = accel_top_create(cfg, &aimg, &src, &o, err, sizeof err);
    if (!top)
        goto fail;
    fid_result fres;
    fid_result_full(&fres);
    if (fid_register_stats(&fres, accel_top_stats(top))) {
        snprintf(err, sizeof err, "fidelity statistics: %s", ks_stats_error(accel_top_stats(top)));
        goto fail;
    }
    progress_state ps = {!quiet && isatty(2), false, 0, 0, 0, src.primary_count, wall(), &src};
    {
        /* the estimate: said before a long run starts, and with --progress */
        rtsim_estimate_params ep;
        char eerr[1200];
        if (!rtsim_estimate_load(&ep, eerr, sizeof eerr)) {
            fprintf(stderr, "rtsim: warning: no run-time estimate: %s\n", eerr);
        } else {
            rt_trv_params tp;
            rt_trv_params_default(&tp, img.width);
            tp.stack_depth = (int)accel_top_params(top)->trv.core.stack_depth;
            tp.distance_cull = accel_top_params(top)->trv.core.distance_cull;
            rtsim_estimate est;
            rtsim_estimate_frame(&ep, &frame, &img, &tp, accel_top_params(top)->trv_count, exhaustive, &est);
            if (progress || est.host_s >= ep.announce_s) {
                char d[32];
                rtsim_estimate_duration(est.host_s, d, sizeof d);
                fprintf(stderr, "rtsim: estimate: ~%.0f rays, ~%.3g simulated cycles, ~%s of host time (%s%s)%s\n",
                        est.rays, est.cycles, d, diffuse ? "diffuse" : "primary", exhaustive ? ", exhaustive" : "",
                        est.host_s >= ep.announce_s && !progress ? "; --progress prints progress lines" : "");
            }
            ps.lines = progress && !isatty(2);
            ps.every = ep.progress_s;
            ps.last = ps.t0;
            ps.est_cycles = est.cycles;
        }
    }
    double t0 = wall(), c0 = cpu();
    ks_interrupt_polling(true);   /* accel_top_run checks ks_interrupted() every slice */
    int run_rc = accel_top_run(top, progress_cb, &ps, err, sizeof err);
    double host_s = wall() - t0, cpu_s = cpu() - c0;
    if (ps.on)
        fprintf(stderr, "\r%70s\r", "");
    const int sig = ks_interrupted();
    char reason[160] = "";
    if (sig)
        snprintf(reason, sizeof reason, "interrupted by %s at cycle %llu", ks_interrupt_name(sig),
                 (unsigned long long)accel_top_cycles(top));
    rc = run_rc ? 1 : 0;
    if (run_rc && !sig)
        fprintf(stderr, "rtsim: %s\n", err);
    if (!quiet) {
        printf("scene       %s, view %s, %ux%u, %s rays\n", sc.name, view->name, w, h,
               diffuse ? "diffuse" : occlusion ? "occlusion" : "primary");
        printf("BVH         %u nodes x %u B, %u triangles\n", img.nnodes, img.node_bytes, img.ntris);
        if (sig)
            printf("PARTIAL     %s: the figures cover the run until then\n", reason);
        accel_top_print_summary(top, stdout);
        fid_print_summary(&fres, stdout);
        printf("host        %.3f s CPU (%.3f s wall), %.2f M simulated cycles/s, %.0f K rays/s (CPU)\n", cpu_s, host_s,
               cpu_s > 0 ? (double)accel_top_cycles(top) / cpu_s / 1e6 : 0.0,
               cpu_s > 0 ? (double)accel_top_rays(top) / cpu_s / 1e3 : 0.0);
    }
    char jhead[4096];
    fid_json_strings(&fres, jhead, sizeof jhead);
    /* provenance (docs/results.md) */
    fill_run(&run, scene_name, views_file, view, &sc, machine, cfg, w, h, diffuse, bounces, seed);
    run.rays = occlusion ? "occlusion" : run.rays;
    run.has_sim = true, run.sim_cpu_s = cpu_s, run.sim_wall_s = host_s;
    run.has_cycles = true, run.cycles = accel_top_cycles(top);
    if (json && write_json(accel_top_stats(top), &run, jhead, outs[0].out, sig ? reason : NULL, err, sizeof err)) {
        fprintf(stderr, "rtsim: %s\n", err);
        rc = rc ? rc : 2;
    }
    if (heatmap && !sig) {   /* an image cannot say it is partial: none from a cut run */
        float lo, hi;
        rt_image_value_range(frame.pixel_cycles, (size_t)w * h, &lo, &hi);
        const char *stage = ks_out_stage(outs[2].out, err, sizeof err);
        if (!stage ||
            !rt_image_write_heatmap(stage, frame.pixel_cycles, w, h, lo, hi, RT_COLORMAP_VIRIDIS, err, sizeof err) ||
            ks_out_commit(outs[2].out, err, sizeof err)) {
            fprintf(stderr, "rtsim: --heatmap %s: %s\n", heatmap, err);
            ks_out_discard(outs[2].out);
            rc = rc ? rc : 2;
        }
    }
    if (autosize && run_rc == 0) {
        FILE *af = NULL;
        if (accel_top_autosize(top, cfg, err, sizeof err) || !(af = ks_out_begin(outs[3].out, err, sizeof err)) ||
            (rtcfg_write_ini_file(cfg, af), ks_out_commit(outs[3].out, err, sizeof err))) {
            fprintf(stderr, "rtsim: --autosize-fifos %s\n", err);
            ks_out_discard(outs[3].out);
            rc = rc ? rc : 2;
        } else if (!quiet) {
            printf("FIFOs       sized configuration written to %s\n", autosize);
        }
    }
    if (sig) {
        /* autosizing from a cut run would size for part of the frame */
        fflush(stdout);
        fprintf(stderr, "rtsim: %s; %s%s%s%s\n", reason, vcd ? "the VCD ends there, " : "",
                json ? "the JSON statistics are marked partial" : "statistics above are partial",
                autosize ? ", no --autosize-fifos file written" : "", heatmap ? ", no heatmap written" : "");
        rc = ks_interrupt_exit_status();
    }
    goto done;
fail:
    fprintf(stderr, "rtsim: %s\n", err);
    rc = 2;
done:
    ks_out_discard_all();   /* outputs not committed (failure, interruption): no temporaries left */
    accel_top_destroy(top);
    rtsim_frame_free(&frame);
    rt_bvh_image_free(&img);
    rt_scene_free(&sc);
    if (cfg)
        rtcfg_destroy(cfg);
    free(sets);
    return rc;
}
