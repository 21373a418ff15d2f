/* rttrace — the software ray tracer's command-line tool (docs/design.md
 * "Command-line conventions"): loads a scene, builds the BVH, traces a view's
 * primary rays, diffuse paths or the ambient-occlusion rays of the primary
 * hits (any-hit, tracer/trace/occlusion.h) with the reference traversal (the hardware's
 * algorithm, tracer/trace/traverse.h), optionally compares every ray with Embree,
 * and writes the trace log, the shaded frame, per-pixel heatmaps of node
 * visits and triangle tests, and statistics (--json).
 *   rttrace SCENE [options]            trace (see usage())
 *   rttrace SCENE --read-log FILE      validate a trace log against the scene
 * Exit: 0 ok, 1 validation failure (an unexplained Embree mismatch, a stack
 * overflow), 2 bad usage or input (message names the option or file),
 * 130/143 interrupted (Ctrl-C/SIGTERM: the JSON holds the statistics so far
 * marked "partial"; no log or image is written).
 * Every output is planned before any work through the output layer
 * (kernel/out_file.h): temporary name and rename for files, in place for
 * stdout "-", devices and pipes, two outputs naming one file refused; on an
 * error the outputs of this run are removed. Deterministic: the same
 * arguments give the same counts, images and log bytes. */
#include <inttypes.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "tracer/trace/bounce.h"
#include "tracer/bvh/bvh.h"
#include "tracer/trace/camera.h"
#include "tracer/check/embree_check.h"
#include "tracer/io/image.h"
#include "tracer/io/mesh.h"
#include "tracer/trace/occlusion.h"
#include "tracer/io/scene.h"
#include "tracer/trace/shade.h"
#include "tracer/log/trace_log.h"
#include "tracer/trace/traverse.h"

#include "cli/json.h"
#include "cli/options.h"
#include "cli/output_path.h"
#include "cli/progress.h"
#include "cli/run_info.h"
#include "cli/version.h"
#include "kernel/interrupt.h"

#define BOUNCES_MAX 32            /* rt_ray.bounce is 8 bits; 32 is far beyond the paper's 4 */

static double now_s(void) { return cli_run_clock(CLOCK_MONOTONIC); }

/* ---- options ---- */

typedef struct options {
    const char *scene, *view, *views, *log, *image, *hm_visits, *hm_tris, *json, *read_log;
    int width;              /* BVH width (--bvh) */
    uint64_t leaf_size, stack_depth, bounces, seed;
    int rays;               /* index in ray_kinds */
    int builder;            /* index in builder_kinds = rt_build_kind */
    bool diffuse, occlusion, check_embree, quiet;
    bool bvh_given, rays_given, res_given, bounces_given, stack_given;   /* on the command line */
    ks_out *out_log, *out_image, *out_hm_visits, *out_hm_tris, *out_json;   /* output plans */
    struct resolution {
        uint32_t w, h;
    } res;
    double max_mismatch_rate;
} options;

enum { RAYS_PRIMARY, RAYS_DIFFUSE, RAYS_OCCLUSION };
static const char *const ray_kinds[] = {"primary", "diffuse", "occlusion", NULL};
/* --builder, in rt_build_kind order (tracer/bvh/bvh.h) */
static const char *const builder_kinds[] = {"collapse", "wald", NULL};

/* --bvh: bvh2 or mbvhN, N = 2..8 (the width) */
static bool parse_bvh(const char *text, void *to, char *err, size_t errlen)
{
    (void)err, (void)errlen;
    int *width = to;
    if (strcmp(text, "bvh2") == 0) {
        *width = 2;
        return true;
    }
    if (strncmp(text, "mbvh", 4) == 0 && text[4] >= '2' && text[4] <= '8' && text[5] == 0) {
        *width = text[4] - '0';
        return true;
    }
    return false;
}

/* --res: WxH (tracer/trace/camera.h) */
static bool parse_res(const char *text, void *to, char *err, size_t errlen)
{
    struct resolution *r = to;
    return rt_parse_resolution(text, &r->w, &r->h, err, errlen);
}

/* Reads argv into o, checks the combinations and plans every output before
 * any work (kernel/out_file.h): CLI_GO_ON to run, else the exit status
 * (0 after --help or --version, 2 with a message naming the option). */
