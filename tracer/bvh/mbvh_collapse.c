/* mbvh_collapse.c — see mbvh_collapse.h. */
#include "tracer/bvh/mbvh_collapse.h"

int rt_mbvh_collapse_children(const rt_bvh2 *b, uint32_t x, int width, uint32_t out[RT_WIDTH_MAX])
{
    int k = 2;
    out[0] = b->nodes[x].first;
    out[1] = b->nodes[x].first + 1;
    while (k < width) {
        int pick = -1;
        float best = -1.0f;
        for (int i = 0; i < k; i++) {
            const rt_bvh2_node *c = &b->nodes[out[i]];
            if (c->count != 0)
                continue;
            const float a = rt_box_half_area(c->lo, c->hi);
            if (a > best)
                best = a, pick = i;
        }
        if (pick < 0)
            break;
        const uint32_t left = b->nodes[out[pick]].first;
        for (int i = k; i > pick + 1; i--)
            out[i] = out[i - 1];
        out[pick] = left;
        out[pick + 1] = left + 1;
        k++;
    }
    return k;
}
