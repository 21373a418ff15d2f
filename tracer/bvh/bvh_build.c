/* bvh_build.c — rt_bvh_build (bvh.h): checks the parameters and the mesh,
 * runs the binned SAH builder (bvh2_sah.c), collapses and lays out the image
 * (bvh_image.c, mbvh_collapse.c) and names the result with a hash. */
#include "tracer/bvh/bvh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tracer/bvh/bvh2_sah.h"
#include "tracer/bvh/bvh_image.h"
#include "tracer/io/scene_error.h"

void rt_bvh_params_default(rt_bvh_params *p)
{
    p->width = 4;
    p->builder = RT_BUILD_COLLAPSE;
    p->leaf_size = 4;
    p->bins = 16;
    p->cost_node = 1.0f;
    p->cost_tri = 1.0f;
}

static bool check_params(const rt_bvh_params *p, char *err, size_t errlen)
{
    if (p->width < RT_WIDTH_MIN || p->width > RT_WIDTH_MAX) {
        rt_scene_errorf(err, errlen, "BVH width %d out of range; allowed %d..%d", p->width, RT_WIDTH_MIN,
                        RT_WIDTH_MAX);
        return false;
    }
    if (p->builder != RT_BUILD_COLLAPSE && p->builder != RT_BUILD_WALD) {
        rt_scene_errorf(err, errlen, "BVH builder %d out of range; allowed %d (collapse) or %d (wald)", p->builder,
                        RT_BUILD_COLLAPSE, RT_BUILD_WALD);
        return false;
    }
    if (p->leaf_size < 1 || p->leaf_size > (int)RT_LEAF_MAX) {
        rt_scene_errorf(err, errlen, "BVH leaf_size %d out of range; allowed 1..%u", p->leaf_size, RT_LEAF_MAX);
        return false;
    }
    if (p->bins < 4 || p->bins > 256) {
        rt_scene_errorf(err, errlen, "BVH bins %d out of range; allowed 4..256", p->bins);
        return false;
    }
    if (!(p->cost_node > 0.0f && p->cost_node <= 1e6f)) {
        rt_scene_errorf(err, errlen, "BVH cost_node %g out of range; allowed (0, 1e6]", (double)p->cost_node);
        return false;
    }
    if (!(p->cost_tri > 0.0f && p->cost_tri <= 1e6f)) {
        rt_scene_errorf(err, errlen, "BVH cost_tri %g out of range; allowed (0, 1e6]", (double)p->cost_tri);
        return false;
    }
    return true;
}

static bool check_mesh(const rt_mesh *m, char *err, size_t errlen)
{
    if (m->ntris == 0) {
        rt_scene_errorf(err, errlen, "BVH: the mesh has no triangles; at least 1 is needed");
        return false;
    }
    if (m->ntris > (UINT32_MAX - 1) / 2) {
        rt_scene_errorf(err, errlen, "BVH: %u triangles; at most %u supported", m->ntris, (UINT32_MAX - 1) / 2);
        return false;
    }
    for (uint64_t i = 0; i < 3ull * m->ntris; i++) {
        if (m->tris[i] >= m->nverts) {
            rt_scene_errorf(err, errlen, "BVH: triangle %llu uses vertex %u; the mesh has %u vertices",
                            (unsigned long long)(i / 3), m->tris[i], m->nverts);
            return false;
        }
    }
    for (uint32_t i = 0; i < m->nverts; i++) {
        const rt_vec3 v = m->verts[i];
        if (!isfinite(v.x) || !isfinite(v.y) || !isfinite(v.z)) {
            rt_scene_errorf(err, errlen, "BVH: vertex %u is not finite; coordinates must be finite", i);
            return false;
        }
    }
    return true;
}

/* FNV-1a 64 (http://www.isthe.com/chongo/tech/comp/fnv/) over 64-bit
 * little-endian words instead of bytes (8x fewer multiplies on a 100 MB
 * image); a zero-padded tail word. */
static uint64_t fnv1a_words(uint64_t h, const uint8_t *p, uint64_t n)
{
    uint64_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t w;
        memcpy(&w, p + i, 8);
        h ^= w;
        h *= 1099511628211ULL;
    }
    if (i < n) {
        uint64_t w = 0;
        memcpy(&w, p + i, (size_t)(n - i));
        h ^= w;
        h *= 1099511628211ULL;
    }
    return h;
}

bool rt_bvh_build(const rt_mesh *mesh, const rt_bvh_params *params, rt_bvh_image *out, rt_bvh_stats *stats,
                  char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    rt_bvh_stats local;
    if (!stats)
        stats = &local;
    memset(stats, 0, sizeof *stats);
    if (!check_params(params, err, errlen) || !check_mesh(mesh, err, errlen))
        return false;
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    rt_bvh2 b;
    if (!rt_bvh2_build_sah(mesh, params, &b)) {
        rt_scene_errorf(err, errlen, "BVH: out of memory building the BVH2 of %u triangles", mesh->ntris);
        return false;
    }
    const bool ok = rt_bvh_layout_image(mesh, &b, params, out, stats);
    rt_bvh2_free(&b);
    if (!ok) {
        rt_scene_errorf(err, errlen, "BVH: out of memory laying out the image of %u triangles", mesh->ntris);
        return false;
    }
    /* the builder joins the hash only when it changes the tree (the hash of
     * every collapse image stays what it was before builders were named) */
    const int32_t wald = params->width > 2 && params->builder == RT_BUILD_WALD;
    const int32_t pv[5] = {params->width, params->leaf_size, params->bins, 0, 0};
    uint8_t pb[32];
    memcpy(pb, pv, 12);
    memcpy(pb + 12, &params->cost_node, 4);
    memcpy(pb + 16, &params->cost_tri, 4);
    const uint64_t mh = rt_mesh_hash(mesh);
    memcpy(pb + 20, &mh, 8);
    memcpy(pb + 28, &wald, 4);
    uint64_t h = fnv1a_words(14695981039346656037ULL, pb, sizeof pb);
    out->hash = fnv1a_words(h, out->bytes, out->size);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    stats->build_seconds = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    return true;
}

void rt_bvh_image_free(rt_bvh_image *img)
{
    free(img->bytes);
    memset(img, 0, sizeof *img);
}
