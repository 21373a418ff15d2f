/* pixel_order.h — the order in which a frame's primary rays are generated.
 *
 * The paper does not say in which order its ray generator (the shader
 * processor of its Fig. 2) hands pixels to the accelerator; the order decides
 * how many rays in flight share nodes and triangles, and so the caches' hit
 * rates and the DRAM traffic of primary rays (docs/paper.md, "Pixel order").
 *
 *   RT_ORDER_SCANLINE  pixel i = row i / W, column i % W;
 *   RT_ORDER_TILES     square tiles of T x T pixels, tiles in scanline order,
 *                      pixels in scanline order inside a tile (edge tiles
 *                      are cut to the image);
 *   RT_ORDER_MORTON    Z order of (x, y) over the image (the bits of x and y
 *                      interleaved), skipping codes outside it.
 *
 * rt_pixel_order_make() returns the permutation as an array: out[k] is the
 * pixel number (py * W + px) of the k-th primary ray; NULL for scanline
 * (the identity needs no array). Deterministic. */
#ifndef RTSIM_TRACER_PIXEL_ORDER_H
#define RTSIM_TRACER_PIXEL_ORDER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { RT_ORDER_SCANLINE, RT_ORDER_TILES, RT_ORDER_MORTON } rt_pixel_order_kind;

/* The names of the kinds in enum order, '|'-separated ("scanline|tiles|morton"). */
#define RT_PIXEL_ORDER_CHOICES "scanline|tiles|morton"

/* The permutation for a width x height image (tile: the side of a tile in
 * pixels, 1..65535, used by RT_ORDER_TILES only). True with *out set (NULL
 * for scanline; free() it); false with a message on bad arguments or out of
 * memory. */
bool rt_pixel_order_make(rt_pixel_order_kind kind, uint32_t tile, uint32_t width, uint32_t height, uint32_t **out,
                         char *err, size_t errlen);

/* The pixel of the k-th primary ray: order[k], or k when order is NULL. */
static inline uint32_t rt_pixel_at(const uint32_t *order, uint64_t k)
{
    return order ? order[k] : (uint32_t)k;
}

#ifdef __cplusplus
}
#endif

#endif
