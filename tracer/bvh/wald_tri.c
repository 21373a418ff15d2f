/* wald_tri.c — see wald_tri.h. Derivation: with P = A + beta (B-A) + gamma (C-A)
 * projected onto the (u, v) plane, p = (hu - A_u, hv - A_v) and e1 = B-A,
 * e2 = C-A, Cramer's rule gives beta = (p_u e2_v - p_v e2_u)/det and
 * gamma = (e1_u p_v - e1_v p_u)/det with det = e1_u e2_v - e1_v e2_u = N_k;
 * expanding p folds A into the constant terms b_d and c_d. */
#include "tracer/bvh/wald_tri.h"

#include <math.h>
#include <string.h>

void rt_wald_precompute(rt_vec3 a, rt_vec3 b, rt_vec3 c, uint32_t prim, rt_tri48 *out)
{
    const double A[3] = {a.x, a.y, a.z};
    const double e1[3] = {(double)b.x - a.x, (double)b.y - a.y, (double)b.z - a.z};
    const double e2[3] = {(double)c.x - a.x, (double)c.y - a.y, (double)c.z - a.z};
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                         e1[0] * e2[1] - e1[1] * e2[0]};
    int k = 0;
    if (fabs(n[1]) > fabs(n[k]))
        k = 1;
    if (fabs(n[2]) > fabs(n[k]))
        k = 2;
    const int u = (k + 1) % 3, v = (k + 2) % 3;
    memset(out, 0, sizeof *out);
    out->prim = prim;
    out->k = (uint32_t)k;
    const double det = n[k];
    if (det == 0.0 || !isfinite(det)) {
        out->flags = RT_TRI_FLAG_DEGENERATE;
        return;
    }
    const double f[9] = {
        n[u] / det,
        n[v] / det,
        (n[0] * A[0] + n[1] * A[1] + n[2] * A[2]) / det,
        -e2[u] / det,
        e2[v] / det,
        (A[v] * e2[u] - A[u] * e2[v]) / det,
        -e1[v] / det,
        e1[u] / det,
        (A[u] * e1[v] - A[v] * e1[u]) / det,
    };
    float g[9];
    for (int i = 0; i < 9; i++) {
        g[i] = (float)f[i];
        if (!isfinite(g[i])) {
            out->flags = RT_TRI_FLAG_DEGENERATE;
            return;
        }
    }
    out->n_u = g[0], out->n_v = g[1], out->n_d = g[2];
    out->b_nu = g[3], out->b_nv = g[4], out->b_d = g[5];
    out->c_nu = g[6], out->c_nv = g[7], out->c_d = g[8];
}

void rt_wald_precompute_prim(const rt_mesh *m, uint32_t prim, rt_tri48 *out)
{
    const uint32_t *t = m->tris + 3 * (size_t)prim;
    rt_wald_precompute(m->verts[t[0]], m->verts[t[1]], m->verts[t[2]], prim, out);
}
