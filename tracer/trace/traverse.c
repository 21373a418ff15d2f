/* traverse.c — the reference traversal of traverse.h, on the image's bytes.
 * Kept tight for speed: the ray preparation is done once, the stack is a
 * local array (no allocation), slots are decoded straight from the bytes, and
 * events/counts cost one predictable branch each when unused. */
#include "tracer/trace/traverse.h"

#include <string.h>

typedef struct stack_entry {
    uint32_t ref, meta;
    float tnear;
} stack_entry;

static inline float load_f32(const uint8_t *p)
{
    float f;
    memcpy(&f, p, 4);
    return f;
}

void rt_trv_params_default(rt_trv_params *p, int width)
{
    p->stack_depth = RT_STACK_DEPTH_DEFAULT;
    p->distance_cull = width > 2;
}

static inline void emit(rt_trv_event_fn fn, void *user, rt_trv_event_kind kind, uint32_t a, uint32_t b, float t)
{
    const rt_trv_event ev = {(uint8_t)kind, a, b, t};
    fn(user, &ev);
}

/* The traversal with the node width as a compile-time constant for the
 * common widths (one inlined copy each, see rt_trace_ray). */
static inline __attribute__((always_inline)) bool trace(const rt_bvh_image *img, const rt_trv_params *p,
                                                        const rt_ray *ray, rt_hit *hit, rt_trv_counts *counts,
                                                        rt_trv_event_fn fn, void *user, const int width)
{
    stack_entry stack[4096];
    int depth = p->stack_depth;
    if (depth > 4096)
        depth = 4096;   /* the documented range is 1..4096 */
    if (depth < 1)
        depth = 1;
    const bool cull = p->distance_cull;
    const uint8_t *nodes = img->bytes + img->node_base;
    const uint8_t *tris = img->bytes + img->tri_base;
    const uint32_t nbytes = img->node_bytes;

    const float org[3] = {ray->org.x, ray->org.y, ray->org.z};
    const float dir[3] = {ray->dir.x, ray->dir.y, ray->dir.z};
    rt_ray_prep rp;
    rt_ray_prepare(org, dir, &rp);
    const float tmin = ray->tmin;
    const bool any_hit = ray->occlusion != 0;
    float closest = ray->tmax;
    uint32_t prim = RT_NO_HIT;
    float hu = 0.0f, hv = 0.0f;
    rt_trv_counts c = {0};
    int sp = 0;
    bool ok = true;

    uint32_t ref = 0, meta = 0;   /* the current target: root, an inner node */
    for (;;) {
        if (meta == 0) {
            /* VISIT */
            c.visits++;
            if (fn)
                emit(fn, user, RT_EV_VISIT, ref, 0, 0.0f);
            const uint8_t *node = nodes + (uint64_t)ref * nbytes;
            stack_entry hits[RT_WIDTH_MAX];
            int nh = 0;
            for (int s = 0; s < width; s++) {
                const uint8_t *slot = node + (size_t)s * RT_SLOT_BYTES;
                uint32_t cref, cmeta;
                memcpy(&cmeta, slot + 28, 4);
                if (cmeta & RT_META_EMPTY)
                    break;   /* used slots come first */
                /* element-wise loads keep the box in registers */
                const float lo[3] = {load_f32(slot), load_f32(slot + 4), load_f32(slot + 8)};
                const float hi[3] = {load_f32(slot + 12), load_f32(slot + 16), load_f32(slot + 20)};
                c.box_tests++;
                float tn;
                if (!rt_slab_test(&rp, lo, hi, tmin, closest, &tn))
                    continue;
                memcpy(&cref, slot + 24, 4);
                /* insertion keeps slot order among equal tnear: stable sort;
                 * occlusion rays bypass the sort and keep slot order */
                int i = nh++;
                while (!any_hit && i > 0 && tn < hits[i - 1].tnear) {
                    hits[i] = hits[i - 1];
                    i--;
                }
                hits[i] = (stack_entry){cref, cmeta & RT_META_COUNT_MASK, tn};
            }
            if (nh > 0) {
                /* Start fetching the pushed children now: incoherent rays
                 * are memory-bound, and the misses then overlap (the nearest
                 * is read right away anyway). No effect on results. */
                for (int i = 1; i < nh; i++) {
                    if (hits[i].meta == 0) {
                        const uint8_t *cn = nodes + (uint64_t)hits[i].ref * nbytes;
                        __builtin_prefetch(cn);
                        __builtin_prefetch(cn + nbytes - 1);
                    } else {
                        const uint8_t *ct = tris + (uint64_t)hits[i].ref * RT_TRI_BYTES;
                        __builtin_prefetch(ct);
                        __builtin_prefetch(ct + (uint64_t)hits[i].meta * RT_TRI_BYTES - 1);
                    }
                }
                for (int i = nh - 1; i >= 1; i--) {
                    if (sp == depth) {
                        ok = false;
                        goto out;
                    }
                    stack[sp++] = hits[i];
                    c.pushes++;
                    if (fn)
                        emit(fn, user, RT_EV_PUSH, hits[i].ref, hits[i].meta, hits[i].tnear);
                }
                if ((uint32_t)sp > c.max_stack)
                    c.max_stack = (uint32_t)sp;
                ref = hits[0].ref, meta = hits[0].meta;
                continue;
            }
        } else {
            /* LEAF */
            c.leaves++;
            if (fn)
                emit(fn, user, RT_EV_LEAF, ref, meta, 0.0f);
            for (uint32_t i = 0; i < meta; i++) {
                const uint8_t *tb = tris + (uint64_t)(ref + i) * RT_TRI_BYTES;
                rt_tri48 tri;
                tri.n_u = load_f32(tb), tri.n_v = load_f32(tb + 4), tri.n_d = load_f32(tb + 8);
                memcpy(&tri.k, tb + 12, 4);
                tri.b_nu = load_f32(tb + 16), tri.b_nv = load_f32(tb + 20), tri.b_d = load_f32(tb + 24);
                memcpy(&tri.prim, tb + 28, 4);
                tri.c_nu = load_f32(tb + 32), tri.c_nv = load_f32(tb + 36), tri.c_d = load_f32(tb + 40);
                memcpy(&tri.flags, tb + 44, 4);
                c.tri_tests++;
                float t, u, v;
                const bool h = rt_wald_test(&tri, org, dir, tmin, closest, &t, &u, &v);
                if (h)
                    closest = t, prim = tri.prim, hu = u, hv = v;
                if (fn)
                    emit(fn, user, RT_EV_TRI, ref + i, h ? 1u : 0u, closest);
                if (h && any_hit)
                    goto done;   /* occlusion ray: the first hit answers it */
            }
        }
        /* POP */
        for (;;) {
            if (sp == 0)
                goto done;
            const stack_entry e = stack[--sp];
            if (cull && e.tnear > closest) {
                c.culls++;
                if (fn)
                    emit(fn, user, RT_EV_CULL, e.ref, e.meta, e.tnear);
                continue;
            }
            c.pops++;
            if (fn)
                emit(fn, user, RT_EV_POP, e.ref, e.meta, e.tnear);
            ref = e.ref, meta = e.meta;
            break;
        }
    }
done:
    if (fn)
        emit(fn, user, RT_EV_DONE, prim, 0, closest);
out:
    hit->t = closest;
    hit->u = hu;
    hit->v = hv;
    hit->prim = prim;
    if (counts)
        *counts = c;
    return ok;
}

