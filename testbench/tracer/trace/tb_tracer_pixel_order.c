/* tb_tracer_pixel_order.c — tracer/trace/pixel_order.h: every order is a
 * permutation of the image's pixels (each once); tiles run tile by tile,
 * scanline inside; Morton order equals sorting the pixels by their
 * interleaved-bit code (x in the low bit), also for images far from a
 * power-of-two square; bad arguments are refused with the range. */
#include <stdlib.h>
#include <string.h>

#include "testbench/tb.h"
#include "tracer/trace/pixel_order.h"

static uint64_t morton_code(uint32_t x, uint32_t y)
{
    uint64_t c = 0;
    for (int b = 0; b < 16; b++)
        c |= (uint64_t)((x >> b) & 1u) << (2 * b) | (uint64_t)((y >> b) & 1u) << (2 * b + 1);
    return c;
}

static bool is_permutation(const uint32_t *o, uint32_t n)
{
    unsigned char *seen = calloc(n, 1);
    bool ok = seen != NULL;
    for (uint32_t i = 0; ok && i < n; i++) {
        ok = o[i] < n && !seen[o[i]];
        if (ok)
            seen[o[i]] = 1;
    }
    free(seen);
    return ok;
}

static void check_size(uint32_t w, uint32_t h)
{
    char name[96], err[256];
    snprintf(name, sizeof name, "pixel_order_%ux%u_permutations_tiles_morton", w, h);
    tb_begin(name);
    uint32_t *t = NULL, *m = NULL, *s = NULL;
    TB_CHECK(rt_pixel_order_make(RT_ORDER_SCANLINE, 1, w, h, &s, err, sizeof err) && s == NULL, "scanline: %s", err);
    if (TB_CHECK(rt_pixel_order_make(RT_ORDER_TILES, 8, w, h, &t, err, sizeof err), "tiles: %s", err)) {
        TB_CHECK(is_permutation(t, w * h), "tiles is not a permutation");
        /* pixel k of the tile order: its tile comes no earlier than the last one's */
        uint64_t bad = 0;
        for (uint32_t k = 1; k < w * h; k++) {
            const uint32_t a = t[k - 1], b = t[k];
            const uint32_t ta = (a / w / 8) * ((w + 7) / 8) + (a % w) / 8, tb = (b / w / 8) * ((w + 7) / 8) + (b % w) / 8;
            bad += tb < ta || (tb == ta && b < a);
        }
        TB_EQ_INT(bad, 0);
    }
    if (TB_CHECK(rt_pixel_order_make(RT_ORDER_MORTON, 0, w, h, &m, err, sizeof err), "morton: %s", err)) {
        TB_CHECK(is_permutation(m, w * h), "morton is not a permutation");
        uint64_t bad = 0;
        for (uint32_t k = 1; k < w * h; k++)
            bad += morton_code(m[k - 1] % w, m[k - 1] / w) >= morton_code(m[k] % w, m[k] / w);
        TB_EQ_INT(bad, 0);
    }
    free(t), free(m);
    tb_end();
}

int main(void)
{
    const uint32_t sizes[][2] = {{1, 1}, {1, 7}, {13, 1}, {8, 8}, {33, 17}, {320, 180}, {1000, 3}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++)
        check_size(sizes[i][0], sizes[i][1]);

    tb_begin("pixel_order_bad_arguments_refused_with_range");
    uint32_t *o = NULL;
    char err[256] = "";
    TB_CHECK(!rt_pixel_order_make(RT_ORDER_TILES, 0, 8, 8, &o, err, sizeof err) && strstr(err, "1..65535"), "%s", err);
    TB_CHECK(!rt_pixel_order_make(RT_ORDER_MORTON, 0, 0, 8, &o, err, sizeof err) && strstr(err, "1..65535"), "%s", err);
    TB_CHECK(o == NULL, "an order was returned on an error");
    tb_end();
    return tb_finish();
}
