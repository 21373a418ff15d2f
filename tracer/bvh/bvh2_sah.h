/* bvh2_sah.h — binary BVH by a binned SAH sweep (Wald, "On fast Construction
 * of SAH-based Bounding Volume Hierarchies", IEEE RT 2007): the first stage of
 * every rt_bvh_build (bvh.h). Internal to tracer/ (tests use it to check the
 * memory image against the tree it was laid out from).
 *
 * Contract: node 0 is the root; an inner node's children are nodes
 * first and first+1 (left, right); a leaf covers order[first .. first+count)
 * (mesh triangle indices). Every mesh triangle appears exactly once in order[],
 * in left-to-right leaf order; boxes are the exact float bounds of their
 * triangles. Per node with n triangles, c_n = cost_node, c_t = cost_tri:
 *   split cost = c_n + c_t (A_L n_L + A_R n_R) / A   (best bin boundary over
 *                the axes of non-zero centroid extent; axis x, y, z, then
 *                boundary order, first strict minimum)
 *   leaf  cost = c_t n
 * A node becomes a leaf when n = 1, or n <= leaf_size and leaf cost <= split
 * cost. Nodes whose centroids all coincide are split at the middle of their
 * range when n > leaf_size. Deterministic (serial, no hashing of pointers). */
#ifndef RTSIM_TRACER_BVH2_SAH_H
#define RTSIM_TRACER_BVH2_SAH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "tracer/bvh/bvh.h"
#include "tracer/io/mesh.h"

typedef struct rt_bvh2_node {
    float lo[3], hi[3];
    uint32_t first;   /* inner: left child node (right = first + 1); leaf: first position in order[] */
    uint32_t count;   /* 0 for an inner node, else the leaf's triangle count */
} rt_bvh2_node;

typedef struct rt_bvh2 {
    rt_bvh2_node *nodes;
    uint32_t nnodes;
    uint32_t *order;  /* ntris mesh triangle indices in leaf order */
    uint32_t ntris;
} rt_bvh2;

/* Builds the tree; the mesh must have >= 1 triangle with finite vertices and
 * params must be valid (rt_bvh_build checks both). False only when out of memory. */
bool rt_bvh2_build_sah(const rt_mesh *mesh, const rt_bvh_params *params, rt_bvh2 *out);
void rt_bvh2_free(rt_bvh2 *b);

/* Half the surface area of a box (the SAH's proportionality factor). */
static inline float rt_box_half_area(const float lo[3], const float hi[3])
{
    const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return dx * dy + dy * dz + dz * dx;
}

#endif
