/* tb_trv_ist_passes.c — the pass logic of the TRV and IST cores
 * (model/ray/trv_core.h, model/ray/ist_core.h) on a hand-made 4-wide BVH: the
 * expected event sequence of a ray and of an occlusion ray; looping for a
 * next chance leaves results and events unchanged. Tested together because a
 * ray passes between the two. */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/accel_config.h"
#include "model/mem/memsys_config.h"
#include "model/ray/ist_core.h"
#include "model/ray/trv_core.h"
#include "testbench/tb.h"

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

int main(void)
{
    test_trv_ist_tiny();
    test_trv_ist_tiny_occlusion();
    return tb_finish();
}
