/* mbvh_collapse.h — MBVH-N from a BVH2 by Wald, Benthin and Boulos 2008
 * ("Getting Rid of Packets", IEEE RT 2008) top-down collapsing. Internal to
 * tracer/ (bvh_image.c lays the result out; tests check it).
 *
 * Contract: the children of the N-wide node standing for BVH2 inner node x
 * start as [left(x), right(x)]; while fewer than N and some child is an inner
 * BVH2 node, the inner child of largest surface area (first in slot order on
 * a tie) is replaced, in its slot, by its left child, with its right child
 * inserted right after it (so slots keep the BVH2's left-to-right order).
 * N = 2 gives the BVH2 itself. */
#ifndef RTSIM_TRACER_MBVH_COLLAPSE_H
#define RTSIM_TRACER_MBVH_COLLAPSE_H

#include <stdint.h>

#include "tracer/bvh/bvh2_sah.h"

/* Fills out[0..k) with BVH2 node indices, returns k (2..width); x must be an
 * inner node of b. */
int rt_mbvh_collapse_children(const rt_bvh2 *b, uint32_t x, int width, uint32_t out[RT_WIDTH_MAX]);

#endif
