/* tb_tracer_embree.c — the reference traversal against Embree 3 (robust
 * mode) on every built-in scene and, when present, the real scenes of
 * ../shared/scenes with their default views: primary rays and the diffuse
 * bounce rays that follow them (4 bounces, seed 1), BVH widths 2 and 4.
 * Every ray's closest hit is classified (embree_check.h); asserted: no
 * unexplained ("other") difference, no stack overflow, and the identical
 * share (over the rays not ending on overlapping coplanar faces, which have
 * no single right answer) at least 99.99% on the built-ins, with at most
 * 0.001% of rays in the precision classes gap/edge/t_round; on the real
 * scenes at least 99.95% (primary) and 99.75% (diffuse), the measured figures
 * less a margin (docs/tracer-bvh.md). The figures are printed on stderr.
 * Also: the classifier itself on constructed cases. Reduced resolutions;
 * under the sanitizers smaller still, and the real scenes above 500K
 * triangles run in the release build only. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "testbench/tb.h"
#include "testbench/tracer/tb_tracer_util.h"
#include "tracer/io/builtin.h"
#include "tracer/bvh/bvh.h"
#include "tracer/check/embree_check.h"
#include "tracer/trace/ray_set.h"
#include "tracer/io/scene.h"
#include "tracer/trace/traverse.h"

static void tally_set(const rt_mesh *m, const rt_bvh_image *img, const rt_trv_params *p, const rt_embree *e,
                      const rt_ray_set *s, rt_embree_tally *t, uint32_t *overflows)
{
    for (uint32_t i = 0; i < s->n; i++) {
        rt_hit ours, ref;
        if (!rt_trace_ray(img, p, &s->rays[i], &ours, NULL, NULL, NULL))
            (*overflows)++;
        rt_embree_intersect(e, &s->rays[i], &ref);
        const rt_embree_cause c = rt_embree_tally_add(t, m, &s->rays[i], &ours, &ref);
        if (c == RT_EMBREE_OTHER && t->cause[c] <= 3)
            fprintf(stderr, "  unexplained: ray %u (pixel %u bounce %u): ours prim %u t %.9g, Embree %u %.9g\n", i,
                    s->rays[i].pixel, s->rays[i].bounce, ours.prim, (double)ours.t, ref.prim, (double)ref.t);
    }
}

typedef struct thresholds {
    double min_identical;   /* identical share of the rays not ending on coplanar overlaps */
    double max_precision;   /* share of rays in gap/edge/t_round */
} thresholds;

static void report(const char *scene, int width, const char *kind, const rt_embree_tally *t, uint32_t overflows,
                   thresholds th)
{
    const double n = (double)t->rays, same = (double)t->cause[RT_EMBREE_SAME];
    const double cop = (double)t->cause[RT_EMBREE_COPLANAR];
    const uint64_t precision = t->cause[RT_EMBREE_GAP] + t->cause[RT_EMBREE_EDGE] + t->cause[RT_EMBREE_T_ROUND];
    fprintf(stderr, "embree %-22s width %d %-7s %7llu rays: identical %.4f%% (%.4f%% without coplanar)", scene, width,
            kind, (unsigned long long)t->rays, 100.0 * same / n, 100.0 * same / (n - cop));
    for (int c = 1; c < RT_EMBREE_CAUSES; c++)
        fprintf(stderr, " %s=%llu", rt_embree_cause_name((rt_embree_cause)c), (unsigned long long)t->cause[c]);
    fprintf(stderr, " (bit-identical t %.1f%%)\n", 100.0 * (double)t->exact_t / n);
    TB_CHECK(overflows == 0, "%s width %d %s: %u stack overflows", scene, width, kind, overflows);
    TB_CHECK(t->cause[RT_EMBREE_OTHER] == 0, "%s width %d %s: %llu unexplained differences", scene, width, kind,
             (unsigned long long)t->cause[RT_EMBREE_OTHER]);
    TB_CHECK(same >= th.min_identical * (n - cop), "%s width %d %s: identical %.5f%% < %.3f%%", scene, width, kind,
             100.0 * same / (n - cop), 100.0 * th.min_identical);
    TB_CHECK((double)precision <= th.max_precision * n + 1.0, "%s width %d %s: %llu gap/edge/t_round of %llu rays",
             scene, width, kind, (unsigned long long)precision, (unsigned long long)t->rays);
    TB_CHECK(t->rays > 200, "%s %s: only %llu rays", scene, kind, (unsigned long long)t->rays);
}

