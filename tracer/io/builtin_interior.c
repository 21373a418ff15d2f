/* builtin_interior.c — "interior": a Sponza-like atrium (Crytek Sponza's role
 * in Viitanen et al. 2016: architecture, large triangles). A 40 x 18 x 20 hall
 * open to the sky, two storeys of colonnades with round arches along both
 * long sides, gallery floors over the aisles, walls, and hanging drapes.
 * Units: metres-ish, +Y up, floor at y = 0, hall centred on the origin. */
#include "tracer/io/builtin_geom.h"

#include "tracer/util/rng.h"

enum { COLS = 10 };                       /* columns per colonnade row */
static const double HALL_X = 20.0;        /* half length */
static const double HALL_Z = 10.0;        /* half width incl. aisles */
static const double ROW_Z = 5.0;          /* colonnade rows at z = +-ROW_Z */
static const double EDGE = 4.3;           /* inner edge of the gallery floors, |z| */
static const double STOREY = 8.0;         /* height of the gallery floor */
static const double TOP = 16.0;           /* wall top */

/* A semicircular arch band between columns at x0 and x1 (row z, springing
 * at height y), `seg` segments, thickness t across z, depth h radially. */
static void arch(rt_mesh_builder *b, double x0, double x1, double y, double z, double t, double h,
                 int seg)
{
    double cx = 0.5 * (x0 + x1), r = 0.5 * (x1 - x0);
    for (int i = 0; i < seg; i++) {
        double a0 = RT_PI * i / seg, a1 = RT_PI * (i + 1) / seg;
        double c0 = rt_det_cos(a0), s0 = rt_det_sin(a0), c1 = rt_det_cos(a1), s1 = rt_det_sin(a1);
        double in0[2] = {cx + r * c0, y + r * s0}, in1[2] = {cx + r * c1, y + r * s1};
        double out0[2] = {cx + (r + h) * c0, y + (r + h) * s0};
        double out1[2] = {cx + (r + h) * c1, y + (r + h) * s1};
        double za = z - t, zb = z + t;
        /* intrados (underside), front, back, extrados */
        rt_mb_quad(b, (double[]){in0[0], in0[1], za}, (double[]){in1[0], in1[1], za},
                   (double[]){in1[0], in1[1], zb}, (double[]){in0[0], in0[1], zb});
        rt_mb_quad(b, (double[]){in0[0], in0[1], za}, (double[]){out0[0], out0[1], za},
                   (double[]){out1[0], out1[1], za}, (double[]){in1[0], in1[1], za});
        rt_mb_quad(b, (double[]){in0[0], in0[1], zb}, (double[]){in1[0], in1[1], zb},
                   (double[]){out1[0], out1[1], zb}, (double[]){out0[0], out0[1], zb});
        rt_mb_quad(b, (double[]){out0[0], out0[1], za}, (double[]){out0[0], out0[1], zb},
                   (double[]){out1[0], out1[1], zb}, (double[]){out1[0], out1[1], za});
    }
}

/* Column with square base and capital: shaft radius r from y0 to y1. */
static void column(rt_mesh_builder *b, double x, double z, double y0, double y1, double r,
                   int sides, int rings)
{
    double bs = 1.4 * r, cap = 0.35;
    rt_mb_box(b, x - bs, y0, z - bs, x + bs, y0 + cap, z + bs);
    rt_mb_cylinder(b, x, y0 + cap, z, r, (y1 - y0) - 2 * cap, sides, rings);
    rt_mb_box(b, x - bs, y1 - cap, z - bs, x + bs, y1, z + bs);
}

/* A drape hanging from (x, ytop, z) across x, gently waved, w x h with an
 * nx x ny grid. */
