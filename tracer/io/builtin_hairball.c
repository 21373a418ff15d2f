/* builtin_hairball.c — "hairball": a dense tangle of thin tubes in a ball
 * (the role of Laine's Hairball in Viitanen et al. 2016: many thin
 * triangles, the triangle-heavy extreme). Like the fur ball stand-in in
 * ../shared/scenes, every strand segment is an open triangular prism
 * (3 sides, 6 triangles) around a random-walk axis inside a unit sphere. */
#include "tracer/io/builtin_geom.h"

#include "tracer/util/rng.h"

enum { STRANDS = 700, SEGMENTS = 20 };   /* 700 * 20 * 6 = 84,000 triangles */
static const double STEP = 0.10;         /* axis step length */
static const double RADIUS = 0.010;      /* tube radius */
static const double BALL = 1.0;          /* strands stay inside this sphere */

static void normalize(double v[3])
{
    double l = rt_det_sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= l, v[1] /= l, v[2] /= l;
}

/* A uniformly random point direction (rejection sampling in the cube). */
static void random_unit(rt_rng *rng, double v[3])
{
    double l2;
    do {
        for (int k = 0; k < 3; k++)
            v[k] = 2.0 * rt_rng_float(rng) - 1.0;
        l2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    } while (l2 > 1.0 || l2 < 1e-4);
    normalize(v);
}

void rt_builtin_hairball(rt_mesh_builder *b, rt_views *views)
{
    rt_rng rng;
    rt_rng_seed(&rng, 0x4a17ba11, 2);
    for (int s = 0; s < STRANDS; s++) {
        double p[3], d[3];
        random_unit(&rng, p);
        double r0 = BALL * rt_det_sqrt(rt_rng_float(&rng));
        for (int k = 0; k < 3; k++)
            p[k] *= r0;
        random_unit(&rng, d);
        uint32_t prev = 0;
        for (int i = 0; i <= SEGMENTS; i++) {
            /* Ring of 3 vertices around the axis, perpendicular to d
             * (frame of Duff et al., JCGT 2017). */
            double sign = d[2] >= 0 ? 1.0 : -1.0;
            double a = -1.0 / (sign + d[2]), bb = d[0] * d[1] * a;
            double t[3] = {1.0 + sign * d[0] * d[0] * a, sign * bb, -sign * d[0]};
            double u[3] = {bb, sign + d[1] * d[1] * a, -d[1]};
            uint32_t ring = b->m.nverts;
            for (int k = 0; k < 3; k++) {
                double ang = 2.0 * RT_PI * k / 3.0 + 0.7 * i;
                double c = RADIUS * rt_det_cos(ang), sn = RADIUS * rt_det_sin(ang);
                rt_mb_vert(b, p[0] + c * t[0] + sn * u[0], p[1] + c * t[1] + sn * u[1],
                           p[2] + c * t[2] + sn * u[2]);
            }
            if (i > 0)
                for (int k = 0; k < 3; k++) {
                    uint32_t a0 = prev + (uint32_t)k, a1 = prev + (uint32_t)((k + 1) % 3);
                    uint32_t b0 = ring + (uint32_t)k, b1 = ring + (uint32_t)((k + 1) % 3);
                    rt_mb_tri(b, a0, a1, b1);
                    rt_mb_tri(b, a0, b1, b0);
                }
            prev = ring;
            /* Curl: perturb the direction, turn back toward the centre near the surface. */
            double w[3];
            random_unit(&rng, w);
            for (int k = 0; k < 3; k++)
                d[k] += 0.6 * w[k];
            double r2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
            if (r2 > 0.8 * 0.8 * BALL * BALL)
                for (int k = 0; k < 3; k++)
                    d[k] -= 0.8 * p[k];
            normalize(d);
            for (int k = 0; k < 3; k++)
                p[k] += STEP * d[k];
        }
    }
    rt_mb_view(b, views, "front", 0.0, 0.5, 2.9, 0.0, 0.0, 0.0, 40.0);
    rt_mb_view(b, views, "oblique", 2.0, 1.2, 1.9, 0.0, 0.0, 0.0, 40.0);
}
