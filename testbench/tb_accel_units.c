/* tb_accel_units.c — unit testbenches of the ray-side hardware logic that
 * need no kernel: the sorting networks (0-1 principle for every width, all
 * orderings of 4 lanes with ties against the reference order), the banked
 * traversal stack (conflicts, overflow), and the TRV/IST pass logic on a
 * hand-made BVH (expected event sequence; looping for next chance leaves
 * results and events unchanged). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/accel_config.h"
#include "model/mem/memsys_config.h"
#include "model/ray/ist.h"
#include "model/ray/ist_core.h"
#include "model/ray/scheduler.h"
#include "model/ray/trv.h"
#include "model/ray/sort_net.h"
#include "model/ray/trv_core.h"
#include "model/ray/trv_slab.h"
#include "model/ray/trv_stack.h"
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

/* -------------------------------------------------------------- trv stack */

static void test_stack_banks(void)
{
    tb_begin("trv_stack_banking_and_conflicts");
    char err[200];
    trv_stack s;
    TB_CHECK(trv_stack_init(&s, 4, 8, 3, err, sizeof err), "%s", err);
    trv_stack_entry e[4] = {{1, 0, 1.0f}, {2, 0, 2.0f}, {3, 4, 3.0f}, {4, 0, 4.0f}};
    /* 3 pushes over 3 banks: one cycle (MBVH4 with N-1 banks) */
    TB_EQ_INT(trv_stack_push(&s, 1, e, 3), 1);
    TB_EQ_INT(s.st.conflict_cycles, 0);
    TB_EQ_INT(trv_stack_size(&s, 1), 3);
    TB_EQ_INT(trv_stack_size(&s, 0), 0);
    trv_stack_entry top;
    TB_CHECK(trv_stack_peek(&s, 1, 0, &top) && top.ref == 3 && top.meta == 4 && top.tnear == 3.0f, "top is last pushed");
    TB_CHECK(trv_stack_peek(&s, 1, 2, &top) && top.ref == 1, "bottom is first pushed");
    TB_CHECK(!trv_stack_peek(&s, 1, 3, &top), "no 4th entry");
    /* 4 entries over 3 banks: two land in one bank -> 2 cycles, 1 conflict */
    TB_EQ_INT(trv_stack_push(&s, 2, e, 4), 2);
    TB_EQ_INT(s.st.conflict_cycles, 1);
    /* pops: 1 entry 1 cycle; 3 at once (culls) 1 cycle */
    TB_EQ_INT(trv_stack_pop(&s, 2, 1), 1);
    TB_EQ_INT(trv_stack_pop(&s, 2, 3), 1);
    TB_CHECK(trv_stack_empty(&s, 2), "emptied");
    /* overflow: 3 + 4 + 2 > 8 entries: reported, nothing pushed */
    TB_EQ_INT(trv_stack_push(&s, 1, e, 4), 2);
    TB_EQ_INT(trv_stack_push(&s, 1, e, 2), -1);
    TB_EQ_INT(trv_stack_size(&s, 1), 7);
    TB_EQ_INT(s.st.overflows, 1);
    TB_EQ_INT(s.st.max_depth, 7);
    trv_stack_free(&s);
    /* a single bank (BVH2 baseline) serialises multi-entry operations */
    TB_CHECK(trv_stack_init(&s, 1, 64, 1, err, sizeof err), "%s", err);
    TB_EQ_INT(trv_stack_push(&s, 0, e, 3), 3);
    TB_EQ_INT(trv_stack_pop(&s, 0, 2), 2);
    TB_EQ_INT(s.st.conflict_cycles, 3);
    trv_stack_free(&s);
    TB_CHECK(!trv_stack_init(&s, 0, 64, 1, err, sizeof err) && strstr(err, "slots 0"), "zero slots refused: %s", err);
    TB_CHECK(!trv_stack_init(&s, 4, 64, 0, err, sizeof err) && strstr(err, "banks 0"), "zero banks refused: %s", err);
    tb_end();
}

