/* ist_core.c — one triangle test (see ist_core.h). */
#include "model/ray/ist_core.h"

ist_result ist_core_test(ist_core *c, accel_ray *r, uint64_t now)
{
    const accel_image *img = c->img;
    uint32_t tri = r->tri_next;
    uint64_t addr = img->tri_base + (uint64_t)tri * RT_TRI_BYTES;
    c->port_cycles = 1;
    cache_result cr = c->probe ? c->probe(c->probe_ctx, addr, RT_TRI_BYTES, now, &c->port_cycles) : CACHE_HIT;
    if (cr != CACHE_HIT) {
        r->loops++;
        if (cr == CACHE_MISS) {
            c->st.loops_miss++;
            return IST_LOOP_MISS;
        }
        c->st.loops_blocked++;
        return IST_LOOP_BLOCKED;
    }
    rt_tri48 t48;
    rt_tri_decode(img->bytes + addr, &t48);
    c->st.tests++;
    r->tri_tests++;
    float t, u, v;
    uint32_t closer = 0;
    if (rt_wald_test(&t48, r->prep.org, r->dir, r->tmin, r->closest, &t, &u, &v)) {
        c->st.hits++;
        if (t < r->closest) {   /* in-order write-back: strictly closer only */
            r->closest = t;
            r->u = u;
            r->v = v;
            r->prim = t48.prim;
            closer = 1;
            c->st.closer++;
        }
    }
    if (c->ev)
        c->ev(c->ev_user, r->uid, ACCEL_EV_TRI, tri, closer, r->closest);
    r->tri_next = tri + 1;
    if (r->tri_next < r->tri_end && !(r->occlusion && closer))
        return IST_MORE;
    c->st.leaves++;
    r->phase = RAY_POP;
    return IST_LAST;
}