static bool trace_w2(const rt_bvh_image *img, const rt_trv_params *p, const rt_ray *ray, rt_hit *hit,
                     rt_trv_counts *counts, rt_trv_event_fn fn, void *user)
{
    return trace(img, p, ray, hit, counts, fn, user, 2);
}

static bool trace_w4(const rt_bvh_image *img, const rt_trv_params *p, const rt_ray *ray, rt_hit *hit,
                     rt_trv_counts *counts, rt_trv_event_fn fn, void *user)
{
    return trace(img, p, ray, hit, counts, fn, user, 4);
}

static bool trace_any(const rt_bvh_image *img, const rt_trv_params *p, const rt_ray *ray, rt_hit *hit,
                      rt_trv_counts *counts, rt_trv_event_fn fn, void *user)
{
    return trace(img, p, ray, hit, counts, fn, user, img->width);
}

bool rt_trace_ray(const rt_bvh_image *img, const rt_trv_params *p, const rt_ray *ray, rt_hit *hit,
                  rt_trv_counts *counts, rt_trv_event_fn fn, void *user)
{
    if (img->width == 2)
        return trace_w2(img, p, ray, hit, counts, fn, user);
    if (img->width == 4)
        return trace_w4(img, p, ray, hit, counts, fn, user);
    return trace_any(img, p, ray, hit, counts, fn, user);
}
