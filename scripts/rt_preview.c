/* rt_preview.c — renders small preview PNGs of scenes for the docs, using
 * the tracer I/O API (scene loading, camera, bounce, shade, image).
 *
 *   rt_preview SCENE OUT.png [--view NAME] [--res WxH] [--path] [--spp N] [--seed N]
 *
 * --path: diffuse path tracing (bounce.h, shade.h), averaged over N frames
 * with seeds seed .. seed+N-1 (default N = 1, the simulated workload).
 *
 * Intersection here is a self-contained median-split BVH with the
 * Moeller-Trumbore test (Moeller & Trumbore, JGT 1997): a preview tool, not
 * the reference traversal (that one implements the hardware algorithm and
 * lives with the BVH builders). Exit 0 ok, 2 bad usage or input. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tracer/trace/bounce.h"
#include "tracer/trace/camera.h"
#include "tracer/io/image.h"
#include "tracer/io/scene.h"
#include "tracer/trace/shade.h"

typedef struct node {
    float lo[3], hi[3];
    uint32_t first, count;   /* leaf: prims [first, first+count); inner: count = 0, first = right child */
} node;

typedef struct bvh {
    node *nodes;
    uint32_t *prims, nnodes;
    const rt_mesh *m;
    float *cent;
} bvh;

static void bounds_of(bvh *b, uint32_t first, uint32_t count, node *n)
{
    for (int k = 0; k < 3; k++)
        n->lo[k] = FLT_MAX, n->hi[k] = -FLT_MAX;
    for (uint32_t i = first; i < first + count; i++)
        for (int v = 0; v < 3; v++) {
            const float *p = &b->m->verts[b->m->tris[3 * b->prims[i] + v]].x;
            for (int k = 0; k < 3; k++)
                n->lo[k] = fminf(n->lo[k], p[k]), n->hi[k] = fmaxf(n->hi[k], p[k]);
        }
}

static int axis_sel;
static const float *cent_sel;
static int cmp_cent(const void *a, const void *b)
{
    float x = cent_sel[3 * *(const uint32_t *)a + axis_sel], y = cent_sel[3 * *(const uint32_t *)b + axis_sel];
    if (x != y)
        return x < y ? -1 : 1;
    return *(const uint32_t *)a < *(const uint32_t *)b ? -1 : 1;   /* deterministic ties */
}

static uint32_t build(bvh *b, uint32_t first, uint32_t count)
{
    uint32_t id = b->nnodes++;
    node *n = &b->nodes[id];
    bounds_of(b, first, count, n);
    n->first = first, n->count = count;
    if (count <= 4)
        return id;
    int axis = 0;
    for (int k = 1; k < 3; k++)
        if (n->hi[k] - n->lo[k] > n->hi[axis] - n->lo[axis])
            axis = k;
    axis_sel = axis, cent_sel = b->cent;
    qsort(b->prims + first, count, sizeof *b->prims, cmp_cent);
    uint32_t half = count / 2;
    b->nodes[id].count = 0;
    build(b, first, half);
    uint32_t right = build(b, first + half, count - half);
    b->nodes[id].first = right;
    return id;
}

static bool slab(const node *n, const float o[3], const float inv[3], float tmax)
{
    float t0 = 0, t1 = tmax;
    for (int k = 0; k < 3; k++) {
        float a = (n->lo[k] - o[k]) * inv[k], c = (n->hi[k] - o[k]) * inv[k];
        if (a > c) {
            float s = a;
            a = c, c = s;
        }
        t0 = a > t0 ? a : t0;
        t1 = c < t1 ? c : t1;
    }
    return t0 <= t1;
}

