/* builtin_geom.c — see builtin_geom.h. */
#include "tracer/io/builtin_geom.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static bool reserve(rt_mesh_builder *b, size_t nv, size_t nt)
{
    if (b->oom)
        return false;
    if (b->m.nverts + nv > b->vcap) {
        size_t c = b->vcap ? b->vcap * 2 : 4096;
        while (c < b->m.nverts + nv)
            c *= 2;
        rt_vec3 *p = realloc(b->m.verts, c * sizeof *p);
        if (!p)
            return !(b->oom = true);
        b->m.verts = p;
        b->vcap = c;
    }
    if (b->m.ntris + nt > b->tcap) {
        size_t c = b->tcap ? b->tcap * 2 : 4096;
        while (c < b->m.ntris + nt)
            c *= 2;
        uint32_t *p = realloc(b->m.tris, c * 3 * sizeof *p);
        if (!p)
            return !(b->oom = true);
        b->m.tris = p;
        b->tcap = c;
    }
    return true;
}

uint32_t rt_mb_vert(rt_mesh_builder *b, double x, double y, double z)
{
    if (!reserve(b, 1, 0))
        return 0;
    b->m.verts[b->m.nverts] = (rt_vec3){(float)x, (float)y, (float)z};
    return b->m.nverts++;
}

void rt_mb_tri(rt_mesh_builder *b, uint32_t a, uint32_t c, uint32_t d)
{
    if (!reserve(b, 0, 1))
        return;
    uint32_t *t = b->m.tris + 3 * (size_t)b->m.ntris++;
    t[0] = a, t[1] = c, t[2] = d;
}

void rt_mb_quad(rt_mesh_builder *b, const double p0[3], const double p1[3], const double p2[3],
                const double p3[3])
{
    uint32_t a = rt_mb_vert(b, p0[0], p0[1], p0[2]), c = rt_mb_vert(b, p1[0], p1[1], p1[2]);
    uint32_t d = rt_mb_vert(b, p2[0], p2[1], p2[2]), e = rt_mb_vert(b, p3[0], p3[1], p3[2]);
    rt_mb_tri(b, a, c, d);
    rt_mb_tri(b, a, d, e);
}

void rt_mb_box(rt_mesh_builder *b, double x0, double y0, double z0, double x1, double y1, double z1)
{
    uint32_t v[8];
    for (int i = 0; i < 8; i++)
        v[i] = rt_mb_vert(b, i & 1 ? x1 : x0, i & 2 ? y1 : y0, i & 4 ? z1 : z0);
    /* Faces -x, +x, -y, +y, -z, +z, counter-clockwise seen from outside. */
    static const int f[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (int i = 0; i < 6; i++) {
        rt_mb_tri(b, v[f[i][0]], v[f[i][1]], v[f[i][2]]);
        rt_mb_tri(b, v[f[i][0]], v[f[i][2]], v[f[i][3]]);
    }
}

void rt_mb_cylinder(rt_mesh_builder *b, double cx, double y0, double cz, double radius,
                    double height, int sides, int rings)
{
    uint32_t base = b->m.nverts;
    for (int r = 0; r <= rings; r++)
        for (int s = 0; s < sides; s++) {
            double a = 2 * RT_PI * s / sides;
            rt_mb_vert(b, cx + radius * rt_det_cos(a), y0 + height * r / rings,
                       cz + radius * rt_det_sin(a));
        }
    for (int r = 0; r < rings; r++)
        for (int s = 0; s < sides; s++) {
            uint32_t a = base + (uint32_t)(r * sides + s);
            uint32_t c = base + (uint32_t)(r * sides + (s + 1) % sides);
            rt_mb_tri(b, a, a + (uint32_t)sides, c);
            rt_mb_tri(b, c, a + (uint32_t)sides, c + (uint32_t)sides);
        }
}

void rt_mb_cone(rt_mesh_builder *b, double cx, double y0, double cz, double radius, double height,
                int sides)
{
    uint32_t tip = rt_mb_vert(b, cx, y0 + height, cz), base = b->m.nverts;
    for (int s = 0; s < sides; s++) {
        double a = 2 * RT_PI * s / sides;
        rt_mb_vert(b, cx + radius * rt_det_cos(a), y0, cz + radius * rt_det_sin(a));
    }
    for (int s = 0; s < sides; s++)
        rt_mb_tri(b, base + (uint32_t)s, tip, base + (uint32_t)((s + 1) % sides));
}

void rt_mb_view(rt_mesh_builder *b, rt_views *vs, const char *name, double ex, double ey,
                double ez, double ax, double ay, double az, double fov)
{
    if (!vs)
        return;
    rt_view v;
    memset(&v, 0, sizeof v);
    snprintf(v.name, sizeof v.name, "%s", name);
    v.eye = (rt_vec3){(float)ex, (float)ey, (float)ez};
    v.at = (rt_vec3){(float)ax, (float)ay, (float)az};
    v.up = (rt_vec3){0, 1, 0};
    v.fov_deg = (float)fov;
    if (!rt_views_add(vs, &v, NULL, 0))
        b->oom = true;
}
