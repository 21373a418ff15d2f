/* ray.h — one ray and its closest hit, shared by ray generation, the
 * reference traversal, the Embree check and the hardware model.
 *
 * Contract: org/dir in world space, dir not necessarily unit length; a hit is
 * accepted for tmin < t < tmax (tmax shrinks as hits are found). prim is the
 * mesh's triangle index (see mesh.h) or RT_NO_HIT. An occlusion ray
 * (occlusion = 1, tracer/trace/occlusion.h) asks only whether anything lies in
 * (tmin, tmax): the first hit found ends it (any-hit traversal, traverse.h),
 * so its hit is *a* hit, not necessarily the closest. */
#ifndef RTSIM_TRACER_RAY_H
#define RTSIM_TRACER_RAY_H

#include <stdint.h>

#include "tracer/io/mesh.h"

#define RT_NO_HIT UINT32_MAX

typedef struct rt_ray {
    rt_vec3 org;
    rt_vec3 dir;
    float tmin, tmax;
    uint32_t pixel;   /* y * width + x of the pixel this ray belongs to */
    uint8_t bounce;   /* 0 = primary, 1.. = diffuse bounce number (occlusion rays: 1) */
    uint8_t occlusion; /* 1: occlusion ray, any hit ends it; 0: closest hit */
} rt_ray;

typedef struct rt_hit {
    float t;          /* distance along dir (in units of |dir|) */
    float u, v;       /* barycentric coordinates of the hit */
    uint32_t prim;    /* triangle index, or RT_NO_HIT */
} rt_hit;

#endif