static void intersect(const bvh *b, const rt_ray *r, rt_hit *h)
{
    float o[3] = {r->org.x, r->org.y, r->org.z}, d[3] = {r->dir.x, r->dir.y, r->dir.z}, inv[3];
    for (int k = 0; k < 3; k++)
        inv[k] = 1.0f / d[k];
    h->t = r->tmax, h->prim = RT_NO_HIT, h->u = h->v = 0;
    uint32_t stack[128], sp = 0;
    stack[sp++] = 0;
    while (sp) {
        uint32_t id = stack[--sp];
        const node *n = &b->nodes[id];
        if (!slab(n, o, inv, h->t))
            continue;
        if (n->count == 0) {
            stack[sp++] = n->first;
            stack[sp++] = id + 1;
            continue;
        }
        for (uint32_t i = n->first; i < n->first + n->count; i++) {
            uint32_t p = b->prims[i];
            const rt_vec3 *v0 = &b->m->verts[b->m->tris[3 * p]], *v1 = &b->m->verts[b->m->tris[3 * p + 1]],
                          *v2 = &b->m->verts[b->m->tris[3 * p + 2]];
            float e1[3] = {v1->x - v0->x, v1->y - v0->y, v1->z - v0->z};
            float e2[3] = {v2->x - v0->x, v2->y - v0->y, v2->z - v0->z};
            float pv[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
            float det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
            if (fabsf(det) < 1e-20f)
                continue;
            float id_ = 1.0f / det;
            float tv[3] = {o[0] - v0->x, o[1] - v0->y, o[2] - v0->z};
            float u = (tv[0] * pv[0] + tv[1] * pv[1] + tv[2] * pv[2]) * id_;
            if (u < 0 || u > 1)
                continue;
            float q[3] = {tv[1] * e1[2] - tv[2] * e1[1], tv[2] * e1[0] - tv[0] * e1[2], tv[0] * e1[1] - tv[1] * e1[0]};
            float v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * id_;
            if (v < 0 || u + v > 1)
                continue;
            float t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * id_;
            if (t > r->tmin && t < h->t)
                h->t = t, h->u = u, h->v = v, h->prim = p;
        }
    }
}

static int usage(const char *msg)
{
    fprintf(stderr, "rt_preview: %s\nusage: rt_preview SCENE OUT.png|OUT.exr [--view NAME] [--res WxH] [--path] [--spp N] [--seed N]\n", msg);
    return 2;
}

int main(int argc, char **argv)
{
    if (argc < 3)
        return usage("need SCENE and OUT");
    const char *view_name = NULL;
    uint32_t w = 320, h = 180;
    bool path = false;
    unsigned long long seed = 1;
    unsigned spp = 1;
    char err[1024];
    for (int i = 3; i < argc; i++) {
        if (!strcmp(argv[i], "--view") && i + 1 < argc)
            view_name = argv[++i];
        else if (!strcmp(argv[i], "--res") && i + 1 < argc) {
            if (!rt_parse_resolution(argv[++i], &w, &h, err, sizeof err))
                return usage(err);
        } else if (!strcmp(argv[i], "--path"))
            path = true;
        else if (!strcmp(argv[i], "--spp") && i + 1 < argc) {
            spp = (unsigned)strtoul(argv[++i], NULL, 10);
            if (spp < 1 || spp > 4096)
                return usage("--spp must be 1..4096");
        } else if (!strcmp(argv[i], "--seed") && i + 1 < argc)
            seed = strtoull(argv[++i], NULL, 10);
        else
            return usage("unknown option");
    }
    if (!rt_image_format_supported(argv[2]))
        return usage("OUT must end .png or .exr");
    rt_scene s;
    if (!rt_scene_load(argv[1], &s, err, sizeof err))
        return usage(err);
    const rt_view *view = rt_scene_view(&s, view_name, err, sizeof err);
    rt_camera cam;
    if (!view || !rt_camera_init(&cam, view, w, h, err, sizeof err)) {
        rt_scene_free(&s);
        return usage(err);
    }
    bvh b = {0};
    b.m = &s.mesh;
    b.nodes = malloc(2 * (size_t)s.mesh.ntris * sizeof *b.nodes);
    b.prims = malloc((size_t)s.mesh.ntris * sizeof *b.prims);
    b.cent = malloc(3 * (size_t)s.mesh.ntris * sizeof *b.cent);
    float *rgb = malloc(3 * (size_t)w * h * sizeof *rgb);
    if (!b.nodes || !b.prims || !b.cent || !rgb)
        return usage("out of memory");
    for (uint32_t i = 0; i < s.mesh.ntris; i++) {
        b.prims[i] = i;
        for (int k = 0; k < 3; k++) {
            float c = 0;
            for (int v = 0; v < 3; v++)
                c += (&s.mesh.verts[s.mesh.tris[3 * i + v]].x)[k];
            b.cent[3 * i + k] = c / 3;
        }
    }
    build(&b, 0, s.mesh.ntris);
    for (uint32_t py = 0; py < h; py++)
        for (uint32_t px = 0; px < w; px++) {
            rt_ray r = rt_camera_primary_ray(&cam, px, py);
            rt_hit hit;
            intersect(&b, &r, &hit);
            rt_vec3 c;
            if (!path) {
                c = rt_shade_headlight(&s.mesh, &r, &hit);
            } else {
                rt_ray primary = r;
                rt_hit first = hit;
                c = (rt_vec3){0, 0, 0};
                for (unsigned k = 0; k < spp; k++) {
                    rt_path p;
                    rt_path_init(&p);
                    r = primary, hit = first;
                    rt_path_add(&p, &r, &hit);
                    rt_ray next;
                    while (rt_bounce_ray(&s.mesh, &r, &hit, seed + k, RT_MAX_BOUNCES_DEFAULT, &next)) {
                        r = next;
                        intersect(&b, &r, &hit);
                        rt_path_add(&p, &r, &hit);
                    }
                    c.x += p.radiance.x / spp, c.y += p.radiance.y / spp, c.z += p.radiance.z / spp;
                }
                /* radiance is linear: encode with display gamma 2.2 for the PNG */
                c = (rt_vec3){powf(c.x, 1 / 2.2f), powf(c.y, 1 / 2.2f), powf(c.z, 1 / 2.2f)};
            }
            float *o = rgb + 3 * ((size_t)py * w + px);
            o[0] = c.x, o[1] = c.y, o[2] = c.z;
        }
    bool ok = rt_image_write_rgb(argv[2], rgb, w, h, err, sizeof err);
    if (!ok)
        fprintf(stderr, "rt_preview: %s\n", err);
    else
        fprintf(stderr, "rt_preview: %s view %s: %u triangles -> %s\n", s.name, view->name, s.mesh.ntris, argv[2]);
    free(rgb), free(b.nodes), free(b.prims), free(b.cent);
    rt_scene_free(&s);
    return ok ? 0 : 2;
}