static int parse_options(int argc, char **argv, options *o)
{
    const cli_opt table[] = {
        {.name = "view", .kind = CLI_STRING, .to.str = &o->view, .arg = "NAME",
         .help = "view to render (default: the scene's first)"},
        {.name = "views", .kind = CLI_STRING, .to.str = &o->views, .arg = "FILE",
         .help = "views.txt-format file replacing the scene's views"},
        {.name = "bvh", .kind = CLI_CUSTOM, .to.custom = &o->width, .parse = parse_bvh, .arg = "bvh2|mbvh4|mbvhN",
         .def = "mbvh4", .given = &o->bvh_given, .what = "is not a BVH type; allowed: bvh2, mbvh4, mbvhN with N = 2..8",
         .help = "BVH width, N = 2..8 (default {default})"},
        {.name = "builder", .kind = CLI_CHOICE, .to.choice = &o->builder, .choices = builder_kinds,
         .def = "collapse", .what = "is not a builder; allowed: %s",
         .help = "how an MBVH is made from the SAH sweep: collapse, or wald (top-down splitting,\n"
                 "leaves cut by size only; docs/tracer-bvh.md); a BVH2 ignores it (default {default})"},
        {.name = "leaf-size", .kind = CLI_UINT, .to.u = &o->leaf_size, .arg = "N", .min = 1, .max = RT_LEAF_MAX,
         .def = "4", .help = "max triangles per leaf, {range} (default {default})"},
        {.name = "rays", .kind = CLI_CHOICE, .to.choice = &o->rays, .choices = ray_kinds, .def = "primary",
         .given = &o->rays_given, .what = "is not a ray type; allowed: %s",
         .help = "primary rays, diffuse paths, or primary rays and " CLI_STR(RT_AO_SAMPLES_DEFAULT) " ambient-\n"
                 "occlusion rays per hit, any hit ends them (default {default})"},
        {.name = "res", .kind = CLI_CUSTOM, .to.custom = &o->res, .parse = parse_res, .arg = "WxH",
         .def = CLI_STR(RT_DEFAULT_WIDTH) "x" CLI_STR(RT_DEFAULT_HEIGHT), .given = &o->res_given,
         .help = "resolution, 1..65535 each (default {default})"},
        {.name = "bounces", .kind = CLI_UINT, .to.u = &o->bounces, .arg = "N", .min = 0, .max = BOUNCES_MAX,
         .def = CLI_STR(RT_MAX_BOUNCES_DEFAULT), .given = &o->bounces_given,
         .help = "diffuse bounces per path, {range} (default {default})"},
        {.name = "seed", .kind = CLI_UINT, .to.u = &o->seed, .arg = "N", .min = 0, .max = UINT64_MAX, .def = "1",
         .help = "random seed of the bounces and AO rays, 0..2^64-1 (default {default})"},
        {.name = "stack-depth", .kind = CLI_UINT, .to.u = &o->stack_depth, .arg = "N", .min = 1, .max = 4096,
         .def = CLI_STR(RT_STACK_DEPTH_DEFAULT), .given = &o->stack_given,
         .help = "traversal stack entries, {range} (default {default}, the paper's);\n"
                 "a ray overflowing it is a validation failure (exit 1)"},
        {.name = "check-embree", .kind = CLI_FLAG, .to.flag = &o->check_embree,
         .help = "compare every ray's closest hit (occlusion rays: occluded or\n"
                 "not, rtcOccluded1) with Embree 3"},
        /* The tracer's target (docs/tracer-bvh.md): at least 99.999% of rays identical to Embree on the built-ins. */
        {.name = "max-mismatch-rate", .kind = CLI_REAL, .to.real = &o->max_mismatch_rate, .arg = "R", .lo = 0, .hi = 1,
         .def = "1e-05",
         .help = "fraction of rays with an explained difference from Embree (tie,\n"
                 "coplanar, gap, edge, t_round), {range}, above which a warning is\n"
                 "printed (default {default}); only an unexplained one ('other') fails"},
        {.name = "log", .kind = CLI_STRING, .to.str = &o->log, .arg = "FILE",
         .help = "write the binary trace log (docs/tracer-log.md)"},
        {.name = "image", .kind = CLI_STRING, .to.str = &o->image, .arg = "FILE", .help = "shaded frame (.png or .exr)"},
        {.name = "heatmap-visits", .kind = CLI_STRING, .to.str = &o->hm_visits, .arg = "FILE",
         .help = "node visits per pixel (.png or .exr; EXR keeps raw values)"},
        {.name = "heatmap-tris", .kind = CLI_STRING, .to.str = &o->hm_tris, .arg = "FILE",
         .help = "triangle tests per pixel (.png or .exr)"},
        {.name = "json", .kind = CLI_STRING, .to.str = &o->json, .arg = "FILE",
         .help = "statistics as one JSON object ('-' = stdout)"},
        {.name = "read-log", .kind = CLI_STRING, .to.str = &o->read_log, .arg = "FILE",
         .help = "validate FILE against SCENE's BVH instead of tracing"},
        {.name = "quiet", .kind = CLI_FLAG, .to.flag = &o->quiet, .help = "no summary, no progress bar"},
        {.name = "help", .kind = CLI_HELP, .help = ""},
        {.name = "version", .kind = CLI_VERSION},
        {0}};
    const cli_tool tool = {
        .name = "rttrace", .opts = table, .indent = 2, .column = 25,
        .about = "usage: rttrace SCENE [options]\n"
                 "       rttrace SCENE --read-log FILE [--bvh ...] [--leaf-size N] [--json FILE]\n"
                 "Traces a view of SCENE (built-in name: interior, hairball, city, forest; or "
                 ".obj/.ply[.gz]/.scene)\n"
                 "with the reference traversal of the accelerator.\n",
        .footer = "Exit status: 0 ok, 1 Embree check failed, 2 bad usage or input.\n",
        .bad_value = "%s: '%s' %s", .uint_what = "is not an integer in %s", .real_what = "is not a number in %s",
        .unknown = "unknown option %s", .missing = "%s needs a value", .hint = "(rttrace --help for usage)",
    };
    memset(o, 0, sizeof *o);
    int args, rc = cli_parse(&tool, argc, argv, &args);
    if (rc != CLI_GO_ON)
        return rc;
    if (args != argc - 1)
        return cli_usage_error(&tool, args == argc ? "missing SCENE argument"
                                                   : "expected one SCENE argument, got '%s' too",
                               args < argc - 1 ? argv[args + 1] : "");
    o->scene = argv[args];
    o->diffuse = o->rays == RAYS_DIFFUSE;
    o->occlusion = o->rays == RAYS_OCCLUSION;
    if (o->bounces_given && !o->diffuse)
        return cli_usage_error(&tool, "--bounces: only with --rays diffuse");
    if (o->occlusion && o->log)
        return cli_usage_error(&tool, "--log: not with --rays occlusion (trace logs hold primary rays and diffuse "
                                      "paths)");
    if (o->read_log && (o->log || o->image || o->hm_visits || o->hm_tris || o->check_embree || o->rays_given ||
                        o->res_given || o->view || o->views || o->stack_given || o->bounces_given))
        return cli_usage_error(&tool, "--read-log: only --bvh, --leaf-size, --json and --quiet apply (the log "
                                      "names its rays, resolution, view and seed)");
    /* every output before any work; the trace log and images are written
     * under the plan's staged name (writers that open by name) */
    cli_output outs[5] = {{"--log", o->log, NULL}, {"--image", o->image, NULL},
                          {"--heatmap-visits", o->hm_visits, NULL}, {"--heatmap-tris", o->hm_tris, NULL},
                          {"--json", o->json, NULL}};
    for (int i = 1; i <= 3; i++)   /* an image must have a supported extension */
        if (outs[i].path && !rt_image_format_supported(outs[i].path))
            return cli_usage_error(&tool, "%s %s: unsupported image type; allowed: .png, .exr", outs[i].opt,
                                   outs[i].path);
    char err[4600];
    if (!cli_plan_outputs(outs, 5, err, sizeof err))
        return cli_usage_error(&tool, "%s", err);
    o->out_log = outs[0].out, o->out_image = outs[1].out, o->out_hm_visits = outs[2].out;
    o->out_hm_tris = outs[3].out, o->out_json = outs[4].out;
    return CLI_GO_ON;
}

/* ---- statistics ---- */

