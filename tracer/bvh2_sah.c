/* bvh2_sah.c — see bvh2_sah.h. Serial binned SAH: each node bins its
 * triangles' centroids (taken as lo + hi, twice the centroid, to save a
 * multiply) into params->bins bins per axis, sweeps the bin boundaries for the
 * cheapest split, and partitions its range of triangle references in place.
 * The centroid bounds of both children are gathered during the partition, so
 * every triangle is read twice per tree level. */
#include "tracer/bvh2_sah.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct prim_ref {
    float lo[3];
    uint32_t id;
    float hi[3];
    uint32_t pad;   /* 32 bytes: two refs per 64-byte cache line */
} prim_ref;

typedef struct build_task {
    uint32_t node, begin, end;
    float clo[3], chi[3];   /* bounds of lo + hi over the range */
} build_task;

typedef struct bin {
    float lo[3], hi[3];
    uint32_t count;
} bin;

enum { BINS_MAX = 256 };

typedef struct builder {
    prim_ref *refs;
    rt_bvh2_node *nodes;
    uint32_t nnodes;
    build_task *stack;
    size_t stack_len, stack_cap;
    int bins, leaf_size;
    float cost_node, cost_tri;
    bin b[3][BINS_MAX];
} builder;

static inline void box_empty(float lo[3], float hi[3])
{
    for (int a = 0; a < 3; a++)
        lo[a] = INFINITY, hi[a] = -INFINITY;
}

static inline void box_grow(float lo[3], float hi[3], const float plo[3], const float phi[3])
{
    for (int a = 0; a < 3; a++) {
        lo[a] = plo[a] < lo[a] ? plo[a] : lo[a];
        hi[a] = phi[a] > hi[a] ? phi[a] : hi[a];
    }
}

static inline void cent_grow(float lo[3], float hi[3], const prim_ref *r)
{
    for (int a = 0; a < 3; a++) {
        const float c = r->lo[a] + r->hi[a];
        lo[a] = c < lo[a] ? c : lo[a];
        hi[a] = c > hi[a] ? c : hi[a];
    }
}

/* The bin of centroid value c on an axis: the same expression in binning
 * and partitioning, so both agree bit for bit. */
static inline int bin_of(float c, float cmin, float scale, int nbins)
{
    int i = (int)((c - cmin) * scale);
    return i < nbins - 1 ? i : nbins - 1;
}

static bool push_task(builder *bd, const build_task *t)
{
    if (bd->stack_len == bd->stack_cap) {
        size_t cap = bd->stack_cap ? 2 * bd->stack_cap : 256;
        build_task *s = realloc(bd->stack, cap * sizeof *s);
        if (!s)
            return false;
        bd->stack = s, bd->stack_cap = cap;
    }
    bd->stack[bd->stack_len++] = *t;
    return true;
}

/* Splits t's range at the middle (all centroids coincide): bounds by passes. */
static uint32_t split_middle(builder *bd, const build_task *t, build_task *l, build_task *r, float llo[3],
                             float lhi[3], float rlo[3], float rhi[3])
{
    const uint32_t mid = t->begin + (t->end - t->begin) / 2;
    box_empty(llo, lhi), box_empty(rlo, rhi);
    box_empty(l->clo, l->chi), box_empty(r->clo, r->chi);
    for (uint32_t i = t->begin; i < mid; i++)
        box_grow(llo, lhi, bd->refs[i].lo, bd->refs[i].hi), cent_grow(l->clo, l->chi, &bd->refs[i]);
    for (uint32_t i = mid; i < t->end; i++)
        box_grow(rlo, rhi, bd->refs[i].lo, bd->refs[i].hi), cent_grow(r->clo, r->chi, &bd->refs[i]);
    return mid;
}

