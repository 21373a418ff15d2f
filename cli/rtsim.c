/* rtsim — runs the cycle-level accelerator model on a scene (docs/design.md
 * "Command-line conventions"): builds the scene's BVH for the machine's
 * width, feeds primary (or diffuse path) rays through the model and prints
 * cycles, MRPS, utilization, cache hit rates, DRAM traffic and rays in flight.
 * Exit status: 0 success, 1 simulation failure (deadlock, stack overflow),
 * 2 bad usage or input. Outputs are written to a temporary name and renamed. */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli/rtsim_frame.h"
#include "fidelity/fidelity.h"
#include "kernel/stats.h"
#include "model/accel_config.h"
#include "model/accel_top.h"
#include "model/config.h"
#include "model/memsys_config.h"
#include "tracer/bvh.h"
#include "tracer/image.h"
#include "tracer/scene.h"

#include "cli/output_path.h"
#include "cli/version.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: rtsim [SCENE] [--view NAME] [--views FILE] [--machine bvh2|mbvh4|FILE.ini]\n"
            "             [--rays primary|diffuse] [--res WxH] [--bounces N] [--seed N]\n"
            "             [--set KEY=VALUE]... [--json FILE] [--vcd FILE] [--vcd-window A:B]\n"
            "             [--vcd-filter GLOB] [--heatmap FILE] [--autosize-fifos OUT.ini]\n"
            "             [--help-module NAME] [--quiet] [--exhaustive] [--help] [--version]\n"
            "             [--fidelity full|fixed-mem|functional|sampled] [--accuracy P%%]\n"
            "             [--sample-rate R]\n"
            "SCENE: a built-in scene (interior, hairball, city, forest; default interior) or an\n"
            "       .obj/.ply(.gz)/.scene file. Defaults: 1280x720, mbvh4, primary rays,\n"
            "       4 bounces, seed 1.\n"
            "--set KEY=VALUE     override a machine key (e.g. trv.count=8); see --help-module\n"
            "--json FILE         every statistic (with units and descriptions) as JSON\n"
            "--vcd FILE          waveforms of all units; --vcd-window A:B limits them to cycles\n"
            "                    [A, B), --vcd-filter a comma-separated list of globs\n"
            "--heatmap FILE      simulated cycles per pixel (.png or .exr)\n"
            "--autosize-fifos F  run, then write the machine with every FIFO shrunk to the\n"
            "                    first power of two above its maximum occupancy (paper sec. 3)\n"
            "--exhaustive        step every unit every cycle (no idle skipping; reference mode)\n"
            "--fidelity LEVEL    full (default), fixed-mem, functional or sampled: cheaper models,\n"
            "                    each result with its error estimate and flag (docs/fidelity.md)\n"
            "--accuracy P%%       pick the cheapest level expected within P%% (falls back to full)\n"
            "--sample-rate R     sampled: fraction of the pixels modelled (0 < R <= 1; default 1/16)\n"
"--help-module NAME  parameters, ports and statistics of a module (trv, ist, sched,\n"
            "                    cache, arbiter, fixed_mem, dram, ...) and the keys of its\n"
            "                    configuration section (node_l1, node_l2, prim, memory, fifo, machine)\n");
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
    if (!cfg) {
        fprintf(stderr, "rtsim: %s\n", err);
        return 2;
    }
    int found = 0;
    const ks_module_desc *d = accel_module_desc(name);
    if (d) {
        ks_module_desc_print(d, stdout);
        found = 1;
    }
    for (int i = 0; i < rtcfg_schema_count(cfg); i++) {
        const rtcfg_schema *s = rtcfg_schema_at(cfg, i);
        if (!strcmp(s->section, name)) {
            if (found)
                printf("\n");
            printf("Configuration keys [%s]:\n", s->section);
            rtcfg_print_schema(stdout, s, NULL);
            found = 1;
        }
    }
    rtcfg_destroy(cfg);
    if (!found) {
        fprintf(stderr, "rtsim: --help-module %s: no such module; modules: ", name);
        accel_module_list(stderr);
        fprintf(stderr, "; configuration sections: node_l1, node_l2, prim, memory, fifo, machine, trv, ist, sched\n");
        return 2;
    }
    return 0;
}

