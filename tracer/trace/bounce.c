/* bounce.c — see bounce.h. */
#include "tracer/trace/bounce.h"

#include <math.h>
#include <string.h>

#include "tracer/trace/camera.h"
#include "tracer/util/det_math.h"
#include "tracer/util/rng.h"

rt_vec3 rt_cosine_hemisphere(rt_vec3 n, float u1, float u2)
{
    /* Concentric square-to-disk map (Shirley & Chiu 1997). */
    double a = 2.0 * u1 - 1.0, b = 2.0 * u2 - 1.0, r, phi;
    if (a == 0.0 && b == 0.0) {
        r = 0.0, phi = 0.0;
    } else if (fabs(a) > fabs(b)) {
        r = a, phi = (M_PI / 4.0) * (b / a);
    } else {
        r = b, phi = (M_PI / 2.0) - (M_PI / 4.0) * (a / b);
    }
    double x = r * rt_det_cos(phi), y = r * rt_det_sin(phi);
    double z = sqrt(fmax(0.0, 1.0 - x * x - y * y));   /* Malley: lift disk to hemisphere */
    /* Orthonormal basis around n (Duff et al., "Building an Orthonormal Basis,
     * Revisited", JCGT 2017). */
    double nx = n.x, ny = n.y, nz = n.z;
    double sign = copysign(1.0, nz);
    double aa = -1.0 / (sign + nz), bb = nx * ny * aa;
    double t[3] = {1.0 + sign * nx * nx * aa, sign * bb, -sign * nx};
    double s[3] = {bb, sign + ny * ny * aa, -ny};
    double d[3] = {x * t[0] + y * s[0] + z * nx, x * t[1] + y * s[1] + z * ny,
                   x * t[2] + y * s[2] + z * nz};
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    return (rt_vec3){(float)(d[0] / l), (float)(d[1] / l), (float)(d[2] / l)};
}

/* Moves float x by k units in the last place (sign of k = direction). */
static float offset_ulps(float x, int k)
{
    int32_t i;
    memcpy(&i, &x, sizeof i);
    i += (x < 0) ? -k : k;
    float r;
    memcpy(&r, &i, sizeof r);
    return r;
}

rt_vec3 rt_offset_ray_origin(rt_vec3 p, rt_vec3 n)
{
    float pc[3] = {p.x, p.y, p.z}, nc[3] = {n.x, n.y, n.z}, o[3];
    for (int i = 0; i < 3; i++) {
        if (fabsf(pc[i]) < RT_BOUNCE_OFFSET_ORIGIN_BAND)
            o[i] = pc[i] + RT_BOUNCE_OFFSET_ABS * nc[i];
        else
            o[i] = offset_ulps(pc[i], (int)(RT_BOUNCE_OFFSET_ULPS * nc[i]));
    }
    return (rt_vec3){o[0], o[1], o[2]};
}

bool rt_hit_point_normal(const rt_mesh *mesh, const rt_ray *in, const rt_hit *hit, rt_vec3 *p, rt_vec3 *n)
{
    if (hit->prim == RT_NO_HIT || hit->prim >= mesh->ntris || !isfinite(hit->t))
        return false;
    *n = rt_mesh_tri_normal(mesh, hit->prim);
    if (n->x == 0 && n->y == 0 && n->z == 0)
        return false;
    /* Face the normal against the incoming ray: leave on the side it came from. */
    if ((double)n->x * in->dir.x + (double)n->y * in->dir.y + (double)n->z * in->dir.z > 0)
        *n = (rt_vec3){-n->x, -n->y, -n->z};
    *p = (rt_vec3){in->org.x + hit->t * in->dir.x, in->org.y + hit->t * in->dir.y, in->org.z + hit->t * in->dir.z};
    return true;
}

bool rt_bounce_ray(const rt_mesh *mesh, const rt_ray *in, const rt_hit *hit, uint64_t seed,
                   uint32_t max_bounces, rt_ray *out)
{
    rt_vec3 p, n;
    if (in->bounce >= max_bounces || !rt_hit_point_normal(mesh, in, hit, &p, &n))
        return false;
    rt_rng rng = rt_rng_for_ray(seed, in->pixel, in->bounce + 1u);
    float u1 = rt_rng_float(&rng), u2 = rt_rng_float(&rng);
    out->org = rt_offset_ray_origin(p, n);
    out->dir = rt_cosine_hemisphere(n, u1, u2);
    out->tmin = 0.0f;
    out->tmax = RT_RAY_TMAX;
    out->pixel = in->pixel;
    out->bounce = (uint8_t)(in->bounce + 1u);
    out->occlusion = 0;
    return true;
}
