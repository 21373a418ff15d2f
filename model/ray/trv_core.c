/* trv_core.c — one TRV pass (see trv_core.h). */
#include "model/ray/trv_core.h"

#include <stdio.h>
#include <string.h>

#include "model/ray/trv_slab.h"

bool trv_core_init(trv_core *c, const trv_core_params *p, const accel_image *img, accel_probe_fn probe,
                   void *probe_ctx, char *err, unsigned errlen)
{
    *c = (trv_core){0};
    if (p->width < RT_WIDTH_MIN || p->width > RT_WIDTH_MAX) {
        snprintf(err, errlen, "trv: width %d out of range (allowed %d..%d)", p->width, RT_WIDTH_MIN, RT_WIDTH_MAX);
        return false;
    }
    if (img && img->width != p->width) {
        snprintf(err, errlen, "trv: machine width %d does not match the BVH image's width %d", p->width, img->width);
        return false;
    }
    if (!trv_stack_init(&c->stack, p->slots, p->stack_depth, p->stack_banks, err, errlen))
        return false;
    c->p = *p;
    c->img = img;
    c->net = sort_net_get(p->width);
    c->probe = probe;
    c->probe_ctx = probe_ctx;
    c->guard_slot = -1;
    return true;
}

void trv_core_free(trv_core *c) { trv_stack_free(&c->stack); }

static inline void emit(trv_core *c, const accel_ray *r, int kind, uint32_t a, uint32_t b, float t)
{
    if (c->ev)
        c->ev(c->ev_user, r->uid, kind, a, b, t);
}

/* The entry becomes the ray's target; returns the pass result for it. */
static trv_pass_result take_target(trv_core *c, accel_ray *r, uint32_t ref, uint32_t meta)
{
    r->target_ref = ref;
    r->target_meta = meta;
    uint32_t count = meta & RT_META_COUNT_MASK;
    /* host-side prefetch of the bytes the ray's next pass reads (a pipeline
     * depth later): simulation speed only, no effect on the model */
    const accel_image *img = c->img;
    const uint8_t *next = count ? img->bytes + img->tri_base + (uint64_t)ref * RT_TRI_BYTES
                                : img->bytes + img->node_base + (uint64_t)ref * img->node_bytes;
    __builtin_prefetch(next);
    __builtin_prefetch(next + 64);
    if (count) {
        r->phase = RAY_LEAF;
        r->tri_next = ref;
        r->tri_end = ref + count;
        emit(c, r, ACCEL_EV_LEAF, ref, count, 0.0f);
        c->st.to_ist++;
        return TRV_TO_IST;
    }
    r->phase = RAY_VISIT;
    return TRV_CONTINUE;
}

static trv_pass_result pop_next(trv_core *c, accel_ray *r, uint32_t *stack_cycles)
{
    uint32_t reads = 0;
    trv_stack_entry e;
    trv_pass_result res = TRV_DONE;
    if (r->occlusion && r->prim != ACCEL_NO_HIT) {
        /* an occlusion ray back from the IST with a hit is answered: the
         * slot's stack pointer is reset (no entry is read) and the ray ends */
        trv_stack_clear(&c->stack, r->slot);
        r->phase = RAY_DONE;
        emit(c, r, ACCEL_EV_DONE, r->prim, 0, r->closest);
        c->st.done++;
        return TRV_DONE;
    }
    c->st.pop_passes++;
    while (trv_stack_peek(&c->stack, r->slot, reads, &e)) {
        reads++;
        if (c->p.distance_cull && e.tnear > r->closest) {
            emit(c, r, ACCEL_EV_CULL, e.ref, e.meta, e.tnear);
            c->st.culls++;
            continue;
        }
        emit(c, r, ACCEL_EV_POP, e.ref, e.meta, e.tnear);
        int cyc = trv_stack_pop(&c->stack, r->slot, reads);
        *stack_cycles = (uint32_t)cyc;
        return take_target(c, r, e.ref, e.meta);
    }
    *stack_cycles = (uint32_t)trv_stack_pop(&c->stack, r->slot, reads);
    r->phase = RAY_DONE;
    emit(c, r, ACCEL_EV_DONE, r->prim, 0, r->closest);
    c->st.done++;
    return res;
}

/* The sort keys of lanes 0..n-1 (sort_key_pack, bit for bit): with SSE2 the
 * float-to-ordered-integer flip of four lanes at once, then the slot and hit
 * folded in per lane. */
static inline __attribute__((always_inline)) void pack_keys(const float *tnear, uint32_t hit_bits, int n, uint64_t *keys)
{
#if defined(__SSE2__)
    uint32_t u[8];
#pragma GCC unroll 2
    for (int base = 0; base < n; base += 4) {
        /* t + 0.0f (so -0 ties +0), then negatives flip all bits, positives the sign */
        const __m128i b = _mm_castps_si128(_mm_add_ps(_mm_loadu_ps(tnear + base), _mm_setzero_ps()));
        const __m128i f = _mm_xor_si128(b, _mm_or_si128(_mm_srai_epi32(b, 31), _mm_set1_epi32((int)0x80000000u)));
        _mm_storeu_si128((__m128i *)(void *)(u + base), f);
    }
#pragma GCC unroll 8
    for (int i = 0; i < n; i++) {
        const uint64_t k = ((uint64_t)u[i] << 8) | (unsigned)i;
        const uint64_t miss = ((uint64_t)1 << 40) | (unsigned)i;
        keys[i] = (hit_bits >> i) & 1 ? k : miss;
    }
#else
    for (int i = 0; i < n; i++)
        keys[i] = sort_key_pack(tnear[i], (unsigned)i, (hit_bits >> i) & 1);
#endif
}