static void compare_scene(const char *label, const rt_mesh *m, const rt_view *view, uint32_t w, uint32_t h,
                          thresholds th_primary, thresholds th_diffuse)
{
    char name[160], err[TB_ERR_MAX];
    snprintf(name, sizeof name, "embree_agrees_%s_%ux%u_primary_diffuse_width2_width4_wald4", label, w, h);
    tb_begin(name);
    rt_embree *e = rt_embree_create(m, RT_EMBREE_ROBUST, err, sizeof err);
    if (!TB_CHECK(e != NULL, "%s", err)) {
        tb_end();
        return;
    }
    rt_ray_set prim;
    if (TB_CHECK(rt_ray_set_primary(view, w, h, &prim, err, sizeof err), "%s", err)) {
        /* BVH2, MBVH4 collapsed, MBVH4 of the top-down splitting builder */
        for (int c = 0; c < 3; c++) {
            const int width = c == 0 ? 2 : 4;
            char lab[128];
            snprintf(lab, sizeof lab, "%s%s", label, c == 2 ? "_wald" : "");
            rt_bvh_params bp;
            rt_bvh_params_default(&bp);
            bp.width = width;
            bp.builder = c == 2 ? RT_BUILD_WALD : RT_BUILD_COLLAPSE;
            rt_bvh_image img;
            if (!TB_CHECK(rt_bvh_build(m, &bp, &img, NULL, err, sizeof err), "%s", err))
                continue;
            rt_trv_params tp;
            rt_trv_params_default(&tp, width);
            rt_ray_set diff;
            if (TB_CHECK(rt_ray_set_diffuse(m, &img, &tp, &prim, 1, 4, &diff, err, sizeof err), "%s", err)) {
                rt_embree_tally tp_prim = {0}, tp_diff = {0};
                uint32_t of = 0;
                tally_set(m, &img, &tp, e, &prim, &tp_prim, &of);
                report(lab, width, "primary", &tp_prim, of, th_primary);
                of = 0;
                tally_set(m, &img, &tp, e, &diff, &tp_diff, &of);
                report(lab, width, "diffuse", &tp_diff, of, th_diffuse);
                rt_ray_set_free(&diff);
            }
            rt_bvh_image_free(&img);
        }
        rt_ray_set_free(&prim);
    }
    rt_embree_free(e);
    tb_end();
}

static void test_builtins(void)
{
    const uint32_t w = tb_is_sanitized() ? 64 : 320, h = tb_is_sanitized() ? 36 : 180;
    for (unsigned i = 0; i < rt_builtin_count(); i++) {
        rt_mesh m;
        rt_views v;
        char err[TB_ERR_MAX];
        if (!rt_builtin_generate(rt_builtin_name(i), &m, &v, err, sizeof err)) {
            tb_begin("embree_builtin_generate");
            TB_CHECK(false, "%s", err);
            tb_end();
            continue;
        }
        /* measured: 100% except shared-edge ties on hairball (3 of 57600
         * primary rays) and city (1); see docs/tracer-bvh.md */
        const thresholds th = {0.9999, 1e-5};
        compare_scene(rt_builtin_name(i), &m, &v.v[0], w, h, th, th);
        rt_mesh_free(&m);
        rt_views_free(&v);
    }
}

static void test_real(void)
{
    static const struct {
        const char *folder, *file;
        int big;
    } scenes[] = {
        {"bunny", "stanford-bunny.obj.gz", 0},
        {"sponza-ravenbridge", "stk_ravenbridge_mansion.ply.gz", 0},
        {"rungholt-candela", "stk_candela_city.ply.gz", 0},
        {"fairy-blackforest", "stk_black_forest.ply.gz", 1},
        {"hairball-furball", "furBall_A_tubes3.ply.gz", 1},
    };
    const char *root = tbt_scenes_dir();
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
        char name[160], path[TB_PATH_MAX], err[TB_ERR_MAX];
        snprintf(name, sizeof name, "embree_agrees_real_%s", scenes[i].folder);
        if (!root) {
            tb_skip(name, "../shared/scenes absent (set RTSIM_SCENES)");
            continue;
        }
        if (tb_is_sanitized() && (scenes[i].big || i > 0)) {
            tb_skip(name, "large scene: release build only");
            continue;
        }
        tb_pathf(path, sizeof path, "%s/%s/%s", root, scenes[i].folder, scenes[i].file);
        if (access(path, R_OK) != 0) {
            tb_skip(name, "scene file absent");
            continue;
        }
        rt_scene s;
        if (!rt_scene_load(path, &s, err, sizeof err)) {
            tb_begin(name);
            TB_CHECK(false, "%s", err);
            tb_end();
            continue;
        }
        const uint32_t w = tb_is_sanitized() ? 48 : 160, h = tb_is_sanitized() ? 27 : 90;
        char label[96];
        snprintf(label, sizeof label, "%s_%s", scenes[i].folder, s.views.v[0].name);
        /* measured at 160x90: primary >= 99.985%, diffuse >= 99.83% (the
         * voxel corners of rungholt and fairy at coordinates in the hundreds
         * flip depth order within Wald's distance rounding: t_round) */
        const thresholds thp = {0.9995, 2e-4}, thd = {0.9975, 2.5e-3};
        compare_scene(label, &s.mesh, &s.views.v[0], w, h, thp, thd);
        rt_scene_free(&s);
    }
}

