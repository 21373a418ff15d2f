/* occlusion.c — see occlusion.h. */
#include "tracer/occlusion.h"

#include <math.h>

#include "tracer/bounce.h"
#include "tracer/rng.h"

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
    if (hit->prim == RT_NO_HIT || hit->prim >= mesh->ntris || !isfinite(hit->t))
        return false;
    rt_vec3 n = rt_mesh_tri_normal(mesh, hit->prim);
    if (n.x == 0 && n.y == 0 && n.z == 0)
        return false;
    /* the hemisphere on the side the primary ray came from (as rt_bounce_ray) */
    if ((double)n.x * in->dir.x + (double)n.y * in->dir.y + (double)n.z * in->dir.z > 0)
        n = (rt_vec3){-n.x, -n.y, -n.z};
    const rt_vec3 p = {in->org.x + hit->t * in->dir.x, in->org.y + hit->t * in->dir.y,
                       in->org.z + hit->t * in->dir.z};
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