/* ------------------------------------------------- TRV and IST pass logic */

/* A hand-made 4-wide BVH: root (node 0) with children
 *   slot 0: inner node 1, box x in [4,5]   (far)
 *   slot 1: leaf tris 0..1, box x in [1,2] (near)
 *   slot 2: empty, slot 3: empty
 * node 1: slot 0 leaf tri 2, box x in [4,5]; rest empty.
 * Triangles: planes x = 1.5 (tri 0, covering), x = 1.8 (tri 1), x = 4.5 (tri 2).
 * Ray from (0,0,0) along +x. */
typedef struct tiny_scene {
    uint8_t bytes[4096 + 3 * 48];
    accel_image img;
} tiny_scene;

static void put_child(uint8_t *node, int c, float lx, float hx, uint32_t ref, uint32_t meta)
{
    rt_child ch = {{lx, -1, -1}, {hx, 1, 1}, ref, meta};
    if (meta & RT_META_EMPTY) {
        for (int a = 0; a < 3; a++)
            ch.lo[a] = INFINITY, ch.hi[a] = -INFINITY;
    }
    memcpy(node + c * 32, &ch, sizeof ch);
}

/* Wald form of a plane x = d with k = 0 (dominant axis x): n_u = n_v = 0,
 * n_d = d; u = y, v = z; edges make a big triangle covering |y|,|z| small. */
static void put_tri_x(uint8_t *at, float d, uint32_t prim)
{
    rt_tri48 t = {0};
    t.k = 0;
    t.n_d = d;
    /* beta = hv * b_nu + hu * b_nv + b_d = 0.25 + y*0.1 ; gamma = 0.25 + z*0.1 */
    t.b_nu = 0.0f, t.b_nv = 0.1f, t.b_d = 0.25f;
    t.c_nu = 0.0f, t.c_nv = 0.1f, t.c_d = 0.25f;
    t.prim = prim;
    memcpy(at, &t, sizeof t);
}

static void tiny_build(tiny_scene *s)
{
    memset(s->bytes, 0, sizeof s->bytes);
    uint8_t *n0 = s->bytes, *n1 = s->bytes + 128;
    put_child(n0, 0, 4, 5, 1, 0);
    put_child(n0, 1, 1, 2, 0, 2);
    put_child(n0, 2, 0, 0, 0, RT_META_EMPTY);
    put_child(n0, 3, 0, 0, 0, RT_META_EMPTY);
    put_child(n1, 0, 4, 5, 2, 1);
    for (int c = 1; c < 4; c++)
        put_child(n1, c, 0, 0, 0, RT_META_EMPTY);
    put_tri_x(s->bytes + 4096, 1.8f, 70);
    put_tri_x(s->bytes + 4096 + 48, 1.5f, 71);
    put_tri_x(s->bytes + 4096 + 96, 4.5f, 72);
    s->img = (accel_image){s->bytes, sizeof s->bytes, 0, 4096, 4, 128, 2, 3};
}

typedef struct ev_log {
    int n;
    int kind[64];
    uint32_t a[64], b[64];
    float t[64];
} ev_log;

static void log_ev(void *user, uint32_t uid, int kind, uint32_t a, uint32_t b, float t)
{
    (void)uid;
    ev_log *l = user;
    if (l->n < 64) {
        l->kind[l->n] = kind, l->a[l->n] = a, l->b[l->n] = b, l->t[l->n] = t;
        l->n++;
    }
}

/* A memory that misses every line the first `misses_per_line` times it is
 * probed (the fill "arrives" by the next probe), and blocks every 5th probe. */
typedef struct flaky_mem {
    int misses_per_line;
    int probes;
    int seen[128];
} flaky_mem;

static cache_result flaky_probe(void *ctx, uint64_t addr, uint32_t bytes, uint64_t now, uint32_t *cycles)
{
    (void)bytes, (void)now;
    *cycles = 1;
    flaky_mem *m = ctx;
    if (++m->probes % 5 == 0)
        return CACHE_BLOCKED;
    int line = (int)(addr / 64) % 128;
    if (m->seen[line] < m->misses_per_line) {
        m->seen[line]++;
        return CACHE_MISS;
    }
    return CACHE_HIT;
}

