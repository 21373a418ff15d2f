/* sort_net.h — depth-optimal sorting networks for 2..8 inputs, as the MBVH
 * TRV's sort stage (paper sec. 3.1, Fig. 4: 4 inputs, 5 comparators in 3
 * layers; "Knuth gives depth-optimal networks for up to 16 inputs").
 *
 * Contract: sort_net_get(n) returns the network for n lanes (1..8); each
 * layer is one pipeline stage of the TRV (layers = extra TRV latency).
 * sort_net_apply() orders lane keys exactly like the reference traversal
 * (tracer/trace/traverse.h): hit lanes first, ascending tnear, ties by slot index;
 * missed lanes last. The keys are unique (distinct slots), so every correct
 * network gives that one order. Networks (depth, comparators): 2 (1, 1),
 * 3 (3, 3), 4 (3, 5), 5 (5, 9), 6 (5, 12), 7 (6, 16), 8 (6, 19) — the optimal
 * figures of Knuth, TAOCP vol. 3, sec. 5.3.4; the 8-input one is Batcher's
 * odd-even merge network. Each was checked with the 0-1 principle (testbench). */
#ifndef RTSIM_MODEL_SORT_NET_H
#define RTSIM_MODEL_SORT_NET_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#define SORT_NET_MAX_LANES 8
#define SORT_NET_MAX_CMPS 19

typedef struct sort_net_cmp {
    uint8_t lo, hi;   /* lane indices, lo < hi: after it lane lo holds the smaller key */
} sort_net_cmp;

typedef struct sort_net {
    int lanes;                        /* n */
    int layers;                       /* depth = pipeline stages */
    int ncmps;                        /* comparators in total */
    uint8_t layer_end[SORT_NET_MAX_LANES];   /* comparators of layer l: [layer_end[l-1], layer_end[l]) */
    sort_net_cmp cmp[SORT_NET_MAX_CMPS];
} sort_net;

/* One lane: a child's slab test result. */
typedef struct sort_key {
    float tnear;
    uint8_t slot;     /* child slot index in the node */
    uint8_t hit;      /* 0: the box was missed (sorts last) */
} sort_key;

/* The network for n lanes, 1..SORT_NET_MAX_LANES (n = 1: no comparators);
 * NULL for other n. */
const sort_net *sort_net_get(int n);

/* True when key a must come before key b (the comparator's decision). */
static inline bool sort_key_before(const sort_key *a, const sort_key *b)
{
    if (a->hit != b->hit)
        return a->hit > b->hit;
    if (a->hit && a->tnear != b->tnear)
        return a->tnear < b->tnear;
    return a->slot < b->slot;
}

/* Passes keys[0..lanes) through the network in place; returns the number of
 * compare-exchanges that swapped (activity statistics). Inline: it runs on
 * every node visit of the simulation. */
static inline int sort_net_apply(const sort_net *net, sort_key *keys)
{
    int swaps = 0;
    for (int i = 0; i < net->ncmps; i++) {
        sort_key *a = &keys[net->cmp[i].lo], *b = &keys[net->cmp[i].hi];
        if (sort_key_before(b, a)) {
            sort_key tmp = *a;
            *a = *b;
            *b = tmp;
            swaps++;
        }
    }
    return swaps;
}

/* The same order as one unsigned 64-bit key per lane, for a branchless
 * network (min/max compile to conditional moves): bit 40 = missed, bits
 * 8..39 = tnear mapped to an order-preserving unsigned integer (-0 taken as
 * +0, so equal distances tie as in the reference), bits 0..7 = slot. */
static inline uint64_t sort_key_pack(float tnear, unsigned slot, bool hit)
{
    float t = tnear + 0.0f;   /* -0 + +0 = +0 (round to nearest): equal zeros tie */
    uint32_t u;
    memcpy(&u, &t, sizeof u);
    u ^= (uint32_t)((int32_t)u >> 31) | 0x80000000u;   /* negatives: flip all; positives: flip the sign */
    uint64_t k = ((uint64_t)u << 8) | slot;
    uint64_t miss = ((uint64_t)1 << 40) | slot;
    return hit ? k : miss;   /* a conditional move, no branch */
}
static inline unsigned sort_key_slot(uint64_t k) { return (unsigned)(k & 0xFF); }
static inline bool sort_key_hit(uint64_t k) { return !(k >> 40); }

/* sort_net_apply on packed keys, branch-free; returns the swaps made. */
static inline int sort_net_apply_packed(const sort_net *net, uint64_t *keys)
{
    int swaps = 0;
    for (int i = 0; i < net->ncmps; i++) {
        uint64_t a = keys[net->cmp[i].lo], b = keys[net->cmp[i].hi];
        int sw = b < a;
        keys[net->cmp[i].lo] = sw ? b : a;
        keys[net->cmp[i].hi] = sw ? a : b;
        swaps += sw;
    }
    return swaps;
}

/* sort_net_apply_packed for the 2- and 4-lane networks (BVH2, MBVH4: every node
 * visit of the simulation) with the comparators as constants, so the keys stay in
 * registers; the same comparators in the same order as the tables of sort_net.c
 * (4 lanes: paper Fig. 4), hence the same order and swap count. Other widths use
 * the table. */
#define SORT_NET_CX_(k, a, b, swaps)                \
    do {                                            \
        const uint64_t x_ = k[a], y_ = k[b];        \
        const int sw_ = y_ < x_;                    \
        k[a] = sw_ ? y_ : x_;                       \
        k[b] = sw_ ? x_ : y_;                       \
        swaps += sw_;                               \
    } while (0)
static inline int sort_net_apply_packed_fast(const sort_net *net, uint64_t *keys)
{
    int swaps = 0;
    if (net->lanes == 4) {
        uint64_t k[4] = {keys[0], keys[1], keys[2], keys[3]};
        SORT_NET_CX_(k, 0, 1, swaps);
        SORT_NET_CX_(k, 2, 3, swaps);
        SORT_NET_CX_(k, 0, 2, swaps);
        SORT_NET_CX_(k, 1, 3, swaps);
        SORT_NET_CX_(k, 1, 2, swaps);
        memcpy(keys, k, sizeof k);
        return swaps;
    }
    if (net->lanes == 2) {
        SORT_NET_CX_(keys, 0, 1, swaps);
        return swaps;
    }
    return sort_net_apply_packed(net, keys);
}

#endif