/* The classifier on constructed cases: a shared edge, coplanar duplicates,
 * a clear miss, and an unexplained difference. */
static void test_classifier(void)
{
    tb_begin("embree_classifier_causes_on_constructed_cases");
    rt_mesh m;
    memset(&m, 0, sizeof m);
    const rt_vec3 v[6] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, -5}, {1, 0, -5}};
    m.verts = malloc(sizeof v);
    memcpy(m.verts, v, sizeof v);
    const uint32_t ix[12] = {0, 1, 2, 1, 3, 2, 2, 1, 0, 4, 5, 2};   /* 0,1: share edge 1-2; 2: duplicate of 0 */
    m.tris = malloc(sizeof ix);
    memcpy(m.tris, ix, sizeof ix);
    m.nverts = 6, m.ntris = 4;
    rt_ray r = {{0.5f, 0.5f, 1}, {0, 0, -1}, 0.0f, FLT_MAX, 0, 0, 0};   /* exactly on the shared edge */
    rt_hit a = {1, 0.5f, 0.5f, 0}, b = {1, 0, 0.5f, 1};
    TB_CHECK(rt_embree_classify(&m, &r, &a, &b) == RT_EMBREE_TIE, "shared edge: %s",
             rt_embree_cause_name(rt_embree_classify(&m, &r, &a, &b)));
    rt_ray r2 = {{0.2f, 0.2f, 1}, {0, 0, -1}, 0.0f, FLT_MAX, 0, 0, 0};
    rt_hit c = {1, 0.2f, 0.2f, 0}, d = {1, 0.2f, 0.2f, 2};
    TB_CHECK(rt_embree_classify(&m, &r2, &c, &d) == RT_EMBREE_COPLANAR, "duplicate");
    rt_hit same = {1, 0.2f, 0.2f, 0}, near = {1.000001f, 0.2f, 0.2f, 0};
    TB_CHECK(rt_embree_classify(&m, &r2, &same, &near) == RT_EMBREE_SAME, "rounding of t");
    rt_hit miss = {FLT_MAX, 0, 0, RT_NO_HIT};
    TB_CHECK(rt_embree_classify(&m, &r2, &miss, &c) == RT_EMBREE_OTHER, "we miss a hit well inside a triangle");
    TB_CHECK(rt_embree_classify(&m, &r2, &c, &miss) == RT_EMBREE_OTHER, "Embree misses well inside");
    TB_CHECK(rt_embree_classify(&m, &r2, &miss, &miss) == RT_EMBREE_SAME, "both miss");
    rt_hit far = {6, 0, 0, 3};
    TB_CHECK(rt_embree_classify(&m, &r2, &far, &c) == RT_EMBREE_OTHER, "we report a farther hit");
    rt_embree_tally t = {0};
    rt_embree_tally_add(&t, &m, &r2, &c, &c);
    rt_embree_tally_add(&t, &m, &r2, &same, &near);
    TB_CHECK(t.rays == 2 && t.cause[RT_EMBREE_SAME] == 2 && t.exact_t == 1, "tally");
    /* the Embree scene itself: the ray on the shared edge hits prim 0, 1 or 2 at t = 1 */
    char err[TB_ERR_MAX];
    rt_embree *e = rt_embree_create(&m, RT_EMBREE_ROBUST, err, sizeof err);
    if (TB_CHECK(e != NULL, "%s", err)) {
        rt_hit h;
        rt_embree_intersect(e, &r2, &h);
        TB_CHECK((h.prim == 0 || h.prim == 2) && h.t == 1.0f, "Embree: prim %u t %g", h.prim, (double)h.t);
        rt_ray bounded = r2;
        bounded.tmax = 1.0f;   /* open interval: t = tmax is not a hit */
        rt_embree_intersect(e, &bounded, &h);
        TB_CHECK(h.prim == RT_NO_HIT, "Embree accepted t = tmax");
        bounded.tmax = FLT_MAX, bounded.tmin = 1.0f;
        rt_embree_intersect(e, &bounded, &h);
        TB_CHECK(h.prim == 3 && h.t == 5.0f, "Embree accepted t = tmin (prim %u t %g)", h.prim, (double)h.t);
        rt_embree_free(e);
    }
    rt_mesh_free(&m);
    tb_end();
}

int main(void)
{
    test_classifier();
    test_builtins();
    test_real();
    return tb_finish();
}
