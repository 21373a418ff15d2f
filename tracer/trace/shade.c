/* shade.c — see shade.h. */
#include "tracer/trace/shade.h"

#include <math.h>

rt_vec3 rt_shade_sky(rt_vec3 dir)
{
    /* Gradient from white-grey at the horizon and below to light blue at the
     * zenith; t = y component of the unit direction mapped to [0,1]. */
    double l = sqrt((double)dir.x * dir.x + (double)dir.y * dir.y + (double)dir.z * dir.z);
    double t = l > 0 ? 0.5 * (dir.y / l + 1.0) : 0.5;
    return (rt_vec3){(float)(1.0 - 0.5 * t), (float)(1.0 - 0.3 * t), 1.0f};
}

rt_vec3 rt_shade_headlight(const rt_mesh *mesh, const rt_ray *ray, const rt_hit *hit)
{
    if (hit->prim == RT_NO_HIT || hit->prim >= mesh->ntris)
        return rt_shade_sky(ray->dir);
    rt_vec3 n = rt_mesh_tri_normal(mesh, hit->prim);
    double l = sqrt((double)ray->dir.x * ray->dir.x + (double)ray->dir.y * ray->dir.y +
                    (double)ray->dir.z * ray->dir.z);
    double c = l > 0 ? fabs(n.x * ray->dir.x + n.y * ray->dir.y + n.z * ray->dir.z) / l : 0;
    float g = (float)(RT_SHADE_ALBEDO * c);
    return (rt_vec3){g, g, g};
}

void rt_path_init(rt_path *p)
{
    p->throughput = (rt_vec3){1, 1, 1};
    p->radiance = (rt_vec3){0, 0, 0};
}

void rt_path_add(rt_path *p, const rt_ray *ray, const rt_hit *hit)
{
    if (hit->prim == RT_NO_HIT) {
        rt_vec3 s = rt_shade_sky(ray->dir);
        p->radiance.x += p->throughput.x * s.x;
        p->radiance.y += p->throughput.y * s.y;
        p->radiance.z += p->throughput.z * s.z;
        p->throughput = (rt_vec3){0, 0, 0};
    } else {
        p->throughput.x *= RT_SHADE_ALBEDO;
        p->throughput.y *= RT_SHADE_ALBEDO;
        p->throughput.z *= RT_SHADE_ALBEDO;
    }
}
