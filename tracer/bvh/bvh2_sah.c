/* bvh2_sah.c — see bvh2_sah.h. Serial binned SAH: each node bins its
 * triangles' centroids (taken as lo + hi, twice the centroid, to save a
 * multiply) into params->bins bins per axis, sweeps the bin boundaries for the
 * cheapest split, and partitions its range of triangle references in place.
 * The centroid bounds of both children are gathered during the partition, so
 * every triangle is read twice per tree level. Box arithmetic is four-lane
 * (vec4_minmax.h: SSE where available, same bits either way). */
#include "tracer/bvh/bvh2_sah.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tracer/util/big_alloc.h"
#include "tracer/util/vec4_minmax.h"

/* 32 bytes: two refs per 64-byte cache line. Lane 3 of lo is 0; lane 3 of hi
 * holds the triangle index bits (ignored by the box arithmetic). */
typedef struct prim_ref {
    _Alignas(16) float lo[4];
    float hi[4];
} prim_ref;

typedef struct box4 {
    _Alignas(16) float lo[4];
    float hi[4];
} box4;

typedef struct build_task {
    uint32_t node, begin, end;
    box4 cent;   /* bounds of lo + hi over the range */
} build_task;

enum { BINS_MAX = 256 };

typedef struct builder {
    prim_ref *refs;
    rt_bvh2_node *nodes;
    uint32_t nnodes;
    build_task *stack;
    size_t stack_len, stack_cap;
    int bins, leaf_size;
    bool leaf_by_size;   /* RT_BUILD_WALD: a leaf iff at most leaf_size triangles (no SAH termination) */
    float cost_node, cost_tri;
    box4 bin[3][BINS_MAX];
    uint32_t count[3][BINS_MAX];
    float rarea[BINS_MAX];
    uint32_t rcount[BINS_MAX];
} builder;

static inline uint32_t ref_id(const prim_ref *p)
{
    uint32_t id;
    memcpy(&id, &p->hi[3], 4);
    return id;
}

static inline void box4_empty(box4 *b)
{
    v4_store(b->lo, v4_set1(INFINITY));
    v4_store(b->hi, v4_set1(-INFINITY));
}

