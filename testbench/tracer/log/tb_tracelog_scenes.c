/* tb_tracelog_scenes.c — trace logs of the reference traversal on every
 * built-in scene, BVH2 and MBVH4, primary and diffuse rays at reduced
 * resolution: the events read back equal rt_trace_ray's events exactly
 * (every kind, index and distance bit, ray by ray), the hits and counts
 * agree, the totals match, and the log stays within the budget of
 * 2 bytes per node visit (measured figures are printed on stderr). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testbench/tb.h"
#include "testbench/tracer/tb_tracer_util.h"
#include "tracer/trace/bounce.h"
#include "tracer/io/builtin.h"
#include "tracer/bvh/bvh.h"
#include "tracer/trace/ray_set.h"
#include "tracer/io/scene.h"
#include "tracer/log/trace_log.h"
#include "tracer/trace/traverse.h"


static uint32_t g_w, g_h;

static const char *tmp_dir(void)
{
    const char *d = getenv("RTSIM_TMP");
    return d && *d ? d : "/tmp";
}

/* Writes rays' log, reads it back comparing against a fresh trace of each
 * ray; returns bytes per node visit (or -1 after a failed check). */
static double round_trip(const char *label, const rt_scene *sc, const rt_bvh_image *img, const rt_trv_params *p,
                         const rt_ray_set *rays, uint32_t ray_kind)
{
    char path[TB_PATH_MAX], err[TB_ERR_MAX];
    tb_pathf(path, sizeof path, "%s/scene_%s.tlog", tmp_dir(), label);
    rt_tlog_info info;
    memset(&info, 0, sizeof info);
    info.mesh_hash = rt_mesh_hash(&sc->mesh);
    info.res_width = g_w;
    info.res_height = g_h;
    info.ray_kind = ray_kind;
    info.max_bounces = 4;
    info.seed = 1;
    info.has_view = true;
    info.view = sc->views.v[0];
    info.mesh = &sc->mesh;
    rt_tlog_writer *w = rt_tlog_writer_open(path, img, p, &info, err, sizeof err);
    if (!TB_CHECK(w != NULL, "%s", err))
        return -1;
    uint64_t visits = 0, tri_tests = 0, hits = 0;
    for (uint32_t i = 0; i < rays->n; i++) {
        rt_hit h;
        rt_trv_counts c;
        rt_tlog_ray_begin(w, &rays->rays[i]);
        bool ok = rt_trace_ray(img, p, &rays->rays[i], &h, &c, rt_tlog_event, w);
        visits += c.visits;
        tri_tests += c.tri_tests;
        hits += h.prim != RT_NO_HIT;
        if (!TB_CHECK(rt_tlog_ray_end(w, !ok, err, sizeof err), "%s", err)) {
            rt_tlog_writer_abort(w);
            return -1;
        }
    }
    rt_tlog_totals tot;
    if (!TB_CHECK(rt_tlog_writer_close(w, &tot, err, sizeof err), "%s", err))
        return -1;
    TB_EQ_INT(tot.visits, visits);
    TB_EQ_INT(tot.tri_tests, tri_tests);
    TB_EQ_INT(tot.hits, hits);

    rt_tlog_header hdr;
    if (ray_kind == RT_TLOG_RAYS_DIFFUSE) {
        /* bounce-derived rays need the mesh; a different mesh is refused */
        TB_CHECK(!rt_tlog_verify(path, img, NULL, NULL, NULL, err, sizeof err) && strstr(err, "needs the scene's mesh"),
                 "without mesh: %s", err);
        TB_CHECK(tot.rays_bounce > 0 && tot.rays_camera > 0, "derived rays: %llu camera, %llu bounce",
                 (unsigned long long)tot.rays_camera, (unsigned long long)tot.rays_bounce);
    } else {
        TB_EQ_INT(tot.rays_camera, rays->n);
    }
    rt_tlog_reader *r = rt_tlog_reader_open(path, img, &sc->mesh, &hdr, err, sizeof err);
    if (!TB_CHECK(r != NULL, "%s", err))
        return -1;
    TB_EQ_INT(hdr.ray_count, rays->n);
    TB_EQ_INT(hdr.info.mesh_hash, rt_mesh_hash(&sc->mesh));
    tbt_ev_list got = {0}, want = {0};
    rt_tlog_ray lr;
    uint64_t n = 0, bad_rays = 0, bad_events = 0;
    int s;
    while ((s = rt_tlog_read_ray(r, &lr, tbt_ev_add, &got, err, sizeof err)) == 1) {
        if (n >= rays->n) {
            bad_rays++;
            break;
        }
        const rt_ray *ray = &rays->rays[n];
        rt_hit h;
        rt_trv_counts c;
        want.n = 0;
        rt_trace_ray(img, p, ray, &h, &c, tbt_ev_add, &want);
        if (memcmp(&lr.ray.org, &ray->org, 12) || memcmp(&lr.ray.dir, &ray->dir, 12) || lr.ray.pixel != ray->pixel ||
            lr.ray.bounce != ray->bounce || lr.hit.prim != h.prim || memcmp(&lr.hit.t, &h.t, 4) ||
            memcmp(&lr.counts, &c, sizeof c) != 0)
            bad_rays++;
        if (got.n != want.n)
            bad_events++;
        for (size_t k = 0; k < got.n && k < want.n; k++) {
            const rt_trv_event *a = &got.e[k], *b = &want.e[k];
            if (a->kind != b->kind || a->a != b->a || a->b != b->b || memcmp(&a->t, &b->t, 4) != 0)
                bad_events++;
        }
        got.n = 0;
        n++;
    }
    TB_CHECK(s == 0, "read: %s", err);
    TB_EQ_INT(n, rays->n);
    TB_CHECK(bad_rays == 0 && bad_events == 0, "%llu rays and %llu events differ", (unsigned long long)bad_rays,
             (unsigned long long)bad_events);
    rt_tlog_totals rt;
    rt_tlog_reader_totals(r, &rt);
    TB_CHECK(rt.stream_hash == tot.stream_hash && rt.file_bytes == tot.file_bytes, "totals differ");
    rt_tlog_reader_close(r);
    free(got.e);
    free(want.e);
    remove(path);
    double bpv = visits ? (double)tot.file_bytes / (double)visits : 0;
    fprintf(stderr, "  %-26s %8u rays %10llu visits %9llu bytes  %.3f bytes/visit\n", label, rays->n,
            (unsigned long long)visits, (unsigned long long)tot.file_bytes, bpv);
    return bpv;
}

