/* occlusion.c — see occlusion.h. */
#include "tracer/trace/occlusion.h"

#include <math.h>

#include "tracer/trace/bounce.h"
#include "tracer/util/rng.h"

float rt_ao_distance(const rt_mesh *mesh)
{
    rt_vec3 lo, hi;
    rt_mesh_bounds(mesh, &lo, &hi);
    const double dx = (double)hi.x - lo.x, dy = (double)hi.y - lo.y, dz = (double)hi.z - lo.z;
    const double d = RT_AO_RADIUS_FRACTION * sqrt(dx * dx + dy * dy + dz * dz);
    return d > 0.0 && d < 3e38 ? (float)d : 1.0f;
}

bool rt_ao_ray(const rt_mesh *mesh, const rt_ray *in, const rt_hit *hit, uint64_t seed, uint32_t k, float tmax,
               rt_ray *out)
{
    /* the hemisphere on the side the primary ray came from (as rt_bounce_ray) */
    rt_vec3 p, n;
    if (!rt_hit_point_normal(mesh, in, hit, &p, &n))
        return false;
    rt_rng rng = rt_rng_for_ray(seed, in->pixel, RT_AO_STREAM + k);
    const float u1 = rt_rng_float(&rng), u2 = rt_rng_float(&rng);
    out->org = rt_offset_ray_origin(p, n);
    out->dir = rt_cosine_hemisphere(n, u1, u2);
    out->tmin = 0.0f;
    out->tmax = tmax;
    out->pixel = in->pixel;
    out->bounce = 1;
    out->occlusion = 1;
    return true;
}
