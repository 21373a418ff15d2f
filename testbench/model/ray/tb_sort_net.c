/* tb_sort_net.c — the TRV's sorting networks (model/ray/sort_net.h): the 0-1
 * principle for every width, and every ordering of 4 lanes with ties against
 * the reference order. */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/ray/sort_net.h"
#include "testbench/tb.h"

/* ---------------------------------------------------------------- sort net */

static void test_sort_zero_one(void)
{
    tb_begin("sort_net_zero_one_principle_all_widths");
    static const int depth[9] = {0, 0, 1, 3, 3, 5, 5, 6, 6};
    static const int cmps[9] = {0, 0, 1, 3, 5, 9, 12, 16, 19};
    for (int n = 1; n <= SORT_NET_MAX_LANES; n++) {
        const sort_net *net = sort_net_get(n);
        if (!TB_CHECK(net != NULL, "no network for %d", n))
            break;
        TB_EQ_INT(net->layers, depth[n]);
        TB_EQ_INT(net->ncmps, cmps[n]);
        /* each layer uses a lane at most once (one pipeline stage) */
        int start = 0;
        for (int l = 0; l < net->layers; l++) {
            unsigned used = 0;
            for (int i = start; i < net->layer_end[l]; i++) {
                unsigned m = (1u << net->cmp[i].lo) | (1u << net->cmp[i].hi);
                TB_CHECK(!(used & m), "n=%d layer %d reuses a lane", n, l);
                TB_CHECK(net->cmp[i].lo < net->cmp[i].hi && net->cmp[i].hi < n, "n=%d bad comparator", n);
                used |= m;
            }
            start = net->layer_end[l];
        }
        for (unsigned bits = 0; bits < (1u << n); bits++) {
            int v[8];
            for (int i = 0; i < n; i++)
                v[i] = (bits >> i) & 1;
            for (int i = 0; i < net->ncmps; i++) {
                int a = net->cmp[i].lo, b = net->cmp[i].hi;
                if (v[a] > v[b]) {
                    int t = v[a];
                    v[a] = v[b];
                    v[b] = t;
                }
            }
            for (int i = 1; i < n; i++)
                TB_CHECK(v[i - 1] <= v[i], "n=%d input %x not sorted", n, bits);
        }
    }
    TB_CHECK(sort_net_get(0) == NULL && sort_net_get(9) == NULL, "out-of-range widths give NULL");
    tb_end();
}

static int ref_cmp(const void *pa, const void *pb)
{
    const sort_key *a = pa, *b = pb;
    if (a->hit != b->hit)
        return a->hit ? -1 : 1;
    if (a->hit && a->tnear != b->tnear)
        return a->tnear < b->tnear ? -1 : 1;
    return (int)a->slot - (int)b->slot;
}

static void test_sort_four_with_ties(void)
{
    tb_begin("sort_net_4_all_orderings_with_ties");
    const sort_net *net = sort_net_get(4);
    static const float vals[4] = {-0.0f, 0.0f, 1.5f, 1.5e30f};   /* ties, signed zeros, extremes */
    long cases = 0;
    /* every assignment of 4 values (ties included, -0 == +0) x every hit mask */
    for (int code = 0; code < 256; code++) {
        for (unsigned mask = 0; mask < 16; mask++) {
            sort_key k[4], want[4];
            for (int i = 0; i < 4; i++) {
                k[i].tnear = vals[(code >> (2 * i)) & 3];
                k[i].slot = (uint8_t)i;
                k[i].hit = (uint8_t)((mask >> i) & 1);
            }
            memcpy(want, k, sizeof k);
            qsort(want, 4, sizeof want[0], ref_cmp);
            uint64_t packed[4];
            for (int i = 0; i < 4; i++)
                packed[i] = sort_key_pack(k[i].tnear, k[i].slot, k[i].hit);
            uint64_t fast[4];
            memcpy(fast, packed, sizeof fast);
            const int swaps = sort_net_apply_packed(net, packed);
            /* the constant-comparator 4-lane network: same order, same swap count */
            TB_EQ_INT(sort_net_apply_packed_fast(net, fast), swaps);
            TB_CHECK(memcmp(fast, packed, sizeof fast) == 0, "fast network differs: code %d mask %x", code, mask);
            for (int i = 0; i < 4; i++)
                TB_CHECK(sort_key_slot(packed[i]) == want[i].slot && sort_key_hit(packed[i]) == (want[i].hit != 0),
                         "packed: code %d mask %x lane %d: slot %u, want %d", code, mask, i, sort_key_slot(packed[i]),
                         want[i].slot);
            sort_net_apply(net, k);
            for (int i = 0; i < 4; i++)
                TB_CHECK(k[i].slot == want[i].slot, "code %d mask %x lane %d: slot %d, want %d", code, mask, i,
                         k[i].slot, want[i].slot);
            cases++;
        }
    }
    TB_EQ_INT(cases, 4096);
    /* the compare-swap of BVH2: slot 1 first only if strictly nearer */
    const sort_net *n2 = sort_net_get(2);
    sort_key a[2] = {{2.0f, 0, 1}, {2.0f, 1, 1}};
    sort_net_apply(n2, a);
    TB_CHECK(a[0].slot == 0, "tie keeps slot 0 first");
    for (int o = 0; o < 2; o++) { /* the 2-lane fast network equals the table */
        uint64_t p2[SORT_NET_MAX_LANES] = {sort_key_pack(1.0f + (float)o, 0, true), sort_key_pack(1.5f, 1, true)},
                 q2[SORT_NET_MAX_LANES];
        memcpy(q2, p2, sizeof q2);
        const int sw2 = sort_net_apply_packed(n2, p2);
        TB_EQ_INT(sort_net_apply_packed_fast(n2, q2), sw2);
        TB_CHECK(memcmp(p2, q2, sizeof p2) == 0, "2-lane fast network differs (case %d)", o);
    }
    sort_key b[2] = {{2.0f, 0, 1}, {1.0f, 1, 1}};
    TB_EQ_INT(sort_net_apply(n2, b), 1);
    TB_CHECK(b[0].slot == 1, "nearer slot 1 first");
    tb_end();
}

int main(void)
{
    test_sort_zero_one();
    test_sort_four_with_ties();
    return tb_finish();
}