typedef struct stats {
    uint64_t rays, primary_rays, bounce_rays, hits, overflows;
    uint64_t visits, box_tests, leaves, tri_tests, pushes, pops, culls;
    uint32_t max_stack;
    rt_embree_tally tally;
    uint64_t occlusion_rays, occluded;
    rt_embree_tally occ_tally;   /* occlusion rays against rtcOccluded1 */
    double embree_build_s;
    rt_tlog_totals log;
    bool log_written;
    double build_s, trace_s, wall_s;
    double trace_cpu_s;           /* host CPU seconds of the tracing loop */
    bool failed;              /* validation failed (exit 1): the JSON says "run_failed": 1 */
    float visits_max, tris_max;
} stats;

static void add_counts(stats *s, const rt_trv_counts *c)
{
    s->visits += c->visits;
    s->box_tests += c->box_tests;
    s->leaves += c->leaves;
    s->tri_tests += c->tri_tests;
    s->pushes += c->pushes;
    s->pops += c->pops;
    s->culls += c->culls;
    if (c->max_stack > s->max_stack)
        s->max_stack = c->max_stack;
}

static double per(uint64_t a, uint64_t b) { return b ? (double)a / (double)b : 0.0; }

static uint64_t embree_mismatches(const rt_embree_tally *t) { return t->rays - t->cause[RT_EMBREE_SAME]; }

/* ---- progress bar (only on a terminal, cli/progress.h) ---- */

static void progress_update(cli_progress *p, uint64_t done, uint64_t total, bool final)
{
    if (!p->on || (!cli_progress_due(p, 0.2) && !final))
        return;
    double f = total ? (double)done / (double)total : 1.0;
    char bar[CLI_PROGRESS_CELLS + 1];
    cli_progress_bar((int)(f * CLI_PROGRESS_CELLS), bar);
    fprintf(stderr, "\r[%s] %5.1f%% %" PRIu64 "/%" PRIu64 " pixels  ETA %4.0f s ", bar, 100.0 * f, done, total,
            final ? 0.0 : cli_progress_eta(p, f));
    if (final)
        fputs("\n", stderr);
    fflush(stderr);
}

/* ---- outputs written in this run, removed again on an error ---- */

static const char *g_written[8];
static int g_nwritten;
/* in-place outputs (stdout, devices, pipes) are never removed */
static void written(const ks_out *out, const char *path)
{
    if (!ks_out_in_place(out))
        g_written[g_nwritten++] = path;
}
static void remove_written(void)
{
    for (int i = 0; i < g_nwritten; i++)
        remove(g_written[i]);
    g_nwritten = 0;
}

/* ---- JSON ---- */

/* What a trace or a log check ran on: the options, the scene, its view and
 * its BVH (for the JSON and the summary). */
typedef struct trace_inputs {
    const options *o;
    const rt_scene *sc;
    const rt_view *view;
    const rt_bvh_params *bp;
    const rt_bvh_stats *bs;
    const rt_bvh_image *img;
} trace_inputs;

/* Provenance (cli/run_info.h, docs/results.md): started in main, filled from
 * the run by fill_run, written first in the JSON. */
static cli_run_info g_run;

static void fill_run(const trace_inputs *ri, const stats *s, bool read_mode, const rt_tlog_header *h)
{
    const options *o = ri->o;
    g_run.scene = o->scene, g_run.views_file = o->views;
    g_run.has_mesh_hash = true, g_run.mesh_hash = rt_mesh_hash(&ri->sc->mesh);
    /* the tracer's settings in place of a machine configuration */
    cli_run_lines l = {0};
    char v[32];
    snprintf(v, sizeof v, "%d", ri->bp->width);
    cli_run_lines_add(&l, "bvh.width", "", "", v);
    snprintf(v, sizeof v, "%d", ri->bp->leaf_size);
    cli_run_lines_add(&l, "bvh.leaf_size", "", "", v);
    if (ri->bp->width > 2 && ri->bp->builder == RT_BUILD_WALD)   /* the collapse keeps the hash it had */
        cli_run_lines_add(&l, "bvh.builder", "", "", builder_kinds[ri->bp->builder]);
    snprintf(v, sizeof v, "%" PRIu64, o->stack_depth);
    cli_run_lines_add(&l, "traversal.stack_depth", "", "", v);
    g_run.has_config_hash = cli_run_lines_hash(&l, &g_run.config_hash);
    if (read_mode) {
        /* the log's own record of its rays */
        g_run.trace = o->read_log;
        g_run.width = h->info.res_width, g_run.height = h->info.res_height;
        g_run.rays = h->info.ray_kind == RT_TLOG_RAYS_PRIMARY   ? "primary"
                     : h->info.ray_kind == RT_TLOG_RAYS_DIFFUSE ? "diffuse"
                                                                : "other";
        g_run.has_bounces = g_run.has_seed = h->info.ray_kind == RT_TLOG_RAYS_DIFFUSE;
        g_run.bounces = h->info.max_bounces, g_run.seed = h->info.seed;
        g_run.has_sim = true, g_run.sim_wall_s = s->wall_s;
        g_run.sim_cpu_s = cli_run_clock(CLOCK_PROCESS_CPUTIME_ID) - g_run.cpu0;
    } else {
        g_run.view = ri->view->name;
        g_run.width = o->res.w, g_run.height = o->res.h;
        g_run.rays = o->diffuse ? "diffuse" : o->occlusion ? "occlusion" : "primary";
        g_run.has_bounces = g_run.has_seed = o->diffuse;
        g_run.bounces = o->bounces, g_run.seed = o->seed;
        g_run.has_sim = true, g_run.sim_wall_s = s->trace_s, g_run.sim_cpu_s = s->trace_cpu_s;
    }
}