/* Drives one ray through TRV and IST passes until done; returns passes. */
static int run_ray(trv_core *trv, ist_core *ist, accel_ray *r, int *loops)
{
    int passes = 0;
    *loops = 0;
    uint32_t sc;
    for (uint64_t now = 0; passes < 1000; now++) {
        passes++;
        if (r->phase == RAY_LEAF) {
            ist_result ir = ist_core_test(ist, r, now);
            if (ir == IST_LOOP_MISS || ir == IST_LOOP_BLOCKED)
                ++*loops;
            continue;
        }
        trv_pass_result pr = trv_core_pass(trv, r, now, &sc);
        if (pr == TRV_LOOP_MISS || pr == TRV_LOOP_BLOCKED)
            ++*loops;
        if (pr == TRV_DONE || pr == TRV_OVERFLOW)
            break;
    }
    return passes;
}

static void test_trv_ist_tiny(void)
{
    tb_begin("trv_ist_pass_sequence_and_looping");
    static tiny_scene sc;
    tiny_build(&sc);
    char err[200];
    trv_core_params p = {4, true, 2, 64, 3};
    ev_log ideal = {0}, flaky = {0};
    float want_t[2];
    uint32_t want_prim[2];
    for (int variant = 0; variant < 2; variant++) {
        flaky_mem fm = {.misses_per_line = 2};
        trv_core trv;
        TB_CHECK(trv_core_init(&trv, &p, &sc.img, variant ? flaky_probe : NULL, &fm, err, sizeof err), "%s", err);
        ist_core ist = {&sc.img, variant ? flaky_probe : NULL, &fm, log_ev, variant ? &flaky : &ideal, {0}, 1};
        trv.ev = log_ev;
        trv.ev_user = variant ? &flaky : &ideal;
        accel_ray r;
        accel_ray_in in = {{0, 0, 0}, {1, 0, 0}, 0.0f, 1e30f, 7, 0, 0};
        accel_ray_start(&r, &in, 0);
        r.slot = 1;
        int loops;
        run_ray(&trv, &ist, &r, &loops);
        TB_EQ_INT(r.phase, RAY_DONE);
        want_t[variant] = r.closest;
        want_prim[variant] = r.prim;
        if (variant == 0)
            TB_EQ_INT(loops, 0);
        else
            TB_CHECK(loops >= 4, "flaky memory made the ray loop (%d loops)", loops);
        TB_EQ_INT(trv_stack_size(&trv.stack, 1), 0);
        trv_core_free(&trv);
    }
    /* expected (distance stack on): VISIT 0, PUSH node 1 (t=4), LEAF 0,2,
     * TRI 0 (x=1.8, closer), TRI 1 (x=1.5, closer), CULL node 1 (4 > 1.5), DONE 71 */
    static const int kinds[] = {ACCEL_EV_VISIT, ACCEL_EV_PUSH, ACCEL_EV_LEAF, ACCEL_EV_TRI,
                                ACCEL_EV_TRI,   ACCEL_EV_CULL, ACCEL_EV_DONE};
    TB_EQ_INT(ideal.n, 7);
    for (int i = 0; i < 7 && i < ideal.n; i++)
        TB_CHECK(ideal.kind[i] == kinds[i], "event %d kind %d want %d", i, ideal.kind[i], kinds[i]);
    TB_CHECK(ideal.a[1] == 1 && ideal.t[1] == 4.0f, "push node 1 at t=4 (a=%u t=%g)", ideal.a[1], ideal.t[1]);
    TB_CHECK(ideal.a[2] == 0 && ideal.b[2] == 2, "leaf 0 count 2");
    TB_CHECK(ideal.b[3] == 1 && ideal.b[4] == 1 && ideal.t[4] == 1.5f, "both triangles closer in turn");
    TB_CHECK(ideal.a[6] == 71 && ideal.t[6] == 1.5f, "done with prim 71 at 1.5 (%u %g)", ideal.a[6], ideal.t[6]);
    TB_CHECK(want_prim[0] == 71 && want_prim[1] == 71 && want_t[0] == want_t[1], "same hit with looping");
    TB_EQ_INT(flaky.n, ideal.n);
    TB_CHECK(memcmp(ideal.kind, flaky.kind, sizeof ideal.kind) == 0 && memcmp(ideal.a, flaky.a, sizeof ideal.a) == 0 &&
                 memcmp(ideal.b, flaky.b, sizeof ideal.b) == 0,
             "looping for next chance leaves the event sequence unchanged");

    /* without the distance stack (BVH-style) node 1 is popped and visited */
    trv_core trv;
    p.distance_cull = false;
    TB_CHECK(trv_core_init(&trv, &p, &sc.img, NULL, NULL, err, sizeof err), "%s", err);
    ev_log nc = {0};
    trv.ev = log_ev, trv.ev_user = &nc;
    ist_core ist = {&sc.img, NULL, NULL, log_ev, &nc, {0}, 1};
    accel_ray r;
    accel_ray_in in = {{0, 0, 0}, {1, 0, 0}, 0.0f, 1e30f, 7, 0, 0};
    accel_ray_start(&r, &in, 0);
    r.slot = 0;
    int loops;
    run_ray(&trv, &ist, &r, &loops);
    TB_CHECK(nc.n >= 6 && nc.kind[5] == ACCEL_EV_POP && nc.a[5] == 1, "pop node 1 instead of cull");
    TB_CHECK(nc.n >= 7 && nc.kind[6] == ACCEL_EV_VISIT && nc.a[6] == 1, "then visit node 1 (which misses the ray's t range)");
    TB_CHECK(r.prim == 71, "same hit");
    trv_core_free(&trv);

    /* width mismatch is refused */
    p.width = 2;
    TB_CHECK(!trv_core_init(&trv, &p, &sc.img, NULL, NULL, err, sizeof err) && strstr(err, "width"), "width mismatch: %s",
             err);
    tb_end();
}

