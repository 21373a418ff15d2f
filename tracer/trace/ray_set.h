/* ray_set.h — batches of rays for tests, benchmarks and the Embree check:
 * a view's primary rays and the diffuse bounce rays or the occlusion rays
 * that follow them.
 *
 * Contract: primary rays in pixel order (row-major, top row first);
 * diffuse rays are generated generation by generation (all first bounces in
 * pixel order, then all second bounces, ...) from the reference traversal's
 * hits (traverse.h) with rt_bounce_ray (bounce.h), so the set depends only on
 * the mesh, BVH image, seed and bounce limit, and every tracer can be timed and
 * compared on exactly the same rays. */
#ifndef RTSIM_TRACER_RAY_SET_H
#define RTSIM_TRACER_RAY_SET_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "tracer/bvh/bvh.h"
#include "tracer/trace/ray.h"
#include "tracer/trace/traverse.h"
#include "tracer/io/view.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rt_ray_set {
    rt_ray *rays;
    uint32_t n;
} rt_ray_set;

/* width x height primary rays of view. False with a message on a bad view or
 * resolution, or out of memory. */
bool rt_ray_set_primary(const rt_view *view, uint32_t width, uint32_t height, rt_ray_set *out, char *err,
                        size_t errlen);

/* All bounce rays (bounces 1..max_bounces) of the paths starting with the rays
 * of primary, traced with rt_trace_ray(img, p). False on a stack overflow
 * (message names the ray) or out of memory. */
bool rt_ray_set_diffuse(const rt_mesh *mesh, const rt_bvh_image *img, const rt_trv_params *p,
                        const rt_ray_set *primary, uint64_t seed, uint32_t max_bounces, rt_ray_set *out, char *err,
                        size_t errlen);

/* The occlusion rays (occlusion.h) of the primary rays' hits, traced with
 * rt_trace_ray(img, p): for each primary ray in order, its AO rays 0..samples-1
 * with tmax = ao_tmax. False on a stack overflow or out of memory. */
bool rt_ray_set_occlusion(const rt_mesh *mesh, const rt_bvh_image *img, const rt_trv_params *p,
                          const rt_ray_set *primary, uint64_t seed, uint32_t samples, float ao_tmax, rt_ray_set *out,
                          char *err, size_t errlen);

void rt_ray_set_free(rt_ray_set *s);

#ifdef __cplusplus
}
#endif

#endif