static void json_common(cli_json *j, const trace_inputs *ri)
{
    cli_json_str(j, "tool", "rttrace " RTSIM_VERSION " (git " RTSIM_GIT ")");
    cli_json_str(j, "scene", ri->sc->name);
    cli_json_uint(j, "triangles", ri->sc->mesh.ntris);
    char hex[24];
    snprintf(hex, sizeof hex, "%016" PRIx64, rt_mesh_hash(&ri->sc->mesh));
    cli_json_str(j, "mesh_hash", hex);
    cli_json_uint(j, "bvh_width", (uint64_t)ri->bp->width);
    cli_json_uint(j, "leaf_size", (uint64_t)ri->bp->leaf_size);
    cli_json_str(j, "bvh_builder", ri->bp->width > 2 ? builder_kinds[ri->bp->builder] : "sah");
    snprintf(hex, sizeof hex, "%016" PRIx64, ri->img->hash);
    cli_json_str(j, "bvh_image_hash", hex);
    cli_json_uint(j, "bvh_inner_nodes", ri->bs->inner_nodes);
    cli_json_uint(j, "bvh_leaves", ri->bs->leaves);
    cli_json_uint(j, "bvh_max_depth", ri->bs->max_depth);
    cli_json_real(j, "bvh_sah_cost", ri->bs->sah_cost);
    cli_json_uint(j, "bvh_node_bytes", ri->bs->node_bytes_total);
    cli_json_uint(j, "bvh_triangle_bytes", ri->bs->tri_bytes_total);
    cli_json_uint(j, "bvh_image_bytes", ri->img->size);
    cli_json_real(j, "bvh_build_s", ri->bs->build_seconds);
}

static int write_json(const char *path, const trace_inputs *ri, const stats *s, bool read_mode, const char *partial)
{
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    if (!f) {
        fprintf(stderr, "rttrace: --json %s: out of memory\n", path);
        return 2;
    }
    fputs("{\n  ", f);
    cli_run_write_member(f, &g_run, "\n    ");
    cli_json j = {f, "\n  ", false};   /* the run object is the first member */
    json_common(&j, ri);
    if (read_mode) {
        cli_json_str(&j, "log", ri->o->read_log);
        cli_json_uint(&j, "log_bytes", s->log.file_bytes);
        cli_json_uint(&j, "log_blocks", s->log.blocks);
        cli_json_uint(&j, "rays", s->log.rays);
        cli_json_uint(&j, "hits", s->log.hits);
        cli_json_uint(&j, "node_visits", s->log.visits);
        cli_json_uint(&j, "leaf_visits", s->log.leaves);
        cli_json_uint(&j, "triangle_tests", s->log.tri_tests);
        cli_json_uint(&j, "stack_pushes", s->log.pushes);
        cli_json_uint(&j, "stack_pops", s->log.pops);
        cli_json_uint(&j, "stack_culls", s->log.culls);
        cli_json_uint(&j, "stack_overflows", s->log.overflows);
        cli_json_uint(&j, "events", s->log.events);
        cli_json_real(&j, "log_bytes_per_node_visit", per(s->log.file_bytes, s->log.visits));
        cli_json_real(&j, "wall_s", s->wall_s);
    } else {
        const options *o = ri->o;
        cli_json_str(&j, "view", ri->view->name);
        cli_json_str(&j, "ray_type", o->diffuse ? "diffuse" : o->occlusion ? "occlusion" : "primary");
        cli_json_uint(&j, "width_px", o->res.w);
        cli_json_uint(&j, "height_px", o->res.h);
        cli_json_uint(&j, "max_bounces", o->diffuse ? o->bounces : 0);
        cli_json_uint(&j, "seed", o->seed);
        cli_json_uint(&j, "rays", s->rays);
        cli_json_uint(&j, "primary_rays", s->primary_rays);
        cli_json_uint(&j, "bounce_rays", s->bounce_rays);
        cli_json_uint(&j, "hits", s->hits);
        cli_json_uint(&j, "stack_overflows", s->overflows);
        cli_json_uint(&j, "node_visits", s->visits);
        cli_json_uint(&j, "box_tests", s->box_tests);
        cli_json_uint(&j, "leaf_visits", s->leaves);
        cli_json_uint(&j, "triangle_tests", s->tri_tests);
        cli_json_uint(&j, "stack_pushes", s->pushes);
        cli_json_uint(&j, "stack_pops", s->pops);
        cli_json_uint(&j, "stack_culls", s->culls);
        cli_json_uint(&j, "max_stack_depth", s->max_stack);
        cli_json_real(&j, "node_visits_per_ray", per(s->visits, s->rays));
        cli_json_real(&j, "box_tests_per_ray", per(s->box_tests, s->rays));
        cli_json_real(&j, "triangle_tests_per_ray", per(s->tri_tests, s->rays));
        cli_json_real(&j, "max_node_visits_per_pixel", s->visits_max);
        cli_json_real(&j, "max_triangle_tests_per_pixel", s->tris_max);
        cli_json_uint(&j, "embree_checked", o->check_embree);
        cli_json_uint(&j, "embree_rays", s->tally.rays);
        cli_json_uint(&j, "embree_mismatches", embree_mismatches(&s->tally));
        cli_json_uint(&j, "embree_same_exact_t", s->tally.exact_t);
        cli_json_uint(&j, "embree_same_t_within_bound", s->tally.t_bound);
        for (int c = RT_EMBREE_TIE; c < RT_EMBREE_CAUSES; c++) {
            char k[64];
            snprintf(k, sizeof k, "embree_mismatch_%s", rt_embree_cause_name((rt_embree_cause)c));
            cli_json_uint(&j, k, s->tally.cause[c]);
        }
        cli_json_real(&j, "embree_build_s", s->embree_build_s);
        cli_json_real(&j, "embree_max_mismatch_rate", o->max_mismatch_rate);
        if (o->occlusion) {
            cli_json_uint(&j, "ao_samples", RT_AO_SAMPLES_DEFAULT);
            cli_json_real(&j, "ao_distance", rt_ao_distance(&ri->sc->mesh));
            cli_json_uint(&j, "occlusion_rays", s->occlusion_rays);
            cli_json_uint(&j, "occluded", s->occluded);
            cli_json_uint(&j, "embree_occlusion_rays", s->occ_tally.rays);
            cli_json_uint(&j, "embree_occlusion_mismatches", embree_mismatches(&s->occ_tally));
            for (int c = RT_EMBREE_TIE; c < RT_EMBREE_CAUSES; c++) {
                char k[64];
                snprintf(k, sizeof k, "embree_occlusion_mismatch_%s", rt_embree_cause_name((rt_embree_cause)c));
                cli_json_uint(&j, k, s->occ_tally.cause[c]);
            }
        }
        cli_json_uint(&j, "log_bytes", s->log_written ? s->log.file_bytes : 0);
        cli_json_real(&j, "log_bytes_per_node_visit", s->log_written ? per(s->log.file_bytes, s->visits) : 0.0);
        cli_json_real(&j, "trace_s", s->trace_s);
        cli_json_real(&j, "trace_mrays_per_s", s->trace_s > 0 ? (double)s->rays / s->trace_s / 1e6 : 0.0);
        cli_json_real(&j, "wall_s", s->wall_s);
        if (s->failed)   /* only then: a passing run's JSON is unchanged */
            cli_json_uint(&j, "run_failed", 1);
    }
    fputs("\n}\n", f);
    fclose(f);
    char err[4600];
    int rc = text ? cli_write_json(ri->o->out_json, text, partial, err, sizeof err) : -1;
    free(text);
    if (rc) {
        fprintf(stderr, "rttrace: %s\n", text ? err : "--json: out of memory");
        return 2;
    }
    written(ri->o->out_json, path);
    return 0;
}