trv_pass_result trv_core_pass(trv_core *c, accel_ray *r, uint64_t now, uint32_t *stack_cycles)
{
    *stack_cycles = 0;
    c->st.passes++;
    if (r->phase == RAY_POP)
        return pop_next(c, r, stack_cycles);

    /* RAY_VISIT: fetch the node through the node L1 */
    const accel_image *img = c->img;
    uint64_t addr = img->node_base + (uint64_t)r->target_ref * img->node_bytes;
    c->fetch_cycles = 1;
    if (c->guard && c->present) {
        if (c->guard_slot < 0) {
            c->guard_slot = r->slot;   /* the first ray to visit takes the token */
        } else if (c->guard_slot != (int64_t)r->slot && !c->present(c->probe_ctx, addr, img->node_bytes)) {
            r->loops++;
            c->st.loops_blocked++;
            return TRV_LOOP_BLOCKED;   /* no new misses while another ray holds the token */
        }
    }
    cache_result cr = c->probe ? c->probe(c->probe_ctx, addr, img->node_bytes, now, &c->fetch_cycles) : CACHE_HIT;
    if (c->guard && cr == CACHE_HIT && c->guard_slot == (int64_t)r->slot)
        c->guard_slot = -1;            /* it got its node: the next ray's turn */
    if (cr != CACHE_HIT) {
        r->loops++;
        if (cr == CACHE_MISS) {
            c->st.loops_miss++;
            return TRV_LOOP_MISS;
        }
        c->st.loops_blocked++;
        return TRV_LOOP_BLOCKED;
    }
    c->st.visits++;
    r->visits++;
    emit(c, r, ACCEL_EV_VISIT, r->target_ref, 0, 0.0f);

    const uint8_t *node = img->bytes + addr;
    const int n = c->p.width;
    uint64_t keys[SORT_NET_MAX_LANES];
    float tnear[SORT_NET_MAX_LANES];
    uint32_t hit_bits;
    /* the used slots' slab tests against [tmin, closest], all lanes at once (trv_slab.h) */
    c->st.box_tests += (uint64_t)trv_slab_lanes(&r->prep, node, n, r->tmin, r->closest, tnear, &hit_bits);
    if (n == 4)   /* constant lane counts: the loops unrolled */
        pack_keys(tnear, hit_bits, 4, keys);
    else if (n == 2)
        pack_keys(tnear, hit_bits, 2, keys);
    else
        pack_keys(tnear, hit_bits, n, keys);
    const int hits = trv_popcount8(hit_bits);
    c->st.box_lanes += (uint64_t)n;
    if (!r->occlusion) {
        c->st.sort_passes++;
        c->st.sort_swaps += (uint64_t)sort_net_apply_packed_fast(c->net, keys);
    } else {
        /* occlusion rays bypass the sorting network (paper sec. 3.1): the
         * hit lanes in slot order (a priority encoder, no comparators) */
        int k = 0;
        for (int i = 0; i < n; i++)
            if ((hit_bits >> i) & 1)
                keys[k++] = keys[i];
    }
    if (hits == 0)
        return pop_next(c, r, stack_cycles);

    /* push all but the nearest, farthest first: the second nearest ends on top */
    trv_stack_entry push[SORT_NET_MAX_LANES];
    uint32_t k = 0;
    for (int i = hits - 1; i >= 1; i--) {
        unsigned sl = sort_key_slot(keys[i]);
        rt_child chi;
        rt_node_child(node, (int)sl, &chi);
        push[k].ref = chi.ref;
        push[k].meta = chi.meta & RT_META_COUNT_MASK;
        push[k].tnear = tnear[sl];
        k++;
    }
    if (k) {
        int cyc = trv_stack_push(&c->stack, r->slot, push, k);
        if (cyc < 0) {
            /* the ray ends here: empty its stack, or the next ray admitted
             * to this slot would start on the failed ray's entries (found
             * by tb_accel_random_configs: later rays overflowed early or
             * popped another ray's nodes) */
            trv_stack_clear(&c->stack, r->slot);
            r->phase = RAY_FAILED;
            c->st.overflows++;
            return TRV_OVERFLOW;
        }
        for (uint32_t i = 0; i < k; i++)
            emit(c, r, ACCEL_EV_PUSH, push[i].ref, push[i].meta, push[i].tnear);
        *stack_cycles = (uint32_t)cyc;
    }
    rt_child near;
    rt_node_child(node, (int)sort_key_slot(keys[0]), &near);
    return take_target(c, r, near.ref, near.meta & RT_META_COUNT_MASK);
}
