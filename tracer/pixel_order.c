/* pixel_order.c — see pixel_order.h. */
#include "tracer/pixel_order.h"

#include <stdio.h>
#include <stdlib.h>

/* The even bits of v packed into 16 bits (x of a Morton code; y from v >> 1). */
static uint32_t pack_bits(uint32_t v)
{
    v &= 0x55555555u;
    v = (v | (v >> 1)) & 0x33333333u;
    v = (v | (v >> 2)) & 0x0f0f0f0fu;
    v = (v | (v >> 4)) & 0x00ff00ffu;
    v = (v | (v >> 8)) & 0x0000ffffu;
    return v;
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
        /* Z order over the smallest power-of-two square holding the image;
         * codes outside the image are skipped */
        uint32_t side = 1;
        while (side < width || side < height)
            side <<= 1;
        const uint64_t codes = (uint64_t)side * side;
        for (uint64_t c = 0; c < codes && k < n; c++) {
            const uint32_t x = pack_bits((uint32_t)c), y = pack_bits((uint32_t)(c >> 1));
            if (x < width && y < height)
                o[k++] = y * width + x;
        }
    }
    *out = o;
    return true;
}