/* ---- the run ---- */

static void print_build(const trace_inputs *ri)
{
    const rt_bvh_stats *b = ri->bs;
    printf("scene      %s: %u triangles, mesh hash %016" PRIx64 "\n", ri->sc->name, ri->sc->mesh.ntris,
           rt_mesh_hash(&ri->sc->mesh));
    printf("bvh        %s%d (leaf size <= %d%s): %u inner nodes, %u leaves, depth %u, SAH cost %.2f\n",
           ri->bp->width == 2 ? "bvh" : "mbvh", ri->bp->width, ri->bp->leaf_size,
           ri->bp->width > 2 && ri->bp->builder == RT_BUILD_WALD ? ", wald builder" : "", b->inner_nodes, b->leaves,
           b->max_depth, b->sah_cost);
    printf("           %" PRIu64 " B nodes + %" PRIu64 " B triangles (image %" PRIu64 " B, hash %016" PRIx64
           "), built in %.3f s\n",
           b->node_bytes_total, b->tri_bytes_total, ri->img->size, ri->img->hash, b->build_seconds);
}

static int read_log_mode(const options *o, rt_scene *sc, const rt_bvh_params *bp, const rt_bvh_stats *bs,
                         const rt_bvh_image *img, double t0)
{
    trace_inputs ri = {o, sc, &sc->views.v[0], bp, bs, img};
    if (!o->quiet)
        print_build(&ri);
    char err[1024];
    stats s;
    memset(&s, 0, sizeof s);
    rt_tlog_header h;
    if (!rt_tlog_verify(o->read_log, img, &sc->mesh, &h, &s.log, err, sizeof err)) {
        fprintf(stderr, "rttrace: --read-log: %s\n", err);
        return 2;
    }
    s.wall_s = now_s() - t0;
    if (!o->quiet) {
        static const char *kinds[] = {"primary", "diffuse", "other"};
        printf("log        %s: valid, version %u, %s rays, %ux%u, %u bounces, seed %" PRIu64 "\n", o->read_log,
               h.version, kinds[h.info.ray_kind], h.info.res_width, h.info.res_height, h.info.max_bounces,
               h.info.seed);
        printf("           %" PRIu64 " rays (%" PRIu64 " hits, %" PRIu64 " overflows), %" PRIu64 " node visits, %" PRIu64
               " triangle tests, %" PRIu64 " events\n",
               s.log.rays, s.log.hits, s.log.overflows, s.log.visits, s.log.tri_tests, s.log.events);
        printf("           %" PRIu64 " bytes in %" PRIu64 " blocks: %.3f bytes per node visit\n", s.log.file_bytes,
               s.log.blocks, per(s.log.file_bytes, s.log.visits));
    }
    fill_run(&ri, &s, true, &h);
    if (o->json && write_json(o->json, &ri, &s, true, NULL) != 0)
        return 2;
    return 0;
}

typedef struct tracer_ctx {
    const options *o;
    const rt_scene *sc;
    const rt_bvh_image *img;
    rt_trv_params tp;
    rt_tlog_writer *log;
    rt_embree *embree;
    float *rgb, *hm_visits, *hm_tris;
    stats *s;
} tracer_ctx;

/* Traces one ray (logged, checked); false on a log error (message in err). */
static bool trace_one(tracer_ctx *c, const rt_ray *ray, rt_hit *hit, char *err, size_t errlen)
{
    rt_trv_counts cnt;
    if (c->log)
        rt_tlog_ray_begin(c->log, ray);
    bool ok = rt_trace_ray(c->img, &c->tp, ray, hit, &cnt, c->log ? rt_tlog_event : NULL, c->log);
    if (c->log && !rt_tlog_ray_end(c->log, !ok, err, errlen))
        return false;
    stats *s = c->s;
    s->rays++;
    if (ray->occlusion) {
        s->occlusion_rays++;
        s->occluded += ok && hit->prim != RT_NO_HIT;
    } else if (ray->bounce == 0) {
        s->primary_rays++;
    } else {
        s->bounce_rays++;
    }
    s->overflows += !ok;
    s->hits += ok && hit->prim != RT_NO_HIT;
    add_counts(s, &cnt);
    c->hm_visits[ray->pixel] += (float)cnt.visits;
    c->hm_tris[ray->pixel] += (float)cnt.tri_tests;
    if (c->embree && ray->occlusion) {
        rt_embree_tally_add_occlusion(&s->occ_tally, c->embree, &c->sc->mesh, ray, hit);
    } else if (c->embree) {
        rt_hit ref;
        rt_embree_intersect(c->embree, ray, &ref);
        rt_embree_tally_add(&s->tally, &c->sc->mesh, ray, hit, &ref);
    }
    return true;
}

/* The scene, its view and camera, and its BVH: what a trace or a log check
 * runs on. */
typedef struct world {
    rt_scene sc;
    const rt_view *view;
    rt_camera cam;
    rt_bvh_params bp;
    rt_bvh_image img;
    rt_bvh_stats bs;
} world;

/* Loads the scene, picks the view, sets up the camera and builds the BVH
 * (the width of a --read-log log's unless --bvh says); 0 or 2 (said). */
