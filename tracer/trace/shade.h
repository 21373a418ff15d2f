/* shade.h — deterministic shading of traced rays into a float RGB frame.
 *
 * Two modes:
 *  - headlight (primary rays only): grey = RT_SHADE_ALBEDO*|cos| between the
 *    geometric normal and the view ray, sky colour for misses; shows geometry.
 *  - path: Lambertian surfaces of albedo RT_SHADE_ALBEDO lit only by the sky
 *    (a blue-white gradient over dir.y). With cosine-weighted bounces the
 *    estimator's throughput is multiplied by the albedo per bounce (cos/pdf
 *    cancel) and a path that escapes adds throughput * sky(dir); a path cut
 *    at the bounce limit adds nothing.
 * Contract: pure functions of their inputs; results in display range [0,1]. */
#ifndef RTSIM_TRACER_SHADE_H
#define RTSIM_TRACER_SHADE_H

#include "tracer/io/mesh.h"
#include "tracer/trace/ray.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RT_SHADE_ALBEDO 0.7f

/* Sky radiance seen along direction dir (need not be unit). */
rt_vec3 rt_shade_sky(rt_vec3 dir);

/* Headlight shade of one primary ray's result. */
rt_vec3 rt_shade_headlight(const rt_mesh *mesh, const rt_ray *ray, const rt_hit *hit);

/* Per-pixel path state for path tracing. */
typedef struct rt_path {
    rt_vec3 throughput;   /* starts at (1,1,1) */
    rt_vec3 radiance;     /* accumulated colour, starts at 0 */
} rt_path;

void rt_path_init(rt_path *p);
/* Accounts for the result of one ray of the path (any bounce): a miss adds
 * throughput*sky(dir); a hit multiplies the throughput by the albedo. */
void rt_path_add(rt_path *p, const rt_ray *ray, const rt_hit *hit);

#ifdef __cplusplus
}
#endif

#endif
