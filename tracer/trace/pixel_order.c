/* pixel_order.c — see pixel_order.h. */
#include "tracer/trace/pixel_order.h"

#include <stdio.h>
#include <stdlib.h>

/* Appends, in Z order, the pixels of the size x size square at (x0, y0)
 * that lie in the image: quadrants in the order (x0, y0), (x0 + h, y0),
 * (x0, y0 + h), (x0 + h, y0 + h) -- x in the low bit of the Morton code.
 * Quadrants outside the image are skipped whole, so the work is bounded by
 * the pixels, not by the power-of-two square around the image. */
static void morton_fill(uint32_t x0, uint32_t y0, uint32_t size, uint32_t w, uint32_t h, uint32_t *o, uint64_t *k)
{
    if (x0 >= w || y0 >= h)
        return;
    if (size == 1) {
        o[(*k)++] = y0 * w + x0;
        return;
    }
    const uint32_t half = size / 2;
    morton_fill(x0, y0, half, w, h, o, k);
    morton_fill(x0 + half, y0, half, w, h, o, k);
    morton_fill(x0, y0 + half, half, w, h, o, k);
    morton_fill(x0 + half, y0 + half, half, w, h, o, k);
}

bool rt_pixel_order_make(rt_pixel_order_kind kind, uint32_t tile, uint32_t width, uint32_t height, uint32_t **out,
                         char *err, size_t errlen)
{
    *out = NULL;
    if (width < 1 || width > 65535 || height < 1 || height > 65535) {
        snprintf(err, errlen, "pixel order: image %ux%u out of range; allowed 1..65535 each", width, height);
        return false;
    }
    if (kind == RT_ORDER_SCANLINE)
        return true;
    if (kind == RT_ORDER_TILES && (tile < 1 || tile > 65535)) {
        snprintf(err, errlen, "pixel order: tile %u out of range; allowed 1..65535", tile);
        return false;
    }
    if (kind != RT_ORDER_TILES && kind != RT_ORDER_MORTON) {
        snprintf(err, errlen, "pixel order: unknown kind %d; allowed %s", (int)kind, RT_PIXEL_ORDER_CHOICES);
        return false;
    }
    const uint64_t n = (uint64_t)width * height;
    uint32_t *o = malloc((size_t)n * sizeof *o);
    if (!o) {
        snprintf(err, errlen, "pixel order: out of memory for %ux%u pixels", width, height);
        return false;
    }
    uint64_t k = 0;
    if (kind == RT_ORDER_TILES) {
        for (uint32_t ty = 0; ty < height; ty += tile)
            for (uint32_t tx = 0; tx < width; tx += tile) {
                const uint32_t ye = height - ty < tile ? height : ty + tile;
                const uint32_t xe = width - tx < tile ? width : tx + tile;
                for (uint32_t y = ty; y < ye; y++)
                    for (uint32_t x = tx; x < xe; x++)
                        o[k++] = y * width + x;
            }
    } else {
        /* Z order over the smallest power-of-two square holding the image
         * (depth at most 17 for 65535 pixels a side) */
        uint32_t side = 1;
        while (side < width || side < height)
            side <<= 1;
        morton_fill(0, 0, side, width, height, o, &k);
    }
    *out = o;
    return true;
}