/* Same expression order as rt_box_half_area. */
static inline float half_area4(v4 lo, v4 hi)
{
    _Alignas(16) float d[4];
    v4_store(d, v4_sub(hi, lo));
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

static inline void box4_to_node(const box4 *b, rt_bvh2_node *n)
{
    memcpy(n->lo, b->lo, 12);
    memcpy(n->hi, b->hi, 12);
}

/* The bin of centroid value c on one axis: the same operations as the
 * four-lane binning, so binning and partitioning agree bit for bit. */
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

/* Bounds and centroid bounds of refs[begin, end). */
static void range_bounds(const builder *bd, uint32_t begin, uint32_t end, box4 *box, box4 *cent)
{
    v4 lo = v4_set1(INFINITY), hi = v4_set1(-INFINITY), clo = lo, chi = hi;
    for (uint32_t i = begin; i < end; i++) {
        const v4 a = v4_load(bd->refs[i].lo), b = v4_load(bd->refs[i].hi), c = v4_add(a, b);
        lo = v4_min(lo, a), hi = v4_max(hi, b);
        clo = v4_min(clo, c), chi = v4_max(chi, c);
    }
    v4_store(box->lo, lo), v4_store(box->hi, hi);
    v4_store(cent->lo, clo), v4_store(cent->hi, chi);
}

static void make_leaf(rt_bvh2_node *node, const build_task *t)
{
    node->first = t->begin;
    node->count = t->end - t->begin;
}

/* Processes one node: leaf, or split with both children pushed. */
static bool build_node(builder *bd, const build_task *t)
{
    rt_bvh2_node *node = &bd->nodes[t->node];
    const uint32_t n = t->end - t->begin;
    const int nb = bd->bins;
    _Alignas(16) float scale[4] = {0, 0, 0, 0};
    bool any_extent = false;
    for (int a = 0; a < 3; a++) {
        const float ext = t->cent.hi[a] - t->cent.lo[a];
        scale[a] = ext > 0.0f ? (float)nb * (1.0f - 1e-6f) / ext : 0.0f;
        any_extent |= ext > 0.0f;
    }
    if (n == 1 || ((!any_extent || bd->leaf_by_size) && n <= (uint32_t)bd->leaf_size)) {
        make_leaf(node, t);
        return true;
    }
    build_task l = {0}, r = {0};
    box4 lbox, rbox;
    uint32_t mid = 0;
    int best_axis = -1, best_split = 0;
    if (any_extent) {
        for (int a = 0; a < 3; a++)
            for (int i = 0; i < nb; i++)
                box4_empty(&bd->bin[a][i]), bd->count[a][i] = 0;
        const v4 cmin = v4_load(t->cent.lo), sc = v4_load(scale);
        for (uint32_t i = t->begin; i < t->end; i++) {
            const prim_ref *p = &bd->refs[i];
            const v4 lo = v4_load(p->lo), hi = v4_load(p->hi);
            _Alignas(16) int idx[4];
            v4_to_int3(v4_mul(v4_sub(v4_add(lo, hi), cmin), sc), idx);
            for (int a = 0; a < 3; a++) {
                const int k = idx[a] < nb - 1 ? idx[a] : nb - 1;
                box4 *b = &bd->bin[a][k];
                v4_store(b->lo, v4_min(v4_load(b->lo), lo));
                v4_store(b->hi, v4_max(v4_load(b->hi), hi));
                bd->count[a][k]++;
            }
        }
        /* Sweep: right-hand areas/counts, then left to right. */
        float best = INFINITY;
        for (int a = 0; a < 3; a++) {
            if (scale[a] == 0.0f)
                continue;
            v4 lo = v4_set1(INFINITY), hi = v4_set1(-INFINITY);
            uint32_t cnt = 0;
            for (int i = nb - 1; i >= 1; i--) {
                lo = v4_min(lo, v4_load(bd->bin[a][i].lo));
                hi = v4_max(hi, v4_load(bd->bin[a][i].hi));
                cnt += bd->count[a][i];
                bd->rcount[i] = cnt;
                bd->rarea[i] = cnt ? half_area4(lo, hi) : 0.0f;
            }
            lo = v4_set1(INFINITY), hi = v4_set1(-INFINITY);
            cnt = 0;
            for (int i = 1; i < nb; i++) {
                lo = v4_min(lo, v4_load(bd->bin[a][i - 1].lo));
                hi = v4_max(hi, v4_load(bd->bin[a][i - 1].hi));
                cnt += bd->count[a][i - 1];
                if (cnt == 0 || bd->rcount[i] == 0)
                    continue;
                const float cost = half_area4(lo, hi) * (float)cnt + bd->rarea[i] * (float)bd->rcount[i];
                if (cost < best)
                    best = cost, best_axis = a, best_split = i;
            }
        }
        if (best_axis >= 0) {
            const float area = rt_box_half_area(node->lo, node->hi);
            const float split_cost =
                area > 0.0f ? bd->cost_node + bd->cost_tri * best / area : bd->cost_node + bd->cost_tri * (float)n;
            if (n <= (uint32_t)bd->leaf_size && bd->cost_tri * (float)n <= split_cost) {
                make_leaf(node, t);
                return true;
            }
            const int a = best_axis;
            v4 llo = v4_set1(INFINITY), lhi = v4_set1(-INFINITY), rlo = llo, rhi = lhi;
            for (int i = 0; i < nb; i++) {
                const v4 blo = v4_load(bd->bin[a][i].lo), bhi = v4_load(bd->bin[a][i].hi);
                if (i < best_split)
                    llo = v4_min(llo, blo), lhi = v4_max(lhi, bhi);
                else
                    rlo = v4_min(rlo, blo), rhi = v4_max(rhi, bhi);
            }
            v4_store(lbox.lo, llo), v4_store(lbox.hi, lhi);
            v4_store(rbox.lo, rlo), v4_store(rbox.hi, rhi);
            v4 lclo = v4_set1(INFINITY), lchi = v4_set1(-INFINITY), rclo = lclo, rchi = lchi;
            uint32_t i = t->begin, j = t->end;
            const float cmin_a = t->cent.lo[a], sc_a = scale[a];
            while (i < j) {
                prim_ref *p = &bd->refs[i];
                const v4 c = v4_add(v4_load(p->lo), v4_load(p->hi));
                if (bin_of(p->lo[a] + p->hi[a], cmin_a, sc_a, nb) < best_split) {
                    lclo = v4_min(lclo, c), lchi = v4_max(lchi, c);
                    i++;
                } else {
                    rclo = v4_min(rclo, c), rchi = v4_max(rchi, c);
                    j--;
                    const prim_ref tmp = *p;
                    *p = bd->refs[j];
                    bd->refs[j] = tmp;
                }
            }
            mid = i;
            v4_store(l.cent.lo, lclo), v4_store(l.cent.hi, lchi);
            v4_store(r.cent.lo, rclo), v4_store(r.cent.hi, rchi);
        }
    }
    if (best_axis < 0) {
        /* all centroids coincide (or no valid boundary): middle of the range */
        mid = t->begin + n / 2;
        range_bounds(bd, t->begin, mid, &lbox, &l.cent);
        range_bounds(bd, mid, t->end, &rbox, &r.cent);
    }
    const uint32_t c = bd->nnodes;
    bd->nnodes += 2;
    node->first = c, node->count = 0;
    box4_to_node(&lbox, &bd->nodes[c]);
    box4_to_node(&rbox, &bd->nodes[c + 1]);
    l.node = c, l.begin = t->begin, l.end = mid;
    r.node = c + 1, r.begin = mid, r.end = t->end;
    /* right first so the left subtree is built (and numbered) first */
    return push_task(bd, &r) && push_task(bd, &l);
}

static inline float min3(float a, float b, float c)
{
    const float m = a < b ? a : b;
    return m < c ? m : c;
}
static inline float max3(float a, float b, float c)
{
    const float m = a > b ? a : b;
    return m > c ? m : c;
}

bool rt_bvh2_build_sah(const rt_mesh *mesh, const rt_bvh_params *params, rt_bvh2 *out)
{
    memset(out, 0, sizeof *out);
    const uint32_t n = mesh->ntris;
    builder *bd = aligned_alloc(16, (sizeof(builder) + 15) & ~(size_t)15);
    if (!bd)
        return false;
    memset(bd, 0, sizeof *bd);
    bd->bins = params->bins, bd->leaf_size = params->leaf_size;
    bd->leaf_by_size = params->width > 2 && params->builder == RT_BUILD_WALD;
    bd->cost_node = params->cost_node, bd->cost_tri = params->cost_tri;
    bd->refs = rt_big_alloc((size_t)n * sizeof *bd->refs);
    bd->nodes = rt_big_alloc((2 * (size_t)n) * sizeof *bd->nodes);
    out->order = malloc((size_t)n * sizeof *out->order);
    bool ok = bd->refs && bd->nodes && out->order;
    if (ok) {
        for (uint32_t i = 0; i < n; i++) {
            const uint32_t *t = mesh->tris + 3 * (size_t)i;
            const rt_vec3 *v0 = &mesh->verts[t[0]], *v1 = &mesh->verts[t[1]], *v2 = &mesh->verts[t[2]];
            prim_ref *p = &bd->refs[i];
            p->lo[0] = min3(v0->x, v1->x, v2->x);
            p->lo[1] = min3(v0->y, v1->y, v2->y);
            p->lo[2] = min3(v0->z, v1->z, v2->z);
            p->lo[3] = 0.0f;
            p->hi[0] = max3(v0->x, v1->x, v2->x);
            p->hi[1] = max3(v0->y, v1->y, v2->y);
            p->hi[2] = max3(v0->z, v1->z, v2->z);
            memcpy(&p->hi[3], &i, 4);
        }
        build_task root = {0};
        root.end = n;
        box4 box;
        range_bounds(bd, 0, n, &box, &root.cent);
        box4_to_node(&box, &bd->nodes[0]);
        bd->nnodes = 1;
        ok = push_task(bd, &root);
        while (ok && bd->stack_len > 0) {
            const build_task t = bd->stack[--bd->stack_len];
            ok = build_node(bd, &t);
        }
    }
    if (ok) {
        for (uint32_t i = 0; i < n; i++)
            out->order[i] = ref_id(&bd->refs[i]);
        out->nodes = bd->nodes;   /* not shrunk: realloc would copy it out of its huge pages */
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