static int load_world(options *o, world *w)
{
    char err[4600];
    if (o->read_log) {
        rt_tlog_header loghdr;
        if (!rt_tlog_read_header(o->read_log, &loghdr, err, sizeof err)) {
            fprintf(stderr, "rttrace: --read-log: %s\n", err);
            return 2;
        }
        if (!o->bvh_given)
            o->width = (int)loghdr.bvh_width;   /* the log names its BVH width */
    }
    if (!rt_scene_load(o->scene, &w->sc, err, sizeof err)) {
        fprintf(stderr, "rttrace: %s\n", err);
        return 2;
    }
    if (o->views && !rt_scene_set_views_file(&w->sc, o->views, err, sizeof err)) {
        fprintf(stderr, "rttrace: --views: %s\n", err);
        return 2;
    }
    w->view = rt_scene_view(&w->sc, o->view, err, sizeof err);
    if (!w->view) {
        fprintf(stderr, "rttrace: --view: %s\n", err);
        return 2;
    }
    if (!rt_camera_init(&w->cam, w->view, o->res.w, o->res.h, err, sizeof err)) {
        fprintf(stderr, "rttrace: view %s: %s\n", w->view->name, err);
        return 2;
    }
    rt_bvh_params_default(&w->bp);
    w->bp.width = o->width;
    w->bp.leaf_size = (int)o->leaf_size;
    w->bp.builder = o->builder;
    if (!rt_bvh_build(&w->sc.mesh, &w->bp, &w->img, &w->bs, err, sizeof err)) {
        fprintf(stderr, "rttrace: BVH: %s\n", err);
        return 2;
    }
    return 0;
}

/* The tracer's buffers, the Embree scene (--check-embree) and the log
 * writer (--log); 0 or 2 (said). */
static int tracer_open(tracer_ctx *tc, const options *o, const world *w, stats *s)
{
    char err[4600];
    tc->o = o;
    tc->sc = &w->sc;
    tc->img = &w->img;
    tc->s = s;
    rt_trv_params_default(&tc->tp, w->bp.width);
    tc->tp.stack_depth = (int)o->stack_depth;
    const size_t npix = (size_t)o->res.w * o->res.h;
    tc->rgb = calloc(3 * npix, sizeof(float));
    tc->hm_visits = calloc(npix, sizeof(float));
    tc->hm_tris = calloc(npix, sizeof(float));
    if (!tc->rgb || !tc->hm_visits || !tc->hm_tris) {
        fprintf(stderr, "rttrace: out of memory for %ux%u pixels\n", o->res.w, o->res.h);
        return 2;
    }
    if (o->check_embree) {
        tc->embree = rt_embree_create(&w->sc.mesh, RT_EMBREE_ROBUST, err, sizeof err);
        if (!tc->embree) {
            fprintf(stderr, "rttrace: --check-embree: %s\n", err);
            return 2;
        }
        s->embree_build_s = rt_embree_build_seconds(tc->embree);
    }
    if (o->log) {
        rt_tlog_info info;
        memset(&info, 0, sizeof info);
        info.mesh_hash = rt_mesh_hash(&w->sc.mesh);
        info.res_width = o->res.w;
        info.res_height = o->res.h;
        info.ray_kind = o->diffuse ? RT_TLOG_RAYS_DIFFUSE : RT_TLOG_RAYS_PRIMARY;
        info.max_bounces = o->diffuse ? (uint32_t)o->bounces : 0;
        info.seed = o->seed;
        info.has_view = true;
        info.view = *w->view;
        info.mesh = &w->sc.mesh;
        const char *stage = ks_out_stage(o->out_log, err, sizeof err);
        tc->log = stage ? rt_tlog_writer_open(stage, &w->img, &tc->tp, &info, err, sizeof err) : NULL;
        if (!tc->log) {
            fprintf(stderr, "rttrace: --log: %s\n", err);
            return 2;
        }
    }
    return 0;
}

static void tracer_close(tracer_ctx *tc)
{
    rt_tlog_writer_abort(tc->log);
    rt_embree_free(tc->embree);
    free(tc->rgb);
    free(tc->hm_visits);
    free(tc->hm_tris);
}

/* Traces the frame pixel by pixel, each path's rays one after the other,
 * until done or interrupted (*done: pixels traced); 0, or 2 on a log error
 * (said). */
static int trace_pixels(tracer_ctx *tc, const world *w, float ao_tmax, cli_progress *pg, size_t *done)
{
    const options *o = tc->o;
    const rt_mesh *mesh = &w->sc.mesh;
    char err[4600];
    int rc = 0;
    for (uint32_t py = 0; py < o->res.h && rc == 0 && !ks_interrupted(); py++) {
        for (uint32_t px = 0; px < o->res.w && !ks_interrupted(); px++) {
            rt_ray ray = rt_camera_primary_ray(&w->cam, px, py);
            rt_hit hit;
            const size_t pix = (size_t)py * o->res.w + px;
            if (!trace_one(tc, &ray, &hit, err, sizeof err)) {
                fprintf(stderr, "rttrace: --log: %s\n", err);
                rc = 2;
                break;
            }
            rt_vec3 col;
            if (o->occlusion) {
                /* the headlight shade times the share of open AO rays */
                col = rt_shade_headlight(mesh, &ray, &hit);
                uint32_t n = 0, open = 0;
                rt_ray ao;
                rt_hit aoh;
                for (uint32_t k = 0; rc == 0 && k < RT_AO_SAMPLES_DEFAULT; k++) {
                    if (!rt_ao_ray(mesh, &ray, &hit, o->seed, k, ao_tmax, &ao))
                        break;
                    if (!trace_one(tc, &ao, &aoh, err, sizeof err))
                        rc = 2;
                    n++;
                    open += aoh.prim == RT_NO_HIT;
                }
                if (n) {
                    const float f = (float)open / (float)n;
                    col = (rt_vec3){col.x * f, col.y * f, col.z * f};
                }
            } else if (!o->diffuse) {
                col = rt_shade_headlight(mesh, &ray, &hit);
            } else {
                rt_path path;
                rt_path_init(&path);
                rt_path_add(&path, &ray, &hit);
                rt_ray next;
                while (rc == 0 && rt_bounce_ray(mesh, &ray, &hit, o->seed, (uint32_t)o->bounces, &next)) {
                    ray = next;
                    if (!trace_one(tc, &ray, &hit, err, sizeof err)) {
                        fprintf(stderr, "rttrace: --log: %s\n", err);
                        rc = 2;
                    }
                    rt_path_add(&path, &ray, &hit);
                }
                col = path.radiance;
            }
            tc->rgb[3 * pix + 0] = col.x;
            tc->rgb[3 * pix + 1] = col.y;
            tc->rgb[3 * pix + 2] = col.z;
            if ((pix & 1023) == 0)
                progress_update(pg, pix, (uint64_t)o->res.w * o->res.h, false);
            (*done)++;
        }
    }
    return rc;
}

