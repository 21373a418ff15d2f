/* tb_tracer_traverse.c — the reference traversal (traverse.h): closest hit
 * equal to a brute-force loop over every triangle of the image (widths 2..8,
 * several leaf sizes), the event stream obeys the documented algorithm
 * (stack discipline, farthest-first pushes, culls only beyond the closest
 * hit, counts equal to events), closest-first order and distance culling on a
 * hand-made scene, culling never changes a hit, stack overflow reported, and
 * the ray sets used by the Embree check. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testbench/tb.h"
#include "testbench/tracer/tb_tracer_util.h"
#include "tracer/io/builtin.h"
#include "tracer/bvh/bvh.h"
#include "tracer/trace/ray_set.h"
#include "tracer/trace/traverse.h"

/* Closest hit by testing every triangle of the image in image order with the
 * same strict-less rule. */
static rt_hit brute_force(const rt_bvh_image *img, const rt_ray *r)
{
    rt_hit h = {r->tmax, 0, 0, RT_NO_HIT};
    const float org[3] = {r->org.x, r->org.y, r->org.z}, dir[3] = {r->dir.x, r->dir.y, r->dir.z};
    for (uint32_t i = 0; i < img->ntris; i++) {
        rt_tri48 t;
        rt_tri_decode(rt_bvh_tri_ptr(img, i), &t);
        float tt, u, v;
        if (rt_wald_test(&t, org, dir, r->tmin, h.t, &tt, &u, &v))
            h.t = tt, h.u = u, h.v = v, h.prim = t.prim;
    }
    return h;
}

/* t of prim's own test on ray (NAN on a miss) */
static float prim_t(const rt_bvh_image *img, uint32_t prim, const rt_ray *r)
{
    const float org[3] = {r->org.x, r->org.y, r->org.z}, dir[3] = {r->dir.x, r->dir.y, r->dir.z};
    for (uint32_t i = 0; i < img->ntris; i++) {
        rt_tri48 t;
        rt_tri_decode(rt_bvh_tri_ptr(img, i), &t);
        float tt, u, v;
        if (t.prim == prim)
            return rt_wald_test(&t, org, dir, r->tmin, r->tmax, &tt, &u, &v) ? tt : NAN;
    }
    return NAN;
}

/* ---- event stream checker ------------------------------------------------ */

typedef struct ev_log {
    rt_trv_event *ev;
    size_t n, cap;
} ev_log;

static void record(void *user, const rt_trv_event *e)
{
    ev_log *l = user;
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 256;
        l->ev = realloc(l->ev, l->cap * sizeof *l->ev);
    }
    l->ev[l->n++] = *e;
}

