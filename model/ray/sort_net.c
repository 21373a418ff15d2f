/* sort_net.c — the network tables (see sort_net.h for their sources) and the
 * compare-exchange pass. */
#include "model/ray/sort_net.h"

#include <stddef.h>

/* Comparator lists by layer, written as in Knuth's diagrams. */
typedef struct net_def {
    int layers;
    int per_layer[SORT_NET_MAX_LANES];
    sort_net_cmp cmp[SORT_NET_MAX_CMPS];
} net_def;

static const net_def defs[SORT_NET_MAX_LANES + 1] = {
    [1] = {0, {0}, {{0, 0}}},
    [2] = {1, {1}, {{0, 1}}},
    [3] = {3, {1, 1, 1}, {{0, 2}, {0, 1}, {1, 2}}},
    /* paper Fig. 4: (0,1)(2,3) | (0,2)(1,3) | (1,2) */
    [4] = {3, {2, 2, 1}, {{0, 1}, {2, 3}, {0, 2}, {1, 3}, {1, 2}}},
    [5] = {5, {2, 2, 2, 2, 1}, {{0, 3}, {1, 4}, {0, 2}, {1, 3}, {0, 1}, {2, 4}, {1, 2}, {3, 4}, {2, 3}}},
    [6] = {5, {3, 2, 2, 3, 2},
           {{0, 5}, {1, 3}, {2, 4}, {1, 2}, {3, 4}, {0, 3}, {2, 5}, {0, 1}, {2, 3}, {4, 5}, {1, 2}, {3, 4}}},
    [7] = {6, {3, 3, 3, 2, 2, 3},
           {{0, 6}, {2, 3}, {4, 5}, {0, 2}, {1, 4}, {3, 6}, {0, 1}, {2, 5}, {3, 4}, {1, 2}, {4, 6}, {2, 3}, {4, 5},
            {1, 2}, {3, 4}, {5, 6}}},
    [8] = {6, {4, 4, 4, 2, 2, 3},
           {{0, 2}, {1, 3}, {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}, {0, 1}, {2, 3}, {4, 5}, {6, 7}, {2, 4},
            {3, 5}, {1, 4}, {3, 6}, {1, 2}, {3, 4}, {5, 6}}},
};

static sort_net nets[SORT_NET_MAX_LANES + 1];
static bool nets_ready;

static void build_nets(void)
{
    for (int n = 1; n <= SORT_NET_MAX_LANES; n++) {
        sort_net *s = &nets[n];
        s->lanes = n;
        s->layers = defs[n].layers;
        int k = 0;
        for (int l = 0; l < s->layers; l++) {
            k += defs[n].per_layer[l];
            s->layer_end[l] = (uint8_t)k;
        }
        s->ncmps = k;
        for (int i = 0; i < k; i++)
            s->cmp[i] = defs[n].cmp[i];
    }
    nets_ready = true;
}

const sort_net *sort_net_get(int n)
{
    if (n < 1 || n > SORT_NET_MAX_LANES)
        return NULL;
    if (!nets_ready)
        build_nets();   /* idempotent: racing initialisers write identical bytes */
    return &nets[n];
}
