/* bvh_image.c — see bvh_image.h. Two passes: the first collapses the BVH2
 * into N-wide nodes depth-first, numbering each node's inner children as a
 * consecutive block (explicit stack: SAH trees of degenerate inputs can be
 * deep), the second writes node and triangle bytes in node order. */
#include "tracer/bvh/bvh_image.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tracer/util/big_alloc.h"
#include "tracer/bvh/mbvh_collapse.h"
#include "tracer/bvh/wald_tri.h"

typedef struct wide_node {
    uint32_t child[RT_WIDTH_MAX];   /* BVH2 node per used slot */
    uint32_t wide[RT_WIDTH_MAX];    /* wide index of an inner child */
    uint32_t n;
} wide_node;

typedef struct walk_entry {
    uint32_t bvh2, index, unused, depth;
} walk_entry;

static void put_u32(uint8_t *p, uint32_t v) { memcpy(p, &v, 4); }

bool rt_bvh_layout_image(const rt_mesh *mesh, const rt_bvh2 *b, const rt_bvh_params *params, rt_bvh_image *img,
                         rt_bvh_stats *stats)
{
    const int width = params->width;
    memset(img, 0, sizeof *img);
    memset(stats, 0, sizeof *stats);
    uint32_t inner2 = 0;
    for (uint32_t i = 0; i < b->nnodes; i++)
        inner2 += b->nodes[i].count == 0;
    const uint32_t cap = inner2 ? inner2 : 1;
    wide_node *w = rt_big_alloc((size_t)cap * sizeof *w);
    walk_entry *st = malloc(((size_t)cap + 1) * sizeof *st);   /* each wide node is pushed once */
    if (!w || !st) {
        free(w), free(st);
        return false;
    }
    uint32_t nw = 0, max_depth = 0;
    size_t sp = 0;
    if (b->nodes[0].count != 0) {
        /* the whole mesh is one leaf: a root holding it in slot 0 */
        w[0].n = 1, w[0].child[0] = 0, w[0].wide[0] = 0;
        nw = 1, max_depth = 1;
    } else {
        st[sp++] = (walk_entry){0, 0, 0, 1};
        nw = 1;
    }
    while (sp > 0) {
        const walk_entry e = st[--sp];
        const uint32_t me = e.index;
        if (e.depth > max_depth)
            max_depth = e.depth;
        wide_node *wn = &w[me];
        wn->n = (uint32_t)rt_mbvh_collapse_children(b, e.bvh2, width, wn->child);
        /* the inner children get consecutive numbers now (a sibling block) */
        for (uint32_t s = 0; s < wn->n; s++)
            wn->wide[s] = b->nodes[wn->child[s]].count == 0 ? nw++ : 0;
        for (int s = (int)wn->n - 1; s >= 0; s--)
            if (b->nodes[wn->child[s]].count == 0)
                st[sp++] = (walk_entry){wn->child[s], wn->wide[s], 0, e.depth + 1};
    }
    free(st);

    const uint32_t nb = rt_node_bytes(width);
    const uint64_t node_bytes = (uint64_t)nw * nb;
    const uint64_t tri_base = (node_bytes + 4095u) & ~(uint64_t)4095u;
    img->size = tri_base + (uint64_t)b->ntris * RT_TRI_BYTES;
    img->bytes = rt_big_alloc(img->size);
    if (!img->bytes) {
        free(w);
        memset(img, 0, sizeof *img);
        return false;
    }
    memset(img->bytes + node_bytes, 0, tri_base - node_bytes);   /* padding before the triangles */
    img->node_base = 0, img->tri_base = tri_base;
    img->width = width, img->node_bytes = nb;
    img->nnodes = nw, img->ntris = b->ntris;

    float rlo[3] = {INFINITY, INFINITY, INFINITY}, rhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t s = 0; s < w[0].n; s++) {
        const rt_bvh2_node *c = &b->nodes[w[0].child[s]];
        for (int a = 0; a < 3; a++)
            rlo[a] = c->lo[a] < rlo[a] ? c->lo[a] : rlo[a], rhi[a] = c->hi[a] > rhi[a] ? c->hi[a] : rhi[a];
    }
    double root_area = rt_box_half_area(rlo, rhi);
    if (!(root_area > 0.0))
        root_area = 1.0;
    double sah = 0.0;
    uint32_t tri_cursor = 0;
    for (uint32_t i = 0; i < nw; i++) {
        uint8_t *node = img->bytes + (uint64_t)i * nb;
        const wide_node *wn = &w[i];
        float nlo[3] = {INFINITY, INFINITY, INFINITY}, nhi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (uint32_t s = 0; s < (uint32_t)width; s++) {
            rt_child ch;
            if (s >= wn->n) {
                for (int a = 0; a < 3; a++)
                    ch.lo[a] = INFINITY, ch.hi[a] = -INFINITY;
                ch.ref = 0, ch.meta = RT_META_EMPTY;
            } else {
                const rt_bvh2_node *c = &b->nodes[wn->child[s]];
                memcpy(ch.lo, c->lo, sizeof ch.lo), memcpy(ch.hi, c->hi, sizeof ch.hi);
                for (int a = 0; a < 3; a++)
                    nlo[a] = c->lo[a] < nlo[a] ? c->lo[a] : nlo[a], nhi[a] = c->hi[a] > nhi[a] ? c->hi[a] : nhi[a];
                if (c->count == 0) {
                    ch.ref = wn->wide[s], ch.meta = 0;
                } else {
                    ch.ref = tri_cursor, ch.meta = c->count;
                    for (uint32_t j = 0; j < c->count; j++) {
                        rt_tri48 t;
                        rt_wald_precompute_prim(mesh, b->order[c->first + j], &t);
                        memcpy(img->bytes + tri_base + (uint64_t)(tri_cursor + j) * RT_TRI_BYTES, &t, sizeof t);
                    }
                    tri_cursor += c->count;
                    stats->leaves++;
                    stats->leaf_size_hist[c->count]++;
                    sah += params->cost_tri * (double)c->count * rt_box_half_area(c->lo, c->hi) / root_area;
                }
            }
            uint8_t *slot = node + (size_t)s * RT_SLOT_BYTES;
            memcpy(slot, ch.lo, 12), memcpy(slot + 12, ch.hi, 12);
            put_u32(slot + 24, ch.ref), put_u32(slot + 28, ch.meta);
        }
        sah += params->cost_node * rt_box_half_area(nlo, nhi) / root_area;
    }
    free(w);
    stats->sah_cost = sah;
    stats->inner_nodes = nw;
    stats->max_depth = max_depth;
    stats->node_bytes_total = node_bytes;
    stats->tri_bytes_total = (uint64_t)b->ntris * RT_TRI_BYTES;
    return true;
}