int main(void)
{
    const uint32_t W = tb_is_sanitized() ? 48 : 160, H = tb_is_sanitized() ? 27 : 90;
    g_w = W, g_h = H;
    for (unsigned si = 0; si < rt_builtin_count(); si++) {
        const char *name = rt_builtin_name(si);
        char err[TB_ERR_MAX];
        rt_scene sc;
        if (!rt_scene_load(name, &sc, err, sizeof err)) {
            tb_begin(name);
            TB_CHECK(false, "%s", err);
            tb_end();
            continue;
        }
        for (int width = 2; width <= 4; width += 2) {
            rt_bvh_params bp;
            rt_bvh_params_default(&bp);
            bp.width = width;
            rt_bvh_image img;
            rt_bvh_stats st;
            char cname[160];
            snprintf(cname, sizeof cname, "tracelog_round_trip_%s_%s", name, width == 2 ? "bvh2" : "mbvh4");
            tb_begin(cname);
            if (!TB_CHECK(rt_bvh_build(&sc.mesh, &bp, &img, &st, err, sizeof err), "%s", err)) {
                tb_end();
                continue;
            }
            rt_trv_params tp;
            rt_trv_params_default(&tp, width);
            rt_ray_set prim;
            bool ok = rt_ray_set_primary(&sc.views.v[0], W, H, &prim, err, sizeof err);
            if (TB_CHECK(ok, "%s", err)) {
                char label[120];
                snprintf(label, sizeof label, "%s_%s_primary", name, width == 2 ? "bvh2" : "mbvh4");
                double bp1 = round_trip(label, &sc, &img, &tp, &prim, RT_TLOG_RAYS_PRIMARY);
                /* whole paths one after the other (as rttrace logs them) */
                rt_ray_set all = {NULL, 0};
                size_t cap = 0;
                for (uint32_t i = 0; i < prim.n; i++) {
                    rt_ray ray = prim.rays[i], next;
                    for (;;) {
                        if (all.n == cap) {
                            cap = cap ? 2 * cap : 4096;
                            all.rays = realloc(all.rays, cap * sizeof(rt_ray));
                        }
                        all.rays[all.n++] = ray;
                        rt_hit h;
                        rt_trace_ray(&img, &tp, &ray, &h, NULL, NULL, NULL);
                        if (!rt_bounce_ray(&sc.mesh, &ray, &h, 1, 4, &next))
                            break;
                        ray = next;
                    }
                }
                snprintf(label, sizeof label, "%s_%s_diffuse", name, width == 2 ? "bvh2" : "mbvh4");
                double bp2 = round_trip(label, &sc, &img, &tp, &all, RT_TLOG_RAYS_DIFFUSE);
                TB_CHECK(bp1 > 0 && bp1 <= 2.0, "primary: %.3f bytes per node visit (budget 2)", bp1);
                TB_CHECK(bp2 > 0 && bp2 <= 2.0, "diffuse: %.3f bytes per node visit (budget 2)", bp2);
                rt_ray_set_free(&all);
            }
            rt_ray_set_free(&prim);
            rt_bvh_image_free(&img);
            tb_end();
        }
        rt_scene_free(&sc);
    }
    return tb_finish();
}
