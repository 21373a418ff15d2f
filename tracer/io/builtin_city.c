/* builtin_city.c — "city": a voxel town of axis-aligned boxes seen from
 * above (the role of Rungholt, a Minecraft city, in Viitanen et al. 2016:
 * box-heavy). 6 x 6 blocks separated by streets; each block holds 4 houses
 * built storey by storey from unit boxes with window boxes on two facades, a
 * stepped roof and a chimney; streets get pavement slabs and voxel trees.
 * One voxel = 1 unit, +Y up, ground at y = 0, town centred on the origin. */
#include "tracer/io/builtin_geom.h"

#include "tracer/util/rng.h"

enum { BLOCKS = 6, LOT = 6, STREET = 4 };
static const double BLOCK = 2 * LOT + STREET;   /* block pitch in voxels */

static void house(rt_mesh_builder *b, rt_rng *rng, double x0, double z0)
{
    double w = LOT - 1;                  /* 5 x 5 footprint, 1 voxel garden */
    int storeys = 2 + (int)rt_rng_below(rng, 9);
    for (int s = 0; s < storeys; s++) {
        double y = s;
        rt_mb_box(b, x0, y, z0, x0 + w, y + 1, z0 + w);
        /* two window boxes per storey on the -z and +x facades */
        for (int k = 0; k < 2; k++) {
            double off = 1.0 + 2.0 * k;
            rt_mb_box(b, x0 + off, y + 0.35, z0 - 0.2, x0 + off + 1, y + 0.8, z0);
            rt_mb_box(b, x0 + w, y + 0.35, z0 + off, x0 + w + 0.2, y + 0.8, z0 + off + 1);
        }
    }
    /* stepped roof: three shrinking slabs, then a chimney */
    for (int r = 0; r < 3; r++)
        rt_mb_box(b, x0 + 0.5 * r - 0.3, storeys + r, z0 - 0.3 + r,
                  x0 + w + 0.3 - 0.5 * r, storeys + r + 1, z0 + w + 0.3 - r);
    double cx = x0 + 1 + rt_rng_below(rng, 3);
    rt_mb_box(b, cx, storeys, z0 + 3.5, cx + 1, storeys + 4, z0 + 4.5);
}

static void tree(rt_mesh_builder *b, rt_rng *rng, double x, double z)
{
    int h = 3 + (int)rt_rng_below(rng, 3);
    rt_mb_box(b, x, 0, z, x + 1, h, z + 1);
    for (int dx = -1; dx <= 1; dx++)
        for (int dz = -1; dz <= 1; dz++)
            for (int dy = 0; dy < 2; dy++)
                if (rt_rng_below(rng, 4) != 0)
                    rt_mb_box(b, x + dx, h + dy, z + dz, x + dx + 1, h + dy + 1, z + dz + 1);
}

void rt_builtin_city(rt_mesh_builder *b, rt_views *views)
{
    rt_rng rng;
    rt_rng_seed(&rng, 0xc17c17, 3);
    double half = 0.5 * BLOCKS * BLOCK;
    /* ground: one large quad under everything */
    rt_mb_quad(b, (double[]){-half - 8, 0, -half - 8}, (double[]){-half - 8, 0, half + 8},
               (double[]){half + 8, 0, half + 8}, (double[]){half + 8, 0, -half - 8});
    for (int bx = 0; bx < BLOCKS; bx++)
        for (int bz = 0; bz < BLOCKS; bz++) {
            double x0 = -half + bx * BLOCK + 0.5 * STREET, z0 = -half + bz * BLOCK + 0.5 * STREET;
            /* pavement slab of the block */
            rt_mb_box(b, x0 - 0.5, 0, z0 - 0.5, x0 + 2 * LOT + 0.5, 0.2, z0 + 2 * LOT + 0.5);
            for (int lx = 0; lx < 2; lx++)
                for (int lz = 0; lz < 2; lz++)
                    house(b, &rng, x0 + lx * LOT, z0 + lz * LOT);
            /* two street trees at the block's -x side */
            tree(b, &rng, x0 - 0.5 * STREET - 0.5, z0 + 2);
            tree(b, &rng, x0 - 0.5 * STREET - 0.5, z0 + 2 * LOT - 3);
        }
    rt_mb_view(b, views, "overview", 45.0, 55.0, 45.0, 0.0, 0.0, 0.0, 45.0);
    rt_mb_view(b, views, "street", -52.0, 22.0, 8.0, 10.0, 2.0, -4.0, 50.0);
}