/* Replays the events of one ray against the documented algorithm. */
static bool check_events(const rt_bvh_image *img, const rt_trv_params *p, const rt_ray *r, const ev_log *l,
                         const rt_hit *hit, const rt_trv_counts *c, char *msg, size_t len)
{
#define BAD(...) (snprintf(msg, len, __VA_ARGS__), false)
    typedef struct {
        uint32_t a, b;
        float t;
    } entry;
    entry st[4096];
    int sp = 0;
    uint32_t nv = 0, np = 0, npop = 0, nc = 0, nl = 0, nt = 0;
    float closest = r->tmax;
    uint32_t want_kind = RT_EV_VISIT, want_a = 0, want_b = 0;   /* the target after a POP (first: the root) */
    bool expect_target = true;
    float last_push_t = INFINITY;
    if (l->n == 0 || l->ev[l->n - 1].kind != RT_EV_DONE)
        return BAD("stream does not end with DONE");
    for (size_t i = 0; i < l->n; i++) {
        const rt_trv_event *e = &l->ev[i];
        if (expect_target) {
            if (e->kind != want_kind || e->a != want_a || (want_kind == RT_EV_LEAF && e->b != want_b))
                return BAD("event %zu: kind %d a %u, expected target kind %u a %u", i, e->kind, e->a, want_kind, want_a);
            expect_target = false;
        }
        switch (e->kind) {
        case RT_EV_VISIT:
            nv++;
            last_push_t = INFINITY;
            if (e->a >= img->nnodes)
                return BAD("VISIT of node %u", e->a);
            /* what follows: pushes, then the nearest child as target, or a pop */
            {
                size_t j = i + 1;
                while (j < l->n && l->ev[j].kind == RT_EV_PUSH)
                    j++;
                if (j > i + 1 && j < l->n && l->ev[j].kind != RT_EV_VISIT && l->ev[j].kind != RT_EV_LEAF)
                    return BAD("event %zu: pushes not followed by the nearest child", j);
            }
            break;
        case RT_EV_PUSH:
            np++;
            if (sp == p->stack_depth)
                return BAD("push beyond the stack depth");
            if (e->t > last_push_t)
                return BAD("event %zu: pushes not farthest first (%g after %g)", i, (double)e->t, (double)last_push_t);
            if (e->t < r->tmin || e->t > closest)
                return BAD("event %zu: pushed tnear %g outside [tmin, closest %g]", i, (double)e->t, (double)closest);
            last_push_t = e->t;
            st[sp++] = (entry){e->a, e->b, e->t};
            break;
        case RT_EV_POP:
        case RT_EV_CULL:
            if (sp == 0)
                return BAD("event %zu: pop from an empty stack", i);
            sp--;
            if (st[sp].a != e->a || st[sp].b != e->b || st[sp].t != e->t)
                return BAD("event %zu: popped entry is not the top of the stack", i);
            if (e->kind == RT_EV_CULL) {
                nc++;
                if (!p->distance_cull || !(e->t > closest))
                    return BAD("event %zu: cull of tnear %g with closest %g (cull %d)", i, (double)e->t,
                               (double)closest, p->distance_cull);
            } else {
                npop++;
                if (p->distance_cull && e->t > closest)
                    return BAD("event %zu: entry beyond the closest hit not culled", i);
                want_kind = e->b ? RT_EV_LEAF : RT_EV_VISIT, want_a = e->a, want_b = e->b;
                expect_target = true;
            }
            break;
        case RT_EV_LEAF:
            nl++;
            for (uint32_t k = 0; k < e->b; k++) {
                const rt_trv_event *t = &l->ev[i + 1 + k];
                if (i + 1 + k >= l->n || t->kind != RT_EV_TRI || t->a != e->a + k)
                    return BAD("event %zu: leaf of %u triangles not followed by its TRI events", i, e->b);
            }
            break;
        case RT_EV_TRI:
            nt++;
            if (e->b) {
                if (!(e->t < closest))
                    return BAD("event %zu: hit not strictly closer", i);
                closest = e->t;
            } else if (e->t != closest) {
                return BAD("event %zu: TRI miss changed closest", i);
            }
            break;
        case RT_EV_DONE:
            if (i != l->n - 1 || sp != 0)
                return BAD("DONE with %d stack entries left", sp);
            if (e->a != hit->prim || e->t != hit->t || e->t != closest)
                return BAD("DONE prim %u t %g, hit %u %g", e->a, (double)e->t, hit->prim, (double)hit->t);
            break;
        default:
            return BAD("unknown event kind %d", e->kind);
        }
    }
    if (nv != c->visits || np != c->pushes || npop != c->pops || nc != c->culls || nl != c->leaves || nt != c->tri_tests)
        return BAD("counts differ from events: visits %u/%u pushes %u/%u pops %u/%u culls %u/%u leaves %u/%u tris %u/%u",
                   c->visits, nv, c->pushes, np, c->pops, npop, c->culls, nc, c->leaves, nl, c->tri_tests, nt);
    if (c->pushes != c->pops + c->culls || c->max_stack > (uint32_t)p->stack_depth || c->box_tests < c->visits)
        return BAD("pushes %u != pops %u + culls %u, or max_stack %u", c->pushes, c->pops, c->culls, c->max_stack);
    return true;
#undef BAD
}

static bool build(const rt_mesh *m, int width, int leaf, rt_bvh_image *img)
{
    rt_bvh_params p;
    rt_bvh_params_default(&p);
    p.width = width, p.leaf_size = leaf;
    char err[256];
    return TB_CHECK(rt_bvh_build(m, &p, img, NULL, err, sizeof err), "build: %s", err);
}

