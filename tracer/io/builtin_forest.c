/* builtin_forest.c — "forest": an outdoor scene with foliage (the role of
 * Fairy Forest in Viitanen et al. 2016): rolling ground, broadleaf trees
 * whose crowns are many small leaf quads at random orientations, pine trees
 * of stacked cones, and grass blades. +Y up, ground near y = 0. */
#include "tracer/io/builtin_geom.h"

#include "tracer/util/rng.h"

enum { GRID = 48, BROADLEAF = 40, PINES = 40, LEAVES = 220, GRASS = 600 };
static const double EXTENT = 30.0;   /* ground spans [-EXTENT, EXTENT]^2 */

static double ground_height(double x, double z)
{
    return 0.8 * rt_det_sin(0.21 * x) * rt_det_cos(0.17 * z) + 0.4 * rt_det_sin(0.5 * x + 0.3 * z);
}

static void broadleaf(rt_mesh_builder *b, rt_rng *rng, double x, double z)
{
    double y0 = ground_height(x, z), h = 3.0 + 2.0 * rt_rng_float(rng);
    rt_mb_cylinder(b, x, y0 - 0.2, z, 0.22, h + 0.2, 8, 3);
    double cr = 1.8 + rt_rng_float(rng), cy = y0 + h + 0.8 * cr;
    for (int i = 0; i < LEAVES; i++) {
        /* leaf centre uniformly in the crown ellipsoid */
        double c[3];
        do {
            for (int k = 0; k < 3; k++)
                c[k] = 2.0 * rt_rng_float(rng) - 1.0;
        } while (c[0] * c[0] + c[1] * c[1] + c[2] * c[2] > 1.0);
        double px = x + cr * c[0], py = cy + 0.8 * cr * c[1], pz = z + cr * c[2];
        /* leaf quad: two random tangent directions of length ~0.25 */
        double a = 2 * RT_PI * rt_rng_float(rng), t = RT_PI * (rt_rng_float(rng) - 0.5);
        double e1[3] = {0.25 * rt_det_cos(a), 0.25 * rt_det_sin(t), 0.25 * rt_det_sin(a)};
        double e2[3] = {-0.15 * rt_det_sin(a), 0.15 * rt_det_cos(t), 0.15 * rt_det_cos(a)};
        rt_mb_quad(b, (double[]){px - e1[0] - e2[0], py - e1[1] - e2[1], pz - e1[2] - e2[2]},
                   (double[]){px + e1[0] - e2[0], py + e1[1] - e2[1], pz + e1[2] - e2[2]},
                   (double[]){px + e1[0] + e2[0], py + e1[1] + e2[1], pz + e1[2] + e2[2]},
                   (double[]){px - e1[0] + e2[0], py - e1[1] + e2[1], pz - e1[2] + e2[2]});
    }
}

static void pine(rt_mesh_builder *b, rt_rng *rng, double x, double z)
{
    double y0 = ground_height(x, z), h = 6.0 + 3.0 * rt_rng_float(rng);
    rt_mb_cylinder(b, x, y0 - 0.2, z, 0.18, 0.3 * h, 6, 2);
    for (int k = 0; k < 4; k++) {
        double base = y0 + 0.25 * h + 0.18 * h * k, r = 1.8 - 0.35 * k;
        rt_mb_cone(b, x, base, z, r, 0.35 * h, 14);
    }
}

void rt_builtin_forest(rt_mesh_builder *b, rt_views *views)
{
    rt_rng rng;
    rt_rng_seed(&rng, 0xf0e57, 4);
    /* ground heightfield, GRID x GRID cells */
    uint32_t base = b->m.nverts;
    for (int j = 0; j <= GRID; j++)
        for (int i = 0; i <= GRID; i++) {
            double x = -EXTENT + 2 * EXTENT * i / GRID, z = -EXTENT + 2 * EXTENT * j / GRID;
            rt_mb_vert(b, x, ground_height(x, z), z);
        }
    for (int j = 0; j < GRID; j++)
        for (int i = 0; i < GRID; i++) {
            uint32_t a = base + (uint32_t)(j * (GRID + 1) + i), c = a + GRID + 1;
            rt_mb_tri(b, a, c, a + 1);
            rt_mb_tri(b, a + 1, c, c + 1);
        }
    for (int i = 0; i < BROADLEAF + PINES; i++) {
        double x = (2 * rt_rng_float(&rng) - 1) * (EXTENT - 3);
        double z = (2 * rt_rng_float(&rng) - 1) * (EXTENT - 3);
        if (i % 2)
            broadleaf(b, &rng, x, z);
        else
            pine(b, &rng, x, z);
    }
    for (int i = 0; i < GRASS; i++) {
        double x = (2 * rt_rng_float(&rng) - 1) * EXTENT * 0.9;
        double z = (2 * rt_rng_float(&rng) - 1) * EXTENT * 0.9;
        double y = ground_height(x, z), a = 2 * RT_PI * rt_rng_float(&rng);
        double dx = 0.06 * rt_det_cos(a), dz = 0.06 * rt_det_sin(a);
        double h = 0.4 + 0.5 * rt_rng_float(&rng);
        uint32_t v0 = rt_mb_vert(b, x - dx, y - 0.05, z - dz);
        uint32_t v1 = rt_mb_vert(b, x + dx, y - 0.05, z + dz);
        uint32_t v2 = rt_mb_vert(b, x + 2 * dz, y + h, z - 2 * dx);
        rt_mb_tri(b, v0, v1, v2);
    }
    rt_mb_view(b, views, "ground", -24.0, 2.5, 24.0, 0.0, 4.0, 0.0, 55.0);
    rt_mb_view(b, views, "above", 28.0, 20.0, 28.0, 0.0, 2.0, 0.0, 55.0);
}
