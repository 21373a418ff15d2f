/* bounce.h — diffuse path tracing: the next ray of a pixel's path.
 *
 * Model (docs/design.md "The workload side"): Lambertian surfaces, cosine-weighted hemisphere
 * sampling about the geometric normal turned to face the incoming ray, at
 * most RT_MAX_BOUNCES_DEFAULT bounces, 1 sample per pixel. The random numbers
 * of bounce b of pixel p come from rt_rng_for_ray(seed, p, b), so a path does
 * not depend on the order rays are processed in (the hardware model completes
 * rays out of order).
 * Self-hit avoidance: the origin is the hit point org + t*dir pushed off the
 * surface along the facing normal by RT_BOUNCE_OFFSET_ULPS float ulps per
 * coordinate (coordinates with |x| < RT_BOUNCE_OFFSET_ORIGIN_BAND move by a
 * fixed RT_BOUNCE_OFFSET_ABS instead), following Waechter & Binder, "A Fast
 * and Robust Method for Avoiding Self-Intersection", Ray Tracing Gems (2019),
 * ch. 6; tmin = 0, tmax = RT_RAY_TMAX. */
#ifndef RTSIM_TRACER_BOUNCE_H
#define RTSIM_TRACER_BOUNCE_H

#include <stdbool.h>
#include <stdint.h>

#include "tracer/io/mesh.h"
#include "tracer/trace/ray.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RT_MAX_BOUNCES_DEFAULT 4        /* the paper: at most 4 bounces */
#define RT_BOUNCE_OFFSET_ULPS 256       /* Waechter & Binder's int_scale */
#define RT_BOUNCE_OFFSET_ORIGIN_BAND (1.0f / 32.0f)   /* their origin() */
#define RT_BOUNCE_OFFSET_ABS (1.0f / 65536.0f)         /* their float_scale */

/* The bounce ray leaving hit *hit of ray *in, or false when the path ends:
 * the ray missed (hit->prim == RT_NO_HIT), in->bounce >= max_bounces, or the
 * hit triangle is degenerate. out->pixel = in->pixel, out->bounce =
 * in->bounce + 1, unit direction. */
bool rt_bounce_ray(const rt_mesh *mesh, const rt_ray *in, const rt_hit *hit,
                   uint64_t seed, uint32_t max_bounces, rt_ray *out);

/* Cosine-weighted direction about unit normal n from two uniforms in [0,1)
 * (Malley's method: uniform disk, concentric map of Shirley & Chiu 1997,
 * projected up to the hemisphere). */
rt_vec3 rt_cosine_hemisphere(rt_vec3 n, float u1, float u2);

/* The hit point of ray *in and the hit triangle's unit geometric normal,
 * turned to face the incoming ray (the hemisphere the ray came from); false
 * when there is no usable hit (a miss, a bad triangle index, a non-finite
 * t, a degenerate triangle). Shared by bounce and occlusion rays. */
bool rt_hit_point_normal(const rt_mesh *mesh, const rt_ray *in, const rt_hit *hit, rt_vec3 *p, rt_vec3 *n);

/* Hit point pushed off the surface along unit normal n (see above). */
rt_vec3 rt_offset_ray_origin(rt_vec3 p, rt_vec3 n);

#ifdef __cplusplus
}
#endif

#endif