typedef struct progress_state {
    bool on;
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

/* head: JSON members put first (the fidelity strings, fidelity.h). */
static int write_json(ks_stats *st, const char *path, const char *head, char *err, size_t errlen)
{
    char tmp[4096];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (!f) {
        snprintf(err, errlen, "--json %s: cannot create: %s", path, strerror(errno));
        return -1;
    }
    char *mem = NULL;
    size_t memlen = 0;
    FILE *ms = open_memstream(&mem, &memlen);
    int rc = ms ? ks_stats_write_json(st, ms) : -1;
    if (ms && fclose(ms))
        rc = -1;
    if (rc == 0 && mem && !strncmp(mem, "{\n", 2))
        rc = fputs("{\n", f) < 0 || fputs(head, f) < 0 || fputs(mem + 2, f) < 0 ? -1 : 0;
    else if (rc == 0 && mem)
        rc = fputs(mem, f) < 0 ? -1 : 0;
    free(mem);
    if (fclose(f) || rc) {
        remove(tmp);
        snprintf(err, errlen, "--json %s: write error", path);
        return -1;
    }
    if (rename(tmp, path)) {
        remove(tmp);
        snprintf(err, errlen, "--json %s: cannot rename: %s", path, strerror(errno));
        return -1;
    }
    return 0;
}

/* A cheaper fidelity level or --accuracy (fidelity.h): runs, prints the
 * summary and writes the JSON. Returns the exit status. */
static int run_fidelity(rtcfg *cfg, const rt_scene *sc, const rt_view *view, const rt_bvh_image *img, uint32_t w,
                        uint32_t h, bool diffuse, uint32_t bounces, uint64_t seed, fid_level level, double accuracy,
                        double sample_rate, bool quiet, const char *json)
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
        if (write_json(fid_outcome_stats(&fo), json, jhead, err, sizeof err)) {
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
    const char *scene_name = "interior", *view_name = NULL, *views_file = NULL, *machine = "mbvh4";
    const char *json = NULL, *vcd = NULL, *vcd_filter = NULL, *heatmap = NULL, *autosize = NULL;
    const char *res = "1280x720";
    bool diffuse = false, quiet = false, exhaustive = false;
    fid_level level = FID_FULL;
    double accuracy = 0, sample_rate = 0;
    uint64_t bounces = 4, seed = 1, vcd_a = 0, vcd_b = 0;
    const char **sets = calloc((size_t)argc, sizeof *sets);
    int nsets = 0;
    enum { O_VIEW = 256, O_VIEWS, O_MACHINE, O_RAYS, O_RES, O_BOUNCES, O_SEED, O_SET, O_JSON, O_VCD, O_VCDW, O_VCDF,
           O_HEAT, O_AUTO, O_HELPMOD, O_QUIET, O_EXHAUSTIVE, O_HELP, O_VERSION, O_FIDELITY, O_ACCURACY, O_SAMPLE };
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
            if (!strcmp(optarg, "primary"))
                diffuse = false;
            else if (!strcmp(optarg, "diffuse"))
                diffuse = true;
            else
                USAGE_ERR("--rays %s: allowed values are primary, diffuse%s", optarg, "");
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
            break;
        }
        case O_VCDF: vcd_filter = optarg; break;
        case O_HEAT: heatmap = optarg; break;
        case O_AUTO: autosize = optarg; break;
        case O_HELPMOD: free(sets); return help_module(optarg);
        case O_QUIET: quiet = true; break;
        case O_EXHAUSTIVE: exhaustive = true; break;
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
            if (optopt)
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
    if (!cli_output_path_ok("--json", json, err, sizeof err) || !cli_output_path_ok("--vcd", vcd, err, sizeof err) ||
        !cli_output_path_ok("--heatmap", heatmap, err, sizeof err) ||
        !cli_output_path_ok("--autosize-fifos", autosize, err, sizeof err))
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
    if (level != FID_FULL || accuracy > 0) {
        /* a cheaper level or the automatic choice: fidelity/ runs it */
        rc = run_fidelity(cfg, &sc, view, &img, w, h, diffuse, (uint32_t)bounces, seed, level, accuracy, sample_rate,
                          quiet, json);
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
    progress_state ps = {!quiet && isatty(2), src.primary_count, wall(), &src};
    double t0 = wall(), c0 = cpu();
    int run_rc = accel_top_run(top, progress_cb, &ps, err, sizeof err);
    double host_s = wall() - t0, cpu_s = cpu() - c0;
    if (ps.on)
        fprintf(stderr, "\r%70s\r", "");
    rc = run_rc ? 1 : 0;
    if (run_rc)
        fprintf(stderr, "rtsim: %s\n", err);
    if (!quiet) {
        printf("scene       %s, view %s, %ux%u, %s rays\n", sc.name, view->name, w, h, diffuse ? "diffuse" : "primary");
        printf("BVH         %u nodes x %u B, %u triangles\n", img.nnodes, img.node_bytes, img.ntris);
        accel_top_print_summary(top, stdout);
        fid_print_summary(&fres, stdout);
        printf("host        %.3f s CPU (%.3f s wall), %.2f M simulated cycles/s, %.0f K rays/s (CPU)\n", cpu_s, host_s,
               cpu_s > 0 ? (double)accel_top_cycles(top) / cpu_s / 1e6 : 0.0,
               cpu_s > 0 ? (double)accel_top_rays(top) / cpu_s / 1e3 : 0.0);
    }
    char jhead[4096];
    fid_json_strings(&fres, jhead, sizeof jhead);
    if (json && write_json(accel_top_stats(top), json, jhead, err, sizeof err)) {
        fprintf(stderr, "rtsim: %s\n", err);
        rc = rc ? rc : 2;
    }
    if (heatmap) {
        float lo, hi;
        rt_image_value_range(frame.pixel_cycles, (size_t)w * h, &lo, &hi);
        if (!rt_image_write_heatmap(heatmap, frame.pixel_cycles, w, h, lo, hi, RT_COLORMAP_VIRIDIS, err, sizeof err)) {
            fprintf(stderr, "rtsim: --heatmap %s\n", err);
            rc = rc ? rc : 2;
        }
    }
    if (autosize && run_rc == 0) {
        if (accel_top_autosize(top, cfg, err, sizeof err) || rtcfg_write_ini(cfg, autosize, err, sizeof err)) {
            fprintf(stderr, "rtsim: --autosize-fifos %s\n", err);
            rc = rc ? rc : 2;
        } else if (!quiet) {
            printf("FIFOs       sized configuration written to %s\n", autosize);
        }
    }
    goto done;
fail:
    fprintf(stderr, "rtsim: %s\n", err);
    rc = 2;
done:
    accel_top_destroy(top);
    rtsim_frame_free(&frame);
    rt_bvh_image_free(&img);
    rt_scene_free(&sc);
    if (cfg)
        rtcfg_destroy(cfg);
    free(sets);
    return rc;
}
