/* bvh.h — BVH builders and the memory image the hardware fetches.
 *
 * rt_bvh_build() builds, for a mesh, an N-wide BVH (N = params.width, 2..8):
 *   N = 2: binned SAH sweep (paper sec. 3.2, "BVH trees are constructed with a
 *          binned SAH sweep");
 *   N > 2: the same BVH2, then Wald et al. 2008 top-down collapsing: starting
 *          from the root, repeatedly replace the child with the largest surface
 *          area by its two children until the node has N children or only
 *          leaves are left; recurse into the children.
 * and lays it out as one little-endian byte image (tracer/bvh/bvh_layout.h):
 *   [node_base, node_base + nnodes * node_bytes)  nodes, root = node 0
 *   [tri_base,  tri_base + ntris * 48)            triangles in leaf order
 * tri_base is aligned to 4096 bytes. Deterministic: the same mesh and params
 * give the same bytes (and so the same hash) on every run.
 * Errors (bad params, empty mesh, index out of range, non-finite vertex)
 * return false with a message naming the parameter and its allowed range.
 * Layout details (depth-first node order in sibling blocks, single-leaf root, statistics
 * definitions): tracer/bvh/bvh_image.h; algorithm and figures: docs/tracer-bvh.md. */
#ifndef RTSIM_TRACER_BVH_H
#define RTSIM_TRACER_BVH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "tracer/bvh/bvh_layout.h"
#include "tracer/io/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* How an N-wide (N > 2) tree is built (rt_bvh_params.builder; docs/tracer-bvh.md):
 *   RT_BUILD_COLLAPSE  the BVH2 (whose SAH also decides where leaves end),
 *                      collapsed top-down as below;
 *   RT_BUILD_WALD      Wald et al. 2008's top-down recursive splitting: a set
 *                      of triangles is split by the binned SAH until it holds
 *                      at most leaf_size triangles (the SAH chooses the
 *                      splits, never a leaf), and the splits are grouped N
 *                      wide by the same collapse. Fuller leaves, so fewer
 *                      and fuller nodes. */
typedef enum { RT_BUILD_COLLAPSE, RT_BUILD_WALD } rt_build_kind;

typedef struct rt_bvh_params {
    int width;           /* N = 2..8 (RT_WIDTH_MIN..RT_WIDTH_MAX); default 4 */
    int builder;         /* rt_build_kind for N > 2 (a BVH2 is always the SAH sweep); default collapse */
    int leaf_size;       /* max triangles per leaf, 1..RT_LEAF_MAX; default 4 */
    int bins;            /* SAH bins per axis, 4..256; default 16 */
    float cost_node;     /* SAH traversal cost of a node; default 1 */
    float cost_tri;      /* SAH cost of a triangle test; default 1 */
} rt_bvh_params;

void rt_bvh_params_default(rt_bvh_params *p);

typedef struct rt_bvh_stats {
    double sah_cost;            /* SAH cost of the final tree (root area normalised) */
    uint32_t inner_nodes, leaves, max_depth;
    uint32_t leaf_size_hist[RT_LEAF_MAX + 1]; /* leaves with that many triangles */
    uint64_t node_bytes_total, tri_bytes_total;
    double build_seconds;
} rt_bvh_stats;

typedef struct rt_bvh_image {
    uint8_t *bytes;          /* size bytes */
    uint64_t size;
    uint64_t node_base, tri_base;   /* byte addresses in the image */
    int width;               /* N */
    uint32_t node_bytes;     /* N * 32 */
    uint32_t nnodes, ntris;
    uint64_t hash;           /* FNV-1a (over 64-bit little-endian words, not bytes: 8x faster on
                                a 200 MB image) of params, mesh hash and the bytes: names this
                                image in logs */
} rt_bvh_image;

bool rt_bvh_build(const rt_mesh *mesh, const rt_bvh_params *params, rt_bvh_image *out, rt_bvh_stats *stats,
                  char *err, size_t errlen);
void rt_bvh_image_free(rt_bvh_image *img);

static inline const uint8_t *rt_bvh_node_ptr(const rt_bvh_image *img, uint32_t node)
{
    return img->bytes + img->node_base + (uint64_t)node * img->node_bytes;
}
static inline const uint8_t *rt_bvh_tri_ptr(const rt_bvh_image *img, uint32_t tri)
{
    return img->bytes + img->tri_base + (uint64_t)tri * RT_TRI_BYTES;
}

#ifdef __cplusplus
}
#endif

#endif