/* Processes one node: leaf, or split with both children pushed. */
static bool build_node(builder *bd, const build_task *t)
{
    rt_bvh2_node *node = &bd->nodes[t->node];
    const uint32_t n = t->end - t->begin;
    const int nb = bd->bins;
    float scale[3];
    bool any_extent = false;
    for (int a = 0; a < 3; a++) {
        const float ext = t->chi[a] - t->clo[a];
        scale[a] = ext > 0.0f ? (float)nb * (1.0f - 1e-6f) / ext : 0.0f;
        any_extent |= ext > 0.0f;
    }
    if (n == 1 || (!any_extent && n <= (uint32_t)bd->leaf_size)) {
        node->first = t->begin, node->count = n;
        return true;
    }
    build_task l = {0}, r = {0};
    float llo[3], lhi[3], rlo[3], rhi[3];
    uint32_t mid;
    if (any_extent) {
        for (int a = 0; a < 3; a++)
            for (int i = 0; i < nb; i++)
                box_empty(bd->b[a][i].lo, bd->b[a][i].hi), bd->b[a][i].count = 0;
        for (uint32_t i = t->begin; i < t->end; i++) {
            const prim_ref *p = &bd->refs[i];
            for (int a = 0; a < 3; a++) {
                bin *b = &bd->b[a][bin_of(p->lo[a] + p->hi[a], t->clo[a], scale[a], nb)];
                box_grow(b->lo, b->hi, p->lo, p->hi);
                b->count++;
            }
        }
        /* Sweep: right-hand areas/counts, then left to right. */
        float best = INFINITY;
        int best_axis = -1, best_split = 0;
        float rarea[BINS_MAX];
        uint32_t rcount[BINS_MAX];
        for (int a = 0; a < 3; a++) {
            if (scale[a] == 0.0f)
                continue;
            float lo[3], hi[3];
            box_empty(lo, hi);
            uint32_t cnt = 0;
            for (int i = nb - 1; i >= 1; i--) {
                box_grow(lo, hi, bd->b[a][i].lo, bd->b[a][i].hi);
                cnt += bd->b[a][i].count;
                rcount[i] = cnt;
                rarea[i] = cnt ? rt_box_half_area(lo, hi) : 0.0f;
            }
            box_empty(lo, hi);
            cnt = 0;
            for (int i = 1; i < nb; i++) {
                box_grow(lo, hi, bd->b[a][i - 1].lo, bd->b[a][i - 1].hi);
                cnt += bd->b[a][i - 1].count;
                if (cnt == 0 || rcount[i] == 0)
                    continue;
                const float cost = rt_box_half_area(lo, hi) * (float)cnt + rarea[i] * (float)rcount[i];
                if (cost < best)
                    best = cost, best_axis = a, best_split = i;
            }
        }
        if (best_axis < 0) {
            /* cannot happen with a non-zero extent (the first and last bins are
             * non-empty); kept as a guard */
            any_extent = false;
        } else {
            const float area = rt_box_half_area(node->lo, node->hi);
            const float split_cost =
                area > 0.0f ? bd->cost_node + bd->cost_tri * best / area : bd->cost_node + bd->cost_tri * (float)n;
            if (n <= (uint32_t)bd->leaf_size && bd->cost_tri * (float)n <= split_cost) {
                node->first = t->begin, node->count = n;
                return true;
            }
            const int a = best_axis;
            box_empty(llo, lhi), box_empty(rlo, rhi);
            for (int i = 0; i < nb; i++) {
                if (i < best_split)
                    box_grow(llo, lhi, bd->b[a][i].lo, bd->b[a][i].hi);
                else
                    box_grow(rlo, rhi, bd->b[a][i].lo, bd->b[a][i].hi);
            }
            box_empty(l.clo, l.chi), box_empty(r.clo, r.chi);
            uint32_t i = t->begin, j = t->end;
            const float cmin = t->clo[a], sc = scale[a];
            while (i < j) {
                prim_ref *p = &bd->refs[i];
                if (bin_of(p->lo[a] + p->hi[a], cmin, sc, nb) < best_split) {
                    cent_grow(l.clo, l.chi, p);
                    i++;
                } else {
                    j--;
                    prim_ref tmp = *p;
                    *p = bd->refs[j];
                    bd->refs[j] = tmp;
                    cent_grow(r.clo, r.chi, &bd->refs[j]);
                }
            }
            mid = i;
        }
    }
    if (!any_extent)
        mid = split_middle(bd, t, &l, &r, llo, lhi, rlo, rhi);
    const uint32_t c = bd->nnodes;
    bd->nnodes += 2;
    node->first = c, node->count = 0;
    rt_bvh2_node *cl = &bd->nodes[c], *cr = &bd->nodes[c + 1];
    memcpy(cl->lo, llo, sizeof llo), memcpy(cl->hi, lhi, sizeof lhi);
    memcpy(cr->lo, rlo, sizeof rlo), memcpy(cr->hi, rhi, sizeof rhi);
    l.node = c, l.begin = t->begin, l.end = mid;
    r.node = c + 1, r.begin = mid, r.end = t->end;
    /* right first so the left subtree is built (and numbered) first */
    return push_task(bd, &r) && push_task(bd, &l);
}