static void drape(rt_mesh_builder *b, rt_rng *rng, double x, double ytop, double z, double w,
                  double h, int nx, int ny)
{
    double phase = 2 * RT_PI * rt_rng_float(rng), amp = 0.15 + 0.1 * rt_rng_float(rng);
    uint32_t base = b->m.nverts;
    for (int j = 0; j <= ny; j++)
        for (int i = 0; i <= nx; i++) {
            double u = (double)i / nx, v = (double)j / ny;
            double wave = amp * (0.3 + v) * rt_det_sin(phase + 6 * RT_PI * u);
            rt_mb_vert(b, x + w * (u - 0.5), ytop - h * v, z + wave);
        }
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            uint32_t a = base + (uint32_t)(j * (nx + 1) + i), c = a + (uint32_t)(nx + 1);
            rt_mb_tri(b, a, c, a + 1);
            rt_mb_tri(b, a + 1, c, c + 1);
        }
}

void rt_builtin_interior(rt_mesh_builder *b, rt_views *views)
{
    rt_rng rng;
    rt_rng_seed(&rng, 0x1e7e210, 1);
    /* Floor (tiled in 4 x 2 large quads), end walls, side walls: large triangles. */
    for (int i = 0; i < 4; i++)
        for (int k = 0; k < 2; k++) {
            double x0 = -HALL_X + 10.0 * i, z0 = -HALL_Z + 10.0 * k;
            rt_mb_quad(b, (double[]){x0, 0, z0}, (double[]){x0, 0, z0 + 10},
                       (double[]){x0 + 10, 0, z0 + 10}, (double[]){x0 + 10, 0, z0});
        }
    rt_mb_box(b, -HALL_X - 1, 0, -HALL_Z - 1, -HALL_X, TOP, HALL_Z + 1);
    rt_mb_box(b, HALL_X, 0, -HALL_Z - 1, HALL_X + 1, TOP, HALL_Z + 1);
    rt_mb_box(b, -HALL_X, 0, -HALL_Z - 1, HALL_X, TOP, -HALL_Z);
    rt_mb_box(b, -HALL_X, 0, HALL_Z, HALL_X, TOP, HALL_Z + 1);
    /* Aisle ceilings = gallery floors; gallery roofs over the upper aisles.
     * The gallery floor reaches EDGE so the balustrade and the upper column
     * bases stand fully on it: no visible coplanar overlapping faces (they
     * would make closest-hit ties between primitives). */
    for (int side = -1; side <= 1; side += 2) {
        double za = side < 0 ? -HALL_Z : EDGE, zb = side < 0 ? -EDGE : HALL_Z;
        rt_mb_box(b, -HALL_X, STOREY, za, HALL_X, STOREY + 0.4, zb);
        rt_mb_box(b, -HALL_X, TOP - 0.4, za, HALL_X, TOP, zb);
        /* balustrade along the gallery edge, on the floor */
        double z0 = side < 0 ? -EDGE - 0.3 : EDGE;
        rt_mb_box(b, -HALL_X, STOREY + 0.4, z0, HALL_X, STOREY + 1.3, z0 + 0.3);
    }
    /* Two storeys of colonnades with arches between neighbouring columns. */
    double pitch = 2 * HALL_X / COLS;
    for (int side = -1; side <= 1; side += 2) {
        double z = side * ROW_Z;
        for (int i = 0; i < COLS; i++) {
            double x = -HALL_X + pitch * (i + 0.5);
            column(b, x, z, 0, STOREY - 2.0, 0.45, 24, 6);
            column(b, x, z, STOREY + 0.4, TOP - 2.6, 0.3, 16, 4);
            if (i + 1 < COLS) {
                double xn = x + pitch;
                arch(b, x + 0.6, xn - 0.6, STOREY - 2.0, z, 0.5, 0.45, 24);
                arch(b, x + 0.45, xn - 0.45, TOP - 2.6, z, 0.4, 0.35, 20);
            }
        }
    }
    /* Drapes hanging from the gallery balustrades into the court. */
    for (int side = -1; side <= 1; side += 2)
        for (int i = 0; i < 4; i++) {
            double x = -HALL_X + pitch * (2.0 * i + 1.5);
            drape(b, &rng, x, STOREY + 1.2, side * (EDGE - 0.4), pitch - 1.6, 5.5, 16, 12);
        }
    rt_mb_view(b, views, "hall", -18.0, 3.5, 0.5, 10.0, 5.0, -0.5, 60.0);
    rt_mb_view(b, views, "gallery", 18.0, 12.5, 0.0, -6.0, 3.0, 2.5, 60.0);
}
