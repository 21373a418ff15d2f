/* occlusion.h — the occlusion-ray workload: ambient-occlusion (AO) rays from
 * the primary hits (paper sec. 3.1: "occlusion rays may bypass the sort").
 *
 * Model (docs/tracer-io.md "Occlusion rays"): each primary ray that hits a
 * non-degenerate triangle spawns `samples` AO rays (default
 * RT_AO_SAMPLES_DEFAULT). Each leaves the hit point, pushed off the surface
 * as a bounce ray is (rt_offset_ray_origin, bounce.h), in a cosine-weighted
 * direction (rt_cosine_hemisphere) about the geometric normal turned to face
 * the incoming ray; tmin = 0, tmax = the AO distance, RT_AO_RADIUS_FRACTION
 * of the scene's bounding-box diagonal (rt_ao_distance). A ray is occluded
 * when any triangle lies in (tmin, tmax); the traversal stops at the first
 * hit it finds (any-hit, traverse.h).
 * Randomness: the two uniforms of sample k of pixel p come from
 * rt_rng_for_ray(seed, p, RT_AO_STREAM + k): streams that no diffuse bounce
 * uses (bounce numbers are 8 bits), and independent of the order rays are
 * traced or completed in. The ray: pixel of the primary, bounce = 1,
 * occlusion = 1. */
#ifndef RTSIM_TRACER_OCCLUSION_H
#define RTSIM_TRACER_OCCLUSION_H

#include <stdbool.h>
#include <stdint.h>

#include "tracer/io/mesh.h"
#include "tracer/trace/ray.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Ours (the paper names occlusion rays but no workload): 4 AO samples per
 * primary hit, about as many rays per pixel as the paper's 4-bounce diffuse
 * paths; the distance a tenth of the scene's size, so that both open and
 * occluded rays are common in the built-in scenes (docs/tracer-io.md). */
#define RT_AO_SAMPLES_DEFAULT 4
#define RT_AO_SAMPLES_MAX 64
#define RT_AO_RADIUS_FRACTION 0.1
#define RT_AO_STREAM 0x10000u

/* The AO distance of a mesh: RT_AO_RADIUS_FRACTION x the diagonal of its
 * bounding box (1 when that is zero or not finite). */
float rt_ao_distance(const rt_mesh *mesh);

/* AO ray k (0-based) of the primary ray *in that hit *hit, with the given
 * tmax; false when there is none (a miss, a degenerate triangle). */
bool rt_ao_ray(const rt_mesh *mesh, const rt_ray *in, const rt_hit *hit, uint64_t seed, uint32_t k, float tmax,
               rt_ray *out);

#ifdef __cplusplus
}
#endif

#endif
