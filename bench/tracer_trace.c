/* tracer_trace.c — BVH build time and traversal throughput, ours against
 * Embree 3 on the same mesh and the same rays, single-threaded.
 *
 *   tracer_trace SCENE [--view NAME] [--res WxH] [--runs N] [--width N] [--check]
 *
 * Builds our BVH (width N, default 4) and Embree's scene (default flags: its
 * fast mode, as shipped) RUNS times each (default 5), then traces the view's
 * primary rays and the diffuse bounce rays that follow them (4 bounces, seed 1,
 * tracer/trace/ray_set.h) RUNS times with each. stdout, one line per measurement:
 *   <what> <ours_median_s> <embree_median_s> <rays>
 * for what = build, primary, diffuse. --check also prints the Embree (robust)
 * comparison tally on stderr. Exit 2 on bad usage/input. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tracer/bvh/bvh.h"
#include "tracer/trace/camera.h"
#include "tracer/check/embree_check.h"
#include "tracer/trace/ray_set.h"
#include "tracer/io/scene.h"
#include "tracer/trace/traverse.h"

/* CPU time of the process: both sides are single-threaded, so on an idle
 * machine this equals wall time, and on a shared one it is not inflated by
 * other jobs' time slices. */
static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static double time_ours(const rt_bvh_image *img, const rt_trv_params *p, const rt_ray_set *s, uint64_t *sum)
{
    const double t0 = now_s();
    for (uint32_t i = 0; i < s->n; i++) {
        rt_hit h;
        rt_trace_ray(img, p, &s->rays[i], &h, NULL, NULL, NULL);
        *sum += h.prim;
    }
    return now_s() - t0;
}

static double time_embree(const rt_embree *e, const rt_ray_set *s, uint64_t *sum)
{
    const double t0 = now_s();
    for (uint32_t i = 0; i < s->n; i++) {
        rt_hit h;
        rt_embree_intersect(e, &s->rays[i], &h);
        *sum += h.prim;
    }
    return now_s() - t0;
}

static int usage(const char *msg)
{
    fprintf(stderr, "tracer_trace: %s\nusage: tracer_trace SCENE [--view NAME] [--res WxH] [--runs 1..100] "
                    "[--width 2..8] [--check]\n", msg);
    return 2;
}

static void check(const rt_scene *sc, const rt_bvh_image *img, const rt_trv_params *p, const rt_ray_set *s,
                  const char *what)
{
    char err[512];
    rt_embree *e = rt_embree_create(&sc->mesh, RT_EMBREE_ROBUST, err, sizeof err);
    if (!e) {
        fprintf(stderr, "%s\n", err);
        return;
    }
    rt_embree_tally t = {0};
    for (uint32_t i = 0; i < s->n; i++) {
        rt_hit a, b;
        rt_trace_ray(img, p, &s->rays[i], &a, NULL, NULL, NULL);
        rt_embree_intersect(e, &s->rays[i], &b);
        rt_embree_cause c = rt_embree_tally_add(&t, &sc->mesh, &s->rays[i], &a, &b);
        if (c != RT_EMBREE_SAME && getenv("TRACE_VERBOSE"))
            fprintf(stderr, "  ray %u px %u b%u: %s ours %u %.9g ref %u %.9g\n", i, s->rays[i].pixel,
                    s->rays[i].bounce, rt_embree_cause_name(c), a.prim, a.t, b.prim, b.t);
    }
    fprintf(stderr, "check %s: %llu rays, same %.5f%% (exact t %llu, t within bound only %llu)", what, (unsigned long long)t.rays,
            100.0 * (double)t.cause[RT_EMBREE_SAME] / (double)t.rays, (unsigned long long)t.exact_t, (unsigned long long)t.t_bound);
    for (int c = 1; c < RT_EMBREE_CAUSES; c++)
        fprintf(stderr, " %s=%llu", rt_embree_cause_name((rt_embree_cause)c), (unsigned long long)t.cause[c]);
    fprintf(stderr, "\n");
    rt_embree_free(e);
}