static void test_brute_force_and_events(void)
{
    const uint32_t ntri = tb_is_sanitized() ? 300 : 1500;
    const int nrays = tb_is_sanitized() ? 300 : 2000;
    rt_mesh m;
    tbt_soup(ntri, 21, &m);
    const int leaves[3] = {1, 4, 8};
    for (int w = RT_WIDTH_MIN; w <= RT_WIDTH_MAX; w++) {
        for (int li = 0; li < 3; li++) {
            char name[128], msg[512] = "";
            snprintf(name, sizeof name, "traverse_soup_width%d_leaf%d_equals_brute_force_events_consistent", w,
                     leaves[li]);
            tb_begin(name);
            rt_bvh_image img;
            if (!build(&m, w, leaves[li], &img)) {
                tb_end();
                continue;
            }
            rt_trv_params p;
            rt_trv_params_default(&p, w);
            rt_rng r;
            rt_rng_seed(&r, 100 + (uint64_t)w, (uint64_t)li);
            ev_log log = {0};
            int wrong = 0, ties = 0, hits = 0, bad_events = 0;
            for (int i = 0; i < nrays; i++) {
                rt_ray ray = tbt_random_ray(&r);
                if (i % 5 == 4)
                    ray.tmax = 2.5f;   /* bounded rays too */
                rt_hit h, b = brute_force(&img, &ray);
                rt_trv_counts c;
                log.n = 0;
                const bool ok = rt_trace_ray(&img, &p, &ray, &h, &c, record, &log);
                hits += h.prim != RT_NO_HIT;
                if (!ok || h.t != b.t || (h.prim == RT_NO_HIT) != (b.prim == RT_NO_HIT)) {
                    if (wrong++ == 0)
                        TB_CHECK(false, "ray %d: ours prim %u t %.9g, brute force %u %.9g", i, h.prim, (double)h.t,
                                 b.prim, (double)b.t);
                } else if (h.prim != b.prim) {
                    ties++;   /* equal t: allowed only if our prim really gives that t */
                    if (prim_t(&img, h.prim, &ray) != h.t && wrong++ == 0)
                        TB_CHECK(false, "ray %d: prim %u differs and its t is not %.9g", i, h.prim, (double)h.t);
                }
                /* without events and counts: the same hit */
                rt_hit h2;
                rt_trace_ray(&img, &p, &ray, &h2, NULL, NULL, NULL);
                if (memcmp(&h, &h2, sizeof h) != 0 && wrong++ == 0)
                    TB_CHECK(false, "ray %d: result depends on the callback", i);
                if (!check_events(&img, &p, &ray, &log, &h, &c, msg, sizeof msg) && bad_events++ == 0)
                    TB_CHECK(false, "ray %d events: %s", i, msg);
            }
            TB_CHECK(wrong == 0 && bad_events == 0, "%d wrong hits, %d bad event streams", wrong, bad_events);
            TB_CHECK(hits > nrays / 5 && hits < nrays, "%d of %d rays hit: test rays not informative", hits, nrays);
            TB_CHECK(ties <= nrays / 100, "%d ties", ties);
            free(log.ev);
            rt_bvh_image_free(&img);
            tb_end();
        }
    }
    rt_mesh_free(&m);
}

/* Two triangles on the z axis at z = -2 (near) and z = -6 (far), one leaf
 * each, ray from the origin along -z: closest-first and distance culling. */
static void test_hand_made_order_and_cull(void)
{
    tb_begin("traverse_closest_first_and_distance_cull_on_two_triangles");
    rt_mesh m;
    memset(&m, 0, sizeof m);
    m.nverts = 6, m.ntris = 2;
    m.verts = malloc(6 * sizeof *m.verts);
    m.tris = malloc(6 * sizeof *m.tris);
    /* far triangle first in the mesh, so mesh order is not closest-first */
    const rt_vec3 v[6] = {{-1, -1, -6}, {1, -1, -6}, {0, 1, -6}, {-1, -1, -2}, {1, -1, -2}, {0, 1, -2}};
    for (int i = 0; i < 6; i++)
        m.verts[i] = v[i], m.tris[i] = (uint32_t)i;
    const rt_ray ray = {{0, 0, 0}, {0, 0, -1}, 0.0f, FLT_MAX, 0, 0, 0};
    for (int w = 2; w <= 4; w += 2) {
        rt_bvh_image img;
        if (!build(&m, w, 1, &img))
            continue;
        for (int cull = 0; cull < 2; cull++) {
            rt_trv_params p;
            rt_trv_params_default(&p, w);
            TB_CHECK(p.distance_cull == (w > 2) && p.stack_depth == 64, "defaults for width %d", w);
            p.distance_cull = cull;
            ev_log log = {0};
            rt_hit h;
            rt_trv_counts c;
            rt_trace_ray(&img, &p, &ray, &h, &c, record, &log);
            TB_CHECK(h.prim == 1 && h.t == 2.0f, "width %d: hit %u t %g", w, h.prim, (double)h.t);
            /* VISIT 0, PUSH far leaf (t 6), LEAF near, TRI hit, then CULL (cull on) or POP + LEAF + TRI miss */
            const int want_n = cull ? 6 : 8;
            TB_CHECK((int)log.n == want_n, "width %d cull %d: %zu events", w, cull, log.n);
            if ((int)log.n == want_n) {
                TB_CHECK(log.ev[0].kind == RT_EV_VISIT && log.ev[1].kind == RT_EV_PUSH && log.ev[1].t == 6.0f &&
                             log.ev[1].b == 1 && log.ev[2].kind == RT_EV_LEAF && log.ev[3].kind == RT_EV_TRI &&
                             log.ev[3].b == 1 && log.ev[3].t == 2.0f,
                         "width %d: not closest-first", w);
                if (cull)
                    TB_CHECK(log.ev[4].kind == RT_EV_CULL && log.ev[4].t == 6.0f && c.culls == 1, "no cull");
                else
                    TB_CHECK(log.ev[4].kind == RT_EV_POP && log.ev[5].kind == RT_EV_LEAF && log.ev[6].kind == RT_EV_TRI &&
                                 log.ev[6].b == 0 && c.tri_tests == 2,
                             "far leaf not tested without culling");
                TB_CHECK(log.ev[log.n - 1].kind == RT_EV_DONE && log.ev[log.n - 1].a == 1, "DONE");
            }
            free(log.ev);
        }
        rt_bvh_image_free(&img);
    }
    /* equal tnear: slot order decides (both boxes start at the same plane) */
    rt_mesh_free(&m);
    tb_end();
}

