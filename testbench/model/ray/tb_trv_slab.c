/* tb_trv_slab.c — the TRV's slab test lanes (model/ray/trv_slab.h) against
 * the reference traversal's box test, bit for bit. */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/ray/trv_slab.h"
#include "tracer/bvh/bvh_layout.h"
#include "testbench/tb.h"

/* -------------------------------------------------------------- slab lanes */

/* A float from a small set of awkward values or a random one. */
static float slab_value(uint32_t *seed)
{
    *seed = *seed * 1664525u + 1013904223u;
    const uint32_t k = *seed >> 24;
    static const float special[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, 1e-30f, -1e-30f, 1e30f, -1e30f};
    if (k < 24)
        return special[k % 9];
    if (k < 28)
        return k & 1 ? INFINITY : -INFINITY;
    if (k < 30)
        return NAN;
    *seed = *seed * 1664525u + 1013904223u;
    return ((float)(*seed >> 8) / 16777216.0f - 0.5f) * 8.0f;
}

static bool same_float(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* trv_slab_lanes equals rt_slab_test per used slot, bit for bit (tnear included),
 * on random nodes of every width with NaN, infinities, signed zeros, rays on
 * slab planes and parallel to axes, and empty slots. */
static void test_slab_lanes(void)
{
    tb_begin("trv_slab_lanes_equals_rt_slab_test");
    uint32_t seed = 12345;
    long cases = 0, bad = 0, hits = 0;
    const int rounds = tb_is_sanitized() ? 3000 : 30000;
    for (int round = 0; round < rounds; round++) {
        const int n = 1 + round % 8;
        uint8_t node[8 * RT_SLOT_BYTES];
        for (int i = 0; i < n; i++) {
            float f[6];
            for (int k = 0; k < 6; k++)
                f[k] = slab_value(&seed);
            if (round % 3 == 0) /* mostly proper boxes */
                for (int k = 0; k < 3; k++)
                    if (f[k] > f[k + 3]) {
                        const float t = f[k];
                        f[k] = f[k + 3];
                        f[k + 3] = t;
                    }
            const uint32_t ref = seed, meta = (seed >> 5) % 7 == 0 ? RT_META_EMPTY : (seed >> 9) % 5;
            memcpy(node + (size_t)i * RT_SLOT_BYTES, f, sizeof f);
            memcpy(node + (size_t)i * RT_SLOT_BYTES + 24, &ref, 4);
            memcpy(node + (size_t)i * RT_SLOT_BYTES + 28, &meta, 4);
        }
        float org[3], dir[3];
        for (int k = 0; k < 3; k++) {
            org[k] = slab_value(&seed);
            dir[k] = slab_value(&seed);
        }
        rt_ray_prep prep;
        rt_ray_prepare(org, dir, &prep);
        const float tmin = round % 4 ? 0.0f : slab_value(&seed), tmax = round % 5 ? INFINITY : slab_value(&seed);
        float tnear[8];
        uint32_t hit_bits;
        const int used = trv_slab_lanes(&prep, node, n, tmin, tmax, tnear, &hit_bits);
        int want_used = 0;
        for (int i = 0; i < n; i++) {
            const uint8_t *slot = node + (size_t)i * RT_SLOT_BYTES;
            uint32_t meta;
            memcpy(&meta, slot + 28, 4);
            float lohi[6], tn = 0.0f;
            memcpy(lohi, slot, sizeof lohi);
            bool h = false;
            if (!(meta & RT_META_EMPTY)) {
                want_used++;
                h = rt_slab_test(&prep, lohi, lohi + 3, tmin, tmax, &tn);
            }
            hits += h;
            cases++;
            const bool got = (hit_bits >> i) & 1;
            if (h != got || !same_float(tn, tnear[i])) {
                if (bad++ < 3)
                    TB_CHECK(0, "round %d lane %d of %d: hit %d tnear %g, want %d %g", round, i, n, got,
                             (double)tnear[i], h, (double)tn);
            }
        }
        TB_EQ_INT(used, want_used);
        TB_EQ_INT(hit_bits >> n, 0);
    }
    TB_EQ_INT(bad, 0);
    TB_CHECK(hits > cases / 20 && hits < cases, "a mix of hits and misses (%ld of %ld)", hits, cases);
    tb_end();
}

int main(void)
{
    test_slab_lanes();
    return tb_finish();
}