/* An occlusion ray on the tiny scene: no sort, so node 1 (slot 0, tnear 4)
 * is visited before the nearer leaf (slot 1, tnear 1), which is pushed; the
 * first triangle hit (tri 2 at x = 4.5) ends the ray, and the pass that ends
 * it clears the pushed leaf from the slot's stack without reading it. */
static void test_trv_ist_tiny_occlusion(void)
{
    tb_begin("trv_ist_occlusion_ray_slot_order_any_hit");
    static tiny_scene sc;
    tiny_build(&sc);
    char err[200];
    trv_core_params p = {4, true, 2, 64, 3};
    trv_core trv;
    TB_CHECK(trv_core_init(&trv, &p, &sc.img, NULL, NULL, err, sizeof err), "%s", err);
    ev_log lg = {0};
    trv.ev = log_ev, trv.ev_user = &lg;
    ist_core ist = {&sc.img, NULL, NULL, log_ev, &lg, {0}, 1};
    accel_ray r;
    accel_ray_in in = {{0, 0, 0}, {1, 0, 0}, 0.0f, 1e30f, 7, 1, 1};
    accel_ray_start(&r, &in, 0);
    r.slot = 1;
    int loops;
    run_ray(&trv, &ist, &r, &loops);
    TB_EQ_INT(r.phase, RAY_DONE);
    /* VISIT 0, PUSH leaf (0, 2, t=1), VISIT 1, LEAF 2 1, TRI 2 (hit), DONE 72 */
    static const int kinds[] = {ACCEL_EV_VISIT, ACCEL_EV_PUSH, ACCEL_EV_VISIT, ACCEL_EV_LEAF, ACCEL_EV_TRI, ACCEL_EV_DONE};
    TB_EQ_INT(lg.n, 6);
    for (int i = 0; i < 6 && i < lg.n; i++)
        TB_CHECK(lg.kind[i] == kinds[i], "event %d kind %d want %d", i, lg.kind[i], kinds[i]);
    TB_CHECK(lg.a[1] == 0 && lg.b[1] == 2 && lg.t[1] == 1.0f, "the nearer leaf is pushed (slot order)");
    TB_CHECK(lg.a[2] == 1, "node 1 (slot 0) is visited first");
    TB_CHECK(lg.a[4] == 2 && lg.b[4] == 1 && lg.a[5] == 72 && lg.t[5] == 4.5f, "tri 2 at 4.5 answers the ray");
    TB_CHECK(r.prim == 72 && r.closest == 4.5f, "hit kept (%u %g)", r.prim, r.closest);
    TB_EQ_INT(trv.st.sort_passes, 0);
    TB_EQ_INT(trv.st.sort_swaps, 0);
    TB_EQ_INT(trv.st.pop_passes, 0);
    TB_EQ_INT(trv_stack_size(&trv.stack, 1), 0);
    TB_EQ_INT(trv.stack.st.pops, 0);
    trv_core_free(&trv);
    tb_end();
}