static void test_cull_never_changes_hits_and_overflow(void)
{
    tb_begin("traverse_distance_cull_same_hits_less_work_stack_overflow_reported");
    rt_mesh m;
    rt_views views;
    char err[512];
    if (!TB_CHECK(rt_builtin_generate("interior", &m, &views, err, sizeof err), "%s", err)) {
        tb_end();
        return;
    }
    rt_bvh_image img;
    if (build(&m, 4, 4, &img)) {
        rt_ray_set prim;
        const uint32_t W = tb_is_sanitized() ? 40 : 160, H = tb_is_sanitized() ? 24 : 90;
        TB_CHECK(rt_ray_set_primary(&views.v[0], W, H, &prim, err, sizeof err), "%s", err);
        TB_EQ_INT(prim.n, W * H);
        TB_CHECK(prim.n == W * H && prim.rays[W + 3].pixel == W + 3 && prim.rays[W + 3].bounce == 0, "pixel order");
        rt_trv_params on, off, tiny;
        rt_trv_params_default(&on, 4);
        off = on, off.distance_cull = false;
        tiny = on, tiny.stack_depth = 1;
        uint64_t work_on = 0, work_off = 0;
        uint32_t diff = 0, overflow = 0, max_stack = 0;
        for (uint32_t i = 0; i < prim.n; i++) {
            rt_hit a, b, t;
            rt_trv_counts ca, cb;
            rt_trace_ray(&img, &on, &prim.rays[i], &a, &ca, NULL, NULL);
            rt_trace_ray(&img, &off, &prim.rays[i], &b, &cb, NULL, NULL);
            diff += memcmp(&a, &b, sizeof a) != 0;
            work_on += ca.visits + ca.tri_tests, work_off += cb.visits + cb.tri_tests;
            max_stack = ca.max_stack > max_stack ? ca.max_stack : max_stack;
            overflow += !rt_trace_ray(&img, &tiny, &prim.rays[i], &t, NULL, NULL, NULL);
        }
        TB_EQ_INT(diff, 0);
        TB_CHECK(work_on < work_off, "culling saved nothing: %llu vs %llu", (unsigned long long)work_on,
                 (unsigned long long)work_off);
        TB_CHECK(max_stack > 1 && overflow > 0, "max stack %u, %u overflows with depth 1", max_stack, overflow);
        /* the ray-set generator reports the overflow by ray */
        rt_ray_set d;
        TB_CHECK(!rt_ray_set_diffuse(&m, &img, &tiny, &prim, 1, 4, &d, err, sizeof err) &&
                     strstr(err, "stack overflow") && strstr(err, "pixel"),
                 "'%s'", err);
        /* diffuse sets: deterministic, generations in order */
        rt_ray_set d1, d2;
        TB_CHECK(rt_ray_set_diffuse(&m, &img, &on, &prim, 1, 4, &d1, err, sizeof err), "%s", err);
        TB_CHECK(rt_ray_set_diffuse(&m, &img, &on, &prim, 1, 4, &d2, err, sizeof err), "%s", err);
        TB_CHECK(d1.n == d2.n && d1.n > prim.n / 2 && memcmp(d1.rays, d2.rays, d1.n * sizeof *d1.rays) == 0,
                 "diffuse sets differ or are small (%u, %u)", d1.n, d2.n);
        bool ordered = true;
        for (uint32_t i = 1; i < d1.n; i++)
            ordered &= d1.rays[i].bounce >= d1.rays[i - 1].bounce && d1.rays[i].bounce >= 1 && d1.rays[i].bounce <= 4;
        TB_CHECK(ordered && d1.rays[d1.n - 1].bounce == 4, "bounce generations out of order");
        rt_ray_set_free(&d1), rt_ray_set_free(&d2), rt_ray_set_free(&prim);
        rt_bvh_image_free(&img);
    }
    rt_mesh_free(&m);
    rt_views_free(&views);
    tb_end();
}

int main(void)
{
    test_hand_made_order_and_cull();
    test_cull_never_changes_hits_and_overflow();
    test_brute_force_and_events();
    return tb_finish();
}