bool rt_bvh2_build_sah(const rt_mesh *mesh, const rt_bvh_params *params, rt_bvh2 *out)
{
    memset(out, 0, sizeof *out);
    const uint32_t n = mesh->ntris;
    builder *bd = calloc(1, sizeof *bd);
    if (!bd)
        return false;
    bd->bins = params->bins, bd->leaf_size = params->leaf_size;
    bd->cost_node = params->cost_node, bd->cost_tri = params->cost_tri;
    bd->refs = malloc((size_t)n * sizeof *bd->refs);
    bd->nodes = malloc((2 * (size_t)n) * sizeof *bd->nodes);
    out->order = malloc((size_t)n * sizeof *out->order);
    bool ok = bd->refs && bd->nodes && out->order;
    if (ok) {
        build_task root = {0};
        root.end = n;
        box_empty(root.clo, root.chi);
        rt_bvh2_node *r = &bd->nodes[0];
        box_empty(r->lo, r->hi);
        for (uint32_t i = 0; i < n; i++) {
            const uint32_t *t = mesh->tris + 3 * (size_t)i;
            const rt_vec3 *v0 = &mesh->verts[t[0]], *v1 = &mesh->verts[t[1]], *v2 = &mesh->verts[t[2]];
            prim_ref *p = &bd->refs[i];
            p->lo[0] = fminf(v0->x, fminf(v1->x, v2->x));
            p->lo[1] = fminf(v0->y, fminf(v1->y, v2->y));
            p->lo[2] = fminf(v0->z, fminf(v1->z, v2->z));
            p->hi[0] = fmaxf(v0->x, fmaxf(v1->x, v2->x));
            p->hi[1] = fmaxf(v0->y, fmaxf(v1->y, v2->y));
            p->hi[2] = fmaxf(v0->z, fmaxf(v1->z, v2->z));
            p->id = i, p->pad = 0;
            box_grow(r->lo, r->hi, p->lo, p->hi);
            cent_grow(root.clo, root.chi, p);
        }
        bd->nnodes = 1;
        ok = push_task(bd, &root);
        while (ok && bd->stack_len > 0) {
            build_task t = bd->stack[--bd->stack_len];
            ok = build_node(bd, &t);
        }
    }
    if (ok) {
        for (uint32_t i = 0; i < n; i++)
            out->order[i] = bd->refs[i].id;
        rt_bvh2_node *shrunk = realloc(bd->nodes, (size_t)bd->nnodes * sizeof *shrunk);
        out->nodes = shrunk ? shrunk : bd->nodes;
        out->nnodes = bd->nnodes;
        out->ntris = n;
    } else {
        free(bd->nodes);
        free(out->order);
        out->order = NULL;
    }
    free(bd->refs);
    free(bd->stack);
    free(bd);
    return ok;
}

void rt_bvh2_free(rt_bvh2 *b)
{
    free(b->nodes);
    free(b->order);
    memset(b, 0, sizeof *b);
}