/* An image output: staged, written by `write` (true = written), committed. */
#define WRITE_IMAGE(opt, out, path, write)                                                                              \
    do {                                                                                                               \
        const char *stage = ks_out_stage(out, err, sizeof err);                                                        \
        if (!stage || !(write) || ks_out_commit(out, err, sizeof err)) {                                               \
            fprintf(stderr, "rttrace: " opt ": %s\n", err);                                                            \
            return 2;                                                                                                  \
        }                                                                                                              \
        written(out, path);                                                                                            \
    } while (0)

/* The trace log (closed and committed), the image and the heatmaps; 0 or 2
 * (said). */
static int write_images(tracer_ctx *tc, stats *s)
{
    const options *o = tc->o;
    const size_t npix = (size_t)o->res.w * o->res.h;
    char err[4600];
    if (tc->log) {
        bool ok = rt_tlog_writer_close(tc->log, &s->log, err, sizeof err) &&
                  ks_out_commit(o->out_log, err, sizeof err) == 0;
        tc->log = NULL;
        if (!ok) {
            fprintf(stderr, "rttrace: --log: %s\n", err);
            return 2;
        }
        s->log_written = true;
        written(o->out_log, o->log);
    }
    float lo;
    rt_image_value_range(tc->hm_visits, npix, &lo, &s->visits_max);
    rt_image_value_range(tc->hm_tris, npix, &lo, &s->tris_max);
    if (o->image)
        WRITE_IMAGE("--image", o->out_image, o->image,
                    rt_image_write_rgb(stage, tc->rgb, o->res.w, o->res.h, err, sizeof err));
    if (o->hm_visits)
        WRITE_IMAGE("--heatmap-visits", o->out_hm_visits, o->hm_visits,
                    rt_image_write_heatmap(stage, tc->hm_visits, o->res.w, o->res.h, 0.0f, s->visits_max,
                                           RT_COLORMAP_VIRIDIS, err, sizeof err));
    if (o->hm_tris)
        WRITE_IMAGE("--heatmap-tris", o->out_hm_tris, o->hm_tris,
                    rt_image_write_heatmap(stage, tc->hm_tris, o->res.w, o->res.h, 0.0f, s->tris_max,
                                           RT_COLORMAP_VIRIDIS, err, sizeof err));
    return 0;
}

/* The verdict of a traced frame (docs/tracer-bvh.md, "Embree check"): it
 * rests on unexplained mismatches only; a classified one (an exact tie, a
 * coplanar duplicate face, a gap or edge within the float error bound, t
 * rounding) is a property of the scene, not an error of the traversal, and
 * is reported; above --max-mismatch-rate it gives a warning. A ray the
 * hardware's stack cannot trace fails too. */
typedef struct verdict {
    uint64_t mism, occ_mism;
    bool embree_fail, embree_warn;
} verdict;

static verdict judge(const options *o, const stats *s)
{
    verdict v;
    v.mism = embree_mismatches(&s->tally);
    v.occ_mism = embree_mismatches(&s->occ_tally);
    v.embree_fail = o->check_embree && (s->tally.cause[RT_EMBREE_OTHER] > 0 || s->occ_tally.cause[RT_EMBREE_OTHER] > 0);
    v.embree_warn = o->check_embree && ((double)v.mism > o->max_mismatch_rate * (double)s->tally.rays ||
                                        (double)v.occ_mism > o->max_mismatch_rate * (double)s->occ_tally.rays);
    return v;
}

static void print_summary(const tracer_ctx *tc, const world *w, const stats *s, const verdict *v, float ao_tmax)
{
    const options *o = tc->o;
    printf("view       %s, %ux%u, %s", w->view->name, o->res.w, o->res.h, o->diffuse ? "diffuse paths" : "primary rays");
    if (o->diffuse)
        printf(" (<= %" PRIu64 " bounces, seed %" PRIu64 ")", o->bounces, o->seed);
    if (o->occlusion)
        printf(" and their occlusion rays (%d per hit, distance %g, seed %" PRIu64 ")", RT_AO_SAMPLES_DEFAULT,
               (double)ao_tmax, o->seed);
    printf("\n");
    printf("rays       %" PRIu64 " (%" PRIu64 " primary, %" PRIu64 " bounce), %" PRIu64 " hits, %" PRIu64
           " stack overflows\n",
           s->rays, s->primary_rays, s->bounce_rays, s->hits, s->overflows);
    if (o->occlusion)
        printf("occlusion  %" PRIu64 " rays (any hit ends them, no sort), %" PRIu64 " occluded (%.2f%%)\n",
               s->occlusion_rays, s->occluded, 100.0 * per(s->occluded, s->occlusion_rays));
    printf("traversal  %" PRIu64 " node visits (%.2f/ray), %" PRIu64 " box tests (%.2f/ray), %" PRIu64
           " leaves (%.2f/ray),\n           %" PRIu64 " triangle tests (%.2f/ray), %" PRIu64 " pushes, %" PRIu64
           " pops, %" PRIu64 " culls, max stack %u\n",
           s->visits, per(s->visits, s->rays), s->box_tests, per(s->box_tests, s->rays), s->leaves,
           per(s->leaves, s->rays), s->tri_tests, per(s->tri_tests, s->rays), s->pushes, s->pops, s->culls,
           s->max_stack);
    if (o->check_embree) {
        printf("embree     %" PRIu64 " rays compared: %" PRIu64 " identical (%.4f%%; %" PRIu64
               " with bit-equal t), %" PRIu64 " mismatches:",
               s->tally.rays, s->tally.cause[RT_EMBREE_SAME],
               100.0 * per(s->tally.cause[RT_EMBREE_SAME], s->tally.rays), s->tally.exact_t, v->mism);
        for (int k = RT_EMBREE_TIE; k < RT_EMBREE_CAUSES; k++)
            printf(" %s %" PRIu64, rt_embree_cause_name((rt_embree_cause)k), s->tally.cause[k]);
        if (o->occlusion) {
            printf("\nembree     %" PRIu64 " occlusion rays compared with rtcOccluded1: %" PRIu64
                   " same answer (%.4f%%), %" PRIu64 " mismatches:",
                   s->occ_tally.rays, s->occ_tally.cause[RT_EMBREE_SAME],
                   100.0 * per(s->occ_tally.cause[RT_EMBREE_SAME], s->occ_tally.rays), v->occ_mism);
            for (int k = RT_EMBREE_TIE; k < RT_EMBREE_CAUSES; k++)
                printf(" %s %" PRIu64, rt_embree_cause_name((rt_embree_cause)k), s->occ_tally.cause[k]);
        }
        printf("\n           unexplained (other) allowed 0: %s; explained rate %.3g%s (warning above %g)\n",
               v->embree_fail ? "FAIL" : "ok", per(v->mism - s->tally.cause[RT_EMBREE_OTHER], s->tally.rays),
               v->embree_warn ? " WARNING" : "", o->max_mismatch_rate);
    }
    if (s->log_written)
        printf("log        %s: %" PRIu64 " bytes, %.3f bytes per node visit (%" PRIu64 " blocks, %" PRIu64
               " of %" PRIu64 " rays derived from camera/bounce)\n",
               o->log, s->log.file_bytes, per(s->log.file_bytes, s->visits), s->log.blocks,
               s->log.rays_camera + s->log.rays_bounce, s->log.rays);
    if (o->image)
        printf("image      %s\n", o->image);
    if (o->hm_visits)
        printf("heatmap    %s: node visits per pixel, 0..%.0f\n", o->hm_visits, (double)s->visits_max);
    if (o->hm_tris)
        printf("heatmap    %s: triangle tests per pixel, 0..%.0f\n", o->hm_tris, (double)s->tris_max);
    printf("time       %.3f s wall, %.3f s build, %.3f s tracing%s (%.3f Mrays/s)\n", s->wall_s, w->bs.build_seconds,
           s->trace_s, o->log || o->check_embree ? " incl. log/Embree" : "",
           s->trace_s > 0 ? (double)s->rays / s->trace_s / 1e6 : 0.0);
    if (s->overflows)
        printf("FAIL       %" PRIu64 " rays overflowed the %d-entry stack\n", s->overflows, tc->tp.stack_depth);
}

