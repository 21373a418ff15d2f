/* tb_tracer_util.h — helpers shared by the tracer BVH/traversal/Embree
 * testbenches (header-only, like tb.h): deterministic test meshes and rays,
 * and the location of ../shared/scenes. */
#ifndef RTSIM_TB_TRACER_UTIL_H
#define RTSIM_TB_TRACER_UTIL_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tracer/io/mesh.h"
#include "tracer/trace/ray.h"
#include "tracer/util/rng.h"
#include "tracer/trace/traverse.h"

/* The real scenes: $RTSIM_SCENES, else ../shared/scenes from the repository
 * root, else ../../shared/scenes (a git worktree under <root>/wt/); NULL when absent. */
static inline const char *tbt_scenes_dir(void)
{
    const char *e = getenv("RTSIM_SCENES");
    if (e && *e)
        return e;
    if (access("../shared/scenes/README.md", R_OK) == 0)
        return "../shared/scenes";
    if (access("../../shared/scenes/README.md", R_OK) == 0)
        return "../../shared/scenes";
    return NULL;
}

/* Collects a traversal's event stream (an rt_trv_event_fn); free(l.e). */
typedef struct tbt_ev_list {
    rt_trv_event *e;
    size_t n, cap;
} tbt_ev_list;

static inline void tbt_ev_add(void *user, const rt_trv_event *ev)
{
    tbt_ev_list *l = user;
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 256;
        l->e = realloc(l->e, l->cap * sizeof *l->e);
    }
    l->e[l->n++] = *ev;
}

static inline float tbt_uniform(rt_rng *r, float lo, float hi) { return lo + (hi - lo) * rt_rng_float(r); }

/* n random triangles ("soup") in [-1, 1]^3, edges 0.01..0.3 long, three
 * vertices each (no sharing). */
static inline int tbt_soup(uint32_t n, uint64_t seed, rt_mesh *m)
{
    memset(m, 0, sizeof *m);
    m->verts = malloc(3 * (size_t)n * sizeof *m->verts);
    m->tris = malloc(3 * (size_t)n * sizeof *m->tris);
    if (!m->verts || !m->tris)
        return 0;
    rt_rng r;
    rt_rng_seed(&r, seed, 77);
    for (uint32_t i = 0; i < n; i++) {
        const float cx = tbt_uniform(&r, -1, 1), cy = tbt_uniform(&r, -1, 1), cz = tbt_uniform(&r, -1, 1);
        const float s = tbt_uniform(&r, 0.01f, 0.3f);
        for (int k = 0; k < 3; k++) {
            m->verts[3 * i + k] = (rt_vec3){cx + s * tbt_uniform(&r, -1, 1), cy + s * tbt_uniform(&r, -1, 1),
                                            cz + s * tbt_uniform(&r, -1, 1)};
            m->tris[3 * i + k] = 3 * i + k;
        }
    }
    m->nverts = 3 * n, m->ntris = n;
    return 1;
}

/* A ray from a random point on a sphere of radius 3 towards a random point
 * in [-1, 1]^3 (unit direction not required), tmin 0, tmax FLT_MAX. */
static inline rt_ray tbt_random_ray(rt_rng *r)
{
    rt_ray ray;
    memset(&ray, 0, sizeof ray);
    float o[3], l2;
    do {
        for (int a = 0; a < 3; a++)
            o[a] = tbt_uniform(r, -1, 1);
        l2 = o[0] * o[0] + o[1] * o[1] + o[2] * o[2];
    } while (l2 < 0.01f || l2 > 1.0f);
    float s = 3.0f / __builtin_sqrtf(l2);
    ray.org = (rt_vec3){o[0] * s, o[1] * s, o[2] * s};
    ray.dir = (rt_vec3){tbt_uniform(r, -1, 1) - ray.org.x, tbt_uniform(r, -1, 1) - ray.org.y,
                        tbt_uniform(r, -1, 1) - ray.org.z};
    ray.tmin = 0.0f;
    ray.tmax = 3.402823466e+38f;
    return ray;
}

#endif
