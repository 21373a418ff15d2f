/* mesh.c — see mesh.h. */
#include "tracer/io/mesh.h"
#include "tracer/util/fnv1a.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void rt_mesh_free(rt_mesh *m)
{
    free(m->verts);
    free(m->tris);
    memset(m, 0, sizeof *m);
}

void rt_mesh_bounds(const rt_mesh *m, rt_vec3 *lo, rt_vec3 *hi)
{
    rt_vec3 a = {0, 0, 0}, b = {0, 0, 0};
    if (m->nverts > 0) {
        a = b = m->verts[0];
        for (uint32_t i = 1; i < m->nverts; i++) {
            rt_vec3 p = m->verts[i];
            a.x = fminf(a.x, p.x), a.y = fminf(a.y, p.y), a.z = fminf(a.z, p.z);
            b.x = fmaxf(b.x, p.x), b.y = fmaxf(b.y, p.y), b.z = fmaxf(b.z, p.z);
        }
    }
    *lo = a;
    *hi = b;
}

uint64_t rt_mesh_hash(const rt_mesh *m)
{
    uint64_t h = RT_FNV1A64_BASIS;
    h = rt_fnv1a64(h, &m->nverts, sizeof m->nverts);
    h = rt_fnv1a64(h, &m->ntris, sizeof m->ntris);
    if (m->nverts)
        h = rt_fnv1a64(h, m->verts, (size_t)m->nverts * sizeof *m->verts);
    if (m->ntris)
        h = rt_fnv1a64(h, m->tris, (size_t)m->ntris * 3 * sizeof *m->tris);
    return h;
}

rt_vec3 rt_mesh_tri_normal(const rt_mesh *m, uint32_t prim)
{
    const uint32_t *t = m->tris + 3 * (size_t)prim;
    rt_vec3 a = m->verts[t[0]], b = m->verts[t[1]], c = m->verts[t[2]];
    double e1[3] = {(double)b.x - a.x, (double)b.y - a.y, (double)b.z - a.z};
    double e2[3] = {(double)c.x - a.x, (double)c.y - a.y, (double)c.z - a.z};
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                   e1[0] * e2[1] - e1[1] * e2[0]};
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    rt_vec3 r = {0, 0, 0};
    if (len > 0 && isfinite(len))
        r = (rt_vec3){(float)(n[0] / len), (float)(n[1] / len), (float)(n[2] / len)};
    return r;
}
