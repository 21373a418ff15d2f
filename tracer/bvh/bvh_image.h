/* bvh_image.h — lays a BVH2 (bvh2_sah.h), collapsed to width N
 * (mbvh_collapse.h), out as the memory image of bvh.h / bvh_layout.h, and
 * measures it (rt_bvh_stats). Internal to tracer/; rt_bvh_build calls it.
 *
 * Contract: nodes are numbered depth-first (slot 0's subtree first) in
 * sibling blocks: when a node is laid out, its inner children get
 * consecutive numbers, so siblings (often visited together) share cache
 * lines and DRAM rows; the root
 * is node 0 (a BVH2 that is a single leaf gets a root with that leaf in slot
 * 0 and the other slots empty). Triangles are written leaf by leaf in the
 * order the leaves appear walking the nodes by index and slots in order.
 * node_base = 0; tri_base = node bytes rounded up to 4096.
 * Statistics: inner_nodes = nodes of the image, leaves = leaf slots,
 * max_depth = nodes on the longest root-to-leaf path (the root counts 1),
 * sah_cost = sum over nodes of c_n A(node)/A(root) + sum over leaves of
 * c_t n A(leaf)/A(root), A = half surface area, A(node) = union of its slots
 * (a flat root of area 0 counts as area 1). */
#ifndef RTSIM_TRACER_BVH_IMAGE_H
#define RTSIM_TRACER_BVH_IMAGE_H

#include <stdbool.h>

#include "tracer/bvh/bvh.h"
#include "tracer/bvh/bvh2_sah.h"

/* False only when out of memory. img->hash is left 0 (bvh_build.c sets it). */
bool rt_bvh_layout_image(const rt_mesh *mesh, const rt_bvh2 *b, const rt_bvh_params *params, rt_bvh_image *img,
                         rt_bvh_stats *stats);

#endif