/* The ray-side FIFO table names each FIFO's key; the [fifo] schema defines
 * it: every key the table names must be one the schema registers. */
static void test_ray_fifo_table_keys(void)
{
    tb_begin("ray_fifo_table_keys_are_schema_keys");
    char err[300];
    rtcfg *cfg = rtcfg_create();
    TB_CHECK(cfg && memsys_add_schemas(cfg, err, sizeof err) == 0 && accel_add_schemas(cfg, err, sizeof err) == 0,
             "schemas: %s", err);
    for (int i = 0; cfg && i < ACCEL_FIFO_COUNT; i++)
        TB_CHECK(rtcfg_has(cfg, accel_ray_fifos[i].key), "%s: key %s not in the [fifo] schema",
                 accel_ray_fifos[i].name, accel_ray_fifos[i].key);
    rtcfg_destroy(cfg);
    tb_end();
}

static void test_module_tables(void)
{
    tb_begin("module_description_tables_valid");
    const ks_module_desc *descs[] = {&trv_module_desc, &ist_module_desc, &sched_module_desc};
    char err[300];
    for (int i = 0; i < 3; i++) {
        TB_CHECK(ks_module_desc_check(descs[i], err, sizeof err) == 0, "%s", err);
        /* parameters: the unit's configuration section, not rows of its own */
        TB_CHECK(descs[i]->config_sections && !strcmp(descs[i]->config_sections, descs[i]->name) &&
                     ks_module_desc_count(descs[i], KS_DESC_PARAM) == 0 &&
                     ks_module_desc_count(descs[i], KS_DESC_PORT) > 0 && ks_module_desc_count(descs[i], KS_DESC_STAT) > 0,
                 "%s documents its section, ports and statistics", descs[i]->name);
    }
    /* the section the description names is the schema the unit declares */
    TB_CHECK(!strcmp(trv_schema.section, "trv") && !strcmp(ist_schema.section, "ist") &&
                 !strcmp(sched_schema.section, "sched"),
             "schema sections");
    /* depth: fetch 1 + box 3 + sort layers + stack 1 + next 1; MBVH4 is 2 deeper than BVH2 (paper 3.1) */
    trv_params p = {{2, false, 32, 64, 1}, 1, 3, 1, 1, 12};
    uint32_t d2 = trv_pipeline_depth(&p);
    p.core.width = 4;
    TB_EQ_INT(trv_pipeline_depth(&p), d2 + 2);
    tb_end();
}

int main(void)
{
    test_sort_zero_one();
    test_sort_four_with_ties();
    test_slab_lanes();
    test_stack_banks();
    test_trv_ist_tiny();
    test_trv_ist_tiny_occlusion();
    test_module_tables();
    test_ray_fifo_table_keys();
    return tb_finish();
}