/* Traces the frame and writes its outputs; the exit status. */
static int trace_frame(const options *o, world *w, double t0)
{
    trace_inputs ri = {o, &w->sc, w->view, &w->bp, &w->bs, &w->img};
    if (!o->quiet) {
        print_build(&ri);
        fflush(stdout);
    }
    stats s;
    memset(&s, 0, sizeof s);
    tracer_ctx tc;
    memset(&tc, 0, sizeof tc);
    int rc = tracer_open(&tc, o, w, &s);
    const size_t npix = (size_t)o->res.w * o->res.h;
    const float ao_tmax = rt_ao_distance(&w->sc.mesh);
    cli_progress pg;
    cli_progress_start(&pg, !o->quiet && isatty(2));
    size_t pixels_done = 0;
    if (rc == 0) {
        const double tt0 = now_s(), tc0 = cli_run_clock(CLOCK_PROCESS_CPUTIME_ID);
        ks_interrupt_polling(true);   /* checked once a pixel */
        rc = trace_pixels(&tc, w, ao_tmax, &pg, &pixels_done);
        s.trace_s = now_s() - tt0;
        s.trace_cpu_s = cli_run_clock(CLOCK_PROCESS_CPUTIME_ID) - tc0;
    }
    const int sig = rc ? 0 : ks_interrupted();
    if (sig) {
        /* a cut log or image cannot say it is partial: only the JSON is written */
        char reason[160];
        snprintf(reason, sizeof reason, "interrupted by %s after %zu of %zu pixels (%" PRIu64 " rays)",
                 ks_interrupt_name(sig), pixels_done, npix, s.rays);
        if (pg.on)
            fputs("\n", stderr);
        s.wall_s = now_s() - t0;
        rt_tlog_writer_abort(tc.log);
        tc.log = NULL;
        if (o->json && write_json(o->json, &ri, &s, false, reason) != 0)
            rc = 2;
        fflush(stdout);
        fprintf(stderr, "rttrace: %s; %s, no log or image written, temporary files removed\n", reason,
                o->json ? "the JSON statistics are marked partial" : "nothing written");
        ks_out_discard_all();
        if (rc == 0)
            rc = ks_interrupt_exit_status();
    } else if (rc == 0) {
        progress_update(&pg, npix, npix, true);
        rc = write_images(&tc, &s);
    }
    if (rc || sig) {
        tracer_close(&tc);
        return rc;
    }
    s.wall_s = now_s() - t0;
    const verdict v = judge(o, &s);
    if (!o->quiet)
        print_summary(&tc, w, &s, &v, ao_tmax);
    fill_run(&ri, &s, false, NULL);
    /* a failure is said on stderr even with --quiet (it exited 1 silently) */
    if (s.overflows)
        fprintf(stderr, "rttrace: %" PRIu64 " rays overflowed the %d-entry traversal stack (raise --stack-depth, "
                        "allowed 1..4096)\n",
                s.overflows, tc.tp.stack_depth);
    if (v.embree_fail)
        fprintf(stderr, "rttrace: --check-embree: %" PRIu64 " unexplained mismatches with Embree (cause 'other')\n",
                s.tally.cause[RT_EMBREE_OTHER] + s.occ_tally.cause[RT_EMBREE_OTHER]);
    else if (v.embree_warn)
        fprintf(stderr, "rttrace: --check-embree: warning: %" PRIu64 " of %" PRIu64 " rays differ from Embree for "
                        "explained causes (above --max-mismatch-rate %g); not a failure\n",
                v.mism, s.tally.rays, o->max_mismatch_rate);
    s.failed = v.embree_fail || s.overflows > 0;
    rc = o->json && write_json(o->json, &ri, &s, false, NULL) != 0 ? 2 : s.failed ? 1 : 0;
    tracer_close(&tc);
    return rc;
}

int main(int argc, char **argv)
{
    const double t0 = now_s();
    cli_run_init(&g_run, "rttrace", argc, argv);
    ks_interrupt_install("rttrace");
    options o;
    int rc = parse_options(argc, argv, &o);
    if (rc != CLI_GO_ON)
        return rc;
    static world w;   /* zero: what load_world did not fill is freed as empty */
    rc = load_world(&o, &w);
    if (rc == 0)
        rc = o.read_log ? read_log_mode(&o, &w.sc, &w.bp, &w.bs, &w.img, t0) : trace_frame(&o, &w, t0);
    if (rc == 2)
        remove_written();   /* this run's outputs go again */
    ks_out_discard_all();
    rt_bvh_image_free(&w.img);
    rt_scene_free(&w.sc);
    return rc;
}