int main(int argc, char **argv)
{
    const char *scene = NULL, *view_name = NULL;
    uint32_t w = 640, h = 360;
    int runs = 5, width = 4;
    bool do_check = false, ours_only = false;
    char err[1024];
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--view") && i + 1 < argc)
            view_name = argv[++i];
        else if (!strcmp(argv[i], "--res") && i + 1 < argc) {
            if (!rt_parse_resolution(argv[++i], &w, &h, err, sizeof err))
                return usage(err);
        } else if (!strcmp(argv[i], "--runs") && i + 1 < argc) {
            runs = atoi(argv[++i]);
            if (runs < 1 || runs > 100)
                return usage("--runs must be 1..100");
        } else if (!strcmp(argv[i], "--width") && i + 1 < argc) {
            width = atoi(argv[++i]);
            if (width < 2 || width > 8)
                return usage("--width must be 2..8");
        } else if (!strcmp(argv[i], "--check"))
            do_check = true;
        else if (!strcmp(argv[i], "--ours-only"))   /* profiling: our traversal only */
            ours_only = true;
        else if (argv[i][0] != '-' && !scene)
            scene = argv[i];
        else
            return usage("unknown argument");
    }
    if (!scene)
        return usage("SCENE missing");
    rt_scene sc;
    if (!rt_scene_load(scene, &sc, err, sizeof err)) {
        fprintf(stderr, "tracer_trace: %s\n", err);
        return 2;
    }
    const rt_view *view = rt_scene_view(&sc, view_name, err, sizeof err);
    if (!view) {
        fprintf(stderr, "tracer_trace: %s\n", err);
        rt_scene_free(&sc);
        return 2;
    }
    rt_bvh_params bp;
    rt_bvh_params_default(&bp);
    bp.width = width;
    double ours[100], ref[100];
    rt_bvh_image img = {0};
    rt_bvh_stats st;
    for (int r = 0; r < (ours_only ? 1 : runs); r++) {
        rt_bvh_image_free(&img);
        const double t0 = now_s();
        if (!rt_bvh_build(&sc.mesh, &bp, &img, &st, err, sizeof err)) {
            fprintf(stderr, "tracer_trace: %s\n", err);
            return 2;
        }
        ours[r] = now_s() - t0;
        rt_embree *e = rt_embree_create(&sc.mesh, 0, err, sizeof err);
        if (!e) {
            fprintf(stderr, "tracer_trace: %s\n", err);
            return 2;
        }
        ref[r] = rt_embree_build_seconds(e);
        rt_embree_free(e);
    }
    fprintf(stderr, "%s: %u triangles; width %d: %u nodes, %u leaves, depth %u, SAH %.2f\n", sc.name, sc.mesh.ntris,
            width, st.inner_nodes, st.leaves, st.max_depth, st.sah_cost);
    if (!ours_only)
        printf("build %.6f %.6f %u\n", median(ours, runs), median(ref, runs), sc.mesh.ntris);

    rt_trv_params tp;
    rt_trv_params_default(&tp, width);
    rt_ray_set prim, diff;
    if (!rt_ray_set_primary(view, w, h, &prim, err, sizeof err) ||
        !rt_ray_set_diffuse(&sc.mesh, &img, &tp, &prim, 1, 4, &diff, err, sizeof err)) {
        fprintf(stderr, "tracer_trace: %s\n", err);
        return 2;
    }
    rt_embree *e = rt_embree_create(&sc.mesh, 0, err, sizeof err);
    if (!e) {
        fprintf(stderr, "tracer_trace: %s\n", err);
        return 2;
    }
    for (int k = 0; k < 2; k++) {
        const rt_ray_set *s = k ? &diff : &prim;
        uint64_t v = 0, bt = 0, tt = 0, pu = 0, cu = 0;
        for (uint32_t i = 0; i < s->n; i++) {
            rt_hit hh;
            rt_trv_counts cc;
            rt_trace_ray(&img, &tp, &s->rays[i], &hh, &cc, NULL, NULL);
            v += cc.visits, bt += cc.box_tests, tt += cc.tri_tests, pu += cc.pushes, cu += cc.culls;
        }
        const double n = s->n ? (double)s->n : 1.0;
        fprintf(stderr, "%s rays: %u; per ray %.1f visits, %.1f box tests, %.1f triangle tests, %.1f pushes, %.1f culls\n",
                k ? "diffuse" : "primary", s->n, (double)v / n, (double)bt / n, (double)tt / n, (double)pu / n,
                (double)cu / n);
    }
    uint64_t sum = 0;
    const rt_ray_set *sets[2] = {&prim, &diff};
    const char *names[2] = {"primary", "diffuse"};
    for (int k = 0; k < 2; k++) {
        for (int r = 0; r < runs; r++) {
            ours[r] = time_ours(&img, &tp, sets[k], &sum);
            ref[r] = ours_only ? 0.0 : time_embree(e, sets[k], &sum);
        }
        printf("%s %.6f %.6f %u\n", names[k], median(ours, runs), median(ref, runs), sets[k]->n);
        fflush(stdout);
    }
    rt_embree_free(e);
    if (do_check) {
        check(&sc, &img, &tp, &prim, "primary");
        check(&sc, &img, &tp, &diff, "diffuse");
    }
    fprintf(stderr, "(checksum %llu)\n", (unsigned long long)sum);
    rt_ray_set_free(&prim);
    rt_ray_set_free(&diff);
    rt_bvh_image_free(&img);
    rt_scene_free(&sc);
    return 0;
}
