/* tb_tracer_bvh.c — BVH builders and the memory image: invariants of every
 * image (each triangle in exactly one leaf, boxes enclose their subtrees,
 * counts and bytes consistent, statistics recomputed), widths 2..8 and leaf
 * sizes 1..8, the round trip image -> builder's BVH2/collapse, Wald 2004
 * triangle records against a direct barycentric computation, the collapse
 * rule on a hand-made tree, bad parameters, determinism. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testbench/tb.h"
#include "testbench/tracer/tb_tracer_util.h"
#include "tracer/io/builtin.h"
#include "tracer/bvh/bvh.h"
#include "tracer/bvh/bvh2_sah.h"
#include "tracer/bvh/mbvh_collapse.h"
#include "tracer/bvh/wald_tri.h"

static void slot(const rt_bvh_image *img, uint32_t node, int s, rt_child *ch)
{
    rt_node_child(rt_bvh_node_ptr(img, node), s, ch);
}

static bool box_in(const float ilo[3], const float ihi[3], const float olo[3], const float ohi[3])
{
    for (int a = 0; a < 3; a++)
        if (ilo[a] < olo[a] || ihi[a] > ohi[a])
            return false;
    return true;
}

static double half_area(const float lo[3], const float hi[3])
{
    return (double)rt_box_half_area(lo, hi);
}

/* Checks every documented property of an image; the first failure in msg. */
static bool validate(const rt_mesh *m, const rt_bvh_params *p, const rt_bvh_image *img, const rt_bvh_stats *st,
                     char *msg, size_t len)
{
#define BAD(...) (snprintf(msg, len, __VA_ARGS__), false)
    if (img->width != p->width || img->node_bytes != (uint32_t)p->width * 32u || img->node_base != 0)
        return BAD("width %d / node_bytes %u / node_base %llu", img->width, img->node_bytes,
                   (unsigned long long)img->node_base);
    if (img->tri_base % 4096 != 0 || img->tri_base < (uint64_t)img->nnodes * img->node_bytes ||
        img->tri_base >= (uint64_t)img->nnodes * img->node_bytes + 4096)
        return BAD("tri_base %llu for %u nodes", (unsigned long long)img->tri_base, img->nnodes);
    if (img->ntris != m->ntris || img->size != img->tri_base + (uint64_t)m->ntris * RT_TRI_BYTES)
        return BAD("ntris %u size %llu", img->ntris, (unsigned long long)img->size);
    for (uint64_t b = (uint64_t)img->nnodes * img->node_bytes; b < img->tri_base; b++)
        if (img->bytes[b] != 0)
            return BAD("padding byte %llu not zero", (unsigned long long)b);
    uint8_t *node_seen = calloc(img->nnodes, 1), *tri_seen = calloc(m->ntris, 1), *prim_seen = calloc(m->ntris, 1);
    uint32_t *stack = malloc(2 * (size_t)img->nnodes * sizeof *stack);
    bool ok = true;
    uint32_t leaves = 0, hist[RT_LEAF_MAX + 1] = {0}, max_depth = 0, sp = 0, next_tri = 0;
    double sah = 0.0;
    float rlo[3] = {INFINITY, INFINITY, INFINITY}, rhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int s = 0; s < img->width; s++) {
        rt_child ch;
        slot(img, 0, s, &ch);
        if (rt_child_empty(&ch))
            break;
        for (int a = 0; a < 3; a++)
            rlo[a] = fminf(rlo[a], ch.lo[a]), rhi[a] = fmaxf(rhi[a], ch.hi[a]);
    }
    double root_area = half_area(rlo, rhi);
    if (!(root_area > 0))
        root_area = 1;
    /* leaf order: walking nodes by index and slots in order, leaves are consecutive */
    for (uint32_t n = 0; n < img->nnodes && ok; n++) {
        for (int s = 0; s < img->width; s++) {
            rt_child ch;
            slot(img, n, s, &ch);
            if (rt_child_is_leaf(&ch)) {
                if (ch.ref != next_tri)
                    ok = BAD("node %u slot %d: leaf starts at triangle %u, expected %u", n, s, ch.ref, next_tri);
                next_tri += rt_child_count(&ch);
            }
        }
    }
    stack[sp++] = 0, stack[sp++] = 1;
    while (ok && sp > 0) {
        const uint32_t depth = stack[--sp], n = stack[--sp];
        if (n >= img->nnodes || node_seen[n]) {
            ok = BAD("node %u reached twice or out of range", n);
            break;
        }
        node_seen[n] = 1;
        max_depth = depth > max_depth ? depth : max_depth;
        int used = 0, inner = 0;
        uint32_t prev_inner_ref = 0;
        bool empty_seen = false;
        float nlo[3] = {INFINITY, INFINITY, INFINITY}, nhi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int s = 0; s < img->width && ok; s++) {
            rt_child ch;
            slot(img, n, s, &ch);
            if (rt_child_empty(&ch)) {
                empty_seen = true;
                if (ch.meta != RT_META_EMPTY || ch.ref != 0)
                    ok = BAD("node %u slot %d: empty slot meta %08x ref %u", n, s, ch.meta, ch.ref);
                for (int a = 0; a < 3 && ok; a++)
                    if (!(ch.lo[a] == INFINITY && ch.hi[a] == -INFINITY))
                        ok = BAD("node %u slot %d: empty slot box not inverted", n, s);
                continue;
            }
            if (empty_seen) {
                ok = BAD("node %u: used slot %d after an empty one", n, s);
                break;
            }
            used++;
            if (ch.meta & ~(RT_META_COUNT_MASK)) {
                ok = BAD("node %u slot %d: meta %08x has stray bits", n, s, ch.meta);
                break;
            }
            for (int a = 0; a < 3; a++)
                nlo[a] = fminf(nlo[a], ch.lo[a]), nhi[a] = fmaxf(nhi[a], ch.hi[a]);
            if (!rt_child_is_leaf(&ch)) {
                if (inner++ > 0 && ch.ref != prev_inner_ref + 1) {
                    ok = BAD("node %u slot %d: inner children not a consecutive sibling block", n, s);
                    break;
                }
                prev_inner_ref = ch.ref;
                if (ch.ref == 0 || ch.ref >= img->nnodes) {
                    ok = BAD("node %u slot %d: child node %u out of range", n, s, ch.ref);
                    break;
                }
                for (int cs = 0; cs < img->width; cs++) {
                    rt_child g;
                    slot(img, ch.ref, cs, &g);
                    if (!rt_child_empty(&g) && !box_in(g.lo, g.hi, ch.lo, ch.hi))
                        ok = BAD("node %u slot %d: box does not enclose child node %u slot %d", n, s, ch.ref, cs);
                }
                stack[sp++] = ch.ref, stack[sp++] = depth + 1;
                continue;
            }
            const uint32_t cnt = rt_child_count(&ch);
            if (cnt < 1 || cnt > (uint32_t)p->leaf_size || (uint64_t)ch.ref + cnt > m->ntris) {
                ok = BAD("node %u slot %d: leaf of %u triangles at %u (leaf_size %d)", n, s, cnt, ch.ref, p->leaf_size);
                break;
            }
            leaves++, hist[cnt]++;
            sah += p->cost_tri * (double)cnt * half_area(ch.lo, ch.hi) / root_area;
            for (uint32_t i = ch.ref; i < ch.ref + cnt && ok; i++) {
                rt_tri48 t, want;
                rt_tri_decode(rt_bvh_tri_ptr(img, i), &t);
                if (tri_seen[i]++ || t.prim >= m->ntris || prim_seen[t.prim]++) {
                    ok = BAD("triangle slot %u (prim %u) in two leaves", i, t.prim);
                    break;
                }
                rt_wald_precompute_prim(m, t.prim, &want);
                if (memcmp(&t, &want, sizeof t) != 0)
                    ok = BAD("triangle slot %u: record differs from Wald precompute of prim %u", i, t.prim);
                for (int k = 0; k < 3 && ok; k++) {
                    const rt_vec3 v = m->verts[m->tris[3 * (size_t)t.prim + k]];
                    const float pv[3] = {v.x, v.y, v.z};
                    if (!box_in(pv, pv, ch.lo, ch.hi))
                        ok = BAD("node %u slot %d: leaf box misses vertex %d of prim %u", n, s, k, t.prim);
                }
            }
        }
        if (!ok)
            break;
        sah += p->cost_node * half_area(nlo, nhi) / root_area;
        if (used < (n == 0 ? 1 : 2))
            ok = BAD("node %u has %d used slots", n, used);
        else if (used < img->width && inner > 0)
            ok = BAD("node %u: %d of %d slots used but %d inner children left uncollapsed", n, used, img->width, inner);
    }
    if (ok) {
        for (uint32_t n = 0; n < img->nnodes && ok; n++)
            if (!node_seen[n])
                ok = BAD("node %u unreachable", n);
        for (uint32_t i = 0; i < m->ntris && ok; i++)
            if (!tri_seen[i] || !prim_seen[i])
                ok = BAD("triangle slot / prim %u in no leaf", i);
    }
    if (ok && st) {
        uint64_t hist_tris = 0;
        for (uint32_t k = 0; k <= RT_LEAF_MAX; k++) {
            hist_tris += (uint64_t)k * st->leaf_size_hist[k];
            if (st->leaf_size_hist[k] != hist[k])
                ok = BAD("stats: leaf_size_hist[%u] %u, counted %u", k, st->leaf_size_hist[k], hist[k]);
        }
        if (ok && (st->leaves != leaves || st->inner_nodes != img->nnodes || st->max_depth != max_depth ||
                   hist_tris != m->ntris || st->node_bytes_total != (uint64_t)img->nnodes * img->node_bytes ||
                   st->tri_bytes_total != (uint64_t)m->ntris * 48))
            ok = BAD("stats: leaves %u/%u inner %u/%u depth %u/%u hist sum %llu bytes %llu/%llu", st->leaves, leaves,
                     st->inner_nodes, img->nnodes, st->max_depth, max_depth, (unsigned long long)hist_tris,
                     (unsigned long long)st->node_bytes_total, (unsigned long long)st->tri_bytes_total);
        if (ok && !(fabs(st->sah_cost - sah) <= 1e-9 * sah))
            ok = BAD("stats: SAH %.9g, recomputed %.9g", st->sah_cost, sah);
    }
    free(node_seen), free(tri_seen), free(prim_seen), free(stack);
    return ok;
#undef BAD
}

/* Walks the image alongside the builder's BVH2 and collapse: every slot's box
 * must be the BVH2 node's box bit for bit, every leaf its triangles in order. */
static bool round_trip(const rt_mesh *m, const rt_bvh_params *p, const rt_bvh_image *img, char *msg, size_t len)
{
    rt_bvh2 b;
    if (!rt_bvh2_build_sah(m, p, &b)) {
        snprintf(msg, len, "rt_bvh2_build_sah failed");
        return false;
    }
    bool ok = true;
    uint32_t *pairs = malloc(2 * ((size_t)img->nnodes + 1) * sizeof *pairs), sp = 0, visited = 0;
    pairs[sp++] = 0, pairs[sp++] = 0;
    while (ok && sp > 0) {
        const uint32_t x = pairs[--sp], n = pairs[--sp];
        visited++;
        uint32_t kids[RT_WIDTH_MAX];
        int k;
        if (b.nodes[x].count != 0) {
            kids[0] = x, k = 1;   /* single-leaf root */
        } else {
            k = rt_mbvh_collapse_children(&b, x, p->width, kids);
        }
        for (int s = 0; s < p->width && ok; s++) {
            rt_child ch;
            slot(img, n, s, &ch);
            if (s >= k) {
                if (!rt_child_empty(&ch))
                    snprintf(msg, len, "node %u slot %d used, collapse gave %d children", n, s, k), ok = false;
                continue;
            }
            const rt_bvh2_node *bn = &b.nodes[kids[s]];
            if (memcmp(ch.lo, bn->lo, 12) || memcmp(ch.hi, bn->hi, 12)) {
                snprintf(msg, len, "node %u slot %d: box differs from BVH2 node %u", n, s, kids[s]);
                ok = false;
            } else if (bn->count == 0) {
                if (rt_child_is_leaf(&ch))
                    snprintf(msg, len, "node %u slot %d: leaf, BVH2 node %u is inner", n, s, kids[s]), ok = false;
                else
                    pairs[sp++] = ch.ref, pairs[sp++] = kids[s];
            } else if (rt_child_count(&ch) != bn->count) {
                snprintf(msg, len, "node %u slot %d: %u triangles, BVH2 leaf %u", n, s, rt_child_count(&ch), bn->count);
                ok = false;
            } else {
                for (uint32_t i = 0; i < bn->count && ok; i++) {
                    rt_tri48 t;
                    rt_tri_decode(rt_bvh_tri_ptr(img, ch.ref + i), &t);
                    if (t.prim != b.order[bn->first + i])
                        snprintf(msg, len, "node %u slot %d triangle %u: prim %u, BVH2 order says %u", n, s, i, t.prim,
                                 b.order[bn->first + i]), ok = false;
                }
            }
        }
    }
    if (ok && visited != img->nnodes)
        snprintf(msg, len, "walked %u nodes, image has %u", visited, img->nnodes), ok = false;
    free(pairs);
    rt_bvh2_free(&b);
    return ok;
}

static void build_with_and_check(const char *name, const rt_mesh *m, int width, int leaf, int builder)
{
    char cname[160], msg[512] = "", err[512] = "";
    snprintf(cname, sizeof cname, "bvh_%s_width%d_leaf%d%s_invariants_and_round_trip", name, width, leaf,
             builder == RT_BUILD_WALD ? "_wald" : "");
    tb_begin(cname);
    rt_bvh_params p;
    rt_bvh_params_default(&p);
    p.width = width, p.leaf_size = leaf, p.builder = builder;
    rt_bvh_image img;
    rt_bvh_stats st;
    if (TB_CHECK(rt_bvh_build(m, &p, &img, &st, err, sizeof err), "build failed: %s", err)) {
        TB_CHECK(validate(m, &p, &img, &st, msg, sizeof msg), "%s", msg);
        TB_CHECK(round_trip(m, &p, &img, msg, sizeof msg), "round trip: %s", msg);
        rt_bvh_image_free(&img);
    }
    tb_end();
}

static void build_and_check(const char *name, const rt_mesh *m, int width, int leaf)
{
    build_with_and_check(name, m, width, leaf, RT_BUILD_COLLAPSE);
}

/* The top-down splitting builder (RT_BUILD_WALD) against the collapse on
 * one mesh: its leaves are only cut by size, so it makes no more leaves
 * (none with fewer triangles than the SAH sweep would stop at), and so no
 * more N-wide nodes, and every leaf holds at most leaf_size triangles. */
static void test_wald_builder(const rt_mesh *m)
{
    tb_begin("bvh_wald_builder_fuller_leaves_fewer_nodes_width4");
    rt_bvh_params pc, pw;
    rt_bvh_params_default(&pc);
    pw = pc;
    pw.builder = RT_BUILD_WALD;
    rt_bvh_image ic, iw;
    rt_bvh_stats sc, sw;
    char err[512];
    if (TB_CHECK(rt_bvh_build(m, &pc, &ic, &sc, err, sizeof err), "%s", err)) {
        if (TB_CHECK(rt_bvh_build(m, &pw, &iw, &sw, err, sizeof err), "%s", err)) {
            TB_CHECK(sw.leaves < sc.leaves, "wald leaves %u, collapse %u", sw.leaves, sc.leaves);
            TB_CHECK(iw.nnodes < ic.nnodes, "wald nodes %u, collapse %u", iw.nnodes, ic.nnodes);
            uint32_t small = 0;   /* a wald leaf below leaf_size only where a split had to leave one */
            for (int k = pw.leaf_size + 1; k <= (int)RT_LEAF_MAX; k++)
                TB_CHECK(sw.leaf_size_hist[k] == 0, "a wald leaf of %d triangles (leaf_size %d)", k, pw.leaf_size);
            for (int k = 1; k < pw.leaf_size; k++)
                small += sw.leaf_size_hist[k];
            TB_CHECK(small < sw.leaves, "every wald leaf below leaf_size (%u of %u)", small, sw.leaves);
            TB_CHECK(iw.hash != ic.hash, "the builders gave the same image hash");
            rt_bvh_image_free(&iw);
        }
        rt_bvh_image_free(&ic);
    }
    /* a BVH2 ignores the builder: the same image */
    pc.width = pw.width = 2;
    if (TB_CHECK(rt_bvh_build(m, &pc, &ic, NULL, err, sizeof err), "%s", err)) {
        if (TB_CHECK(rt_bvh_build(m, &pw, &iw, NULL, err, sizeof err), "%s", err)) {
            TB_CHECK(iw.hash == ic.hash && iw.size == ic.size, "BVH2 changed with the builder");
            rt_bvh_image_free(&iw);
        }
        rt_bvh_image_free(&ic);
    }
    tb_end();
}

static void test_widths_and_leaves(void)
{
    rt_mesh soup;
    tbt_soup(tb_is_sanitized() ? 300 : 2000, 5, &soup);
    for (int w = RT_WIDTH_MIN; w <= RT_WIDTH_MAX; w++)
        for (int leaf = 1; leaf <= 8; leaf++)
            if (!tb_is_sanitized() || leaf == 1 || leaf == 4 || leaf == 8)
                build_and_check("soup", &soup, w, leaf);
    for (int w = 3; w <= RT_WIDTH_MAX; w++)
        for (int leaf = 1; leaf <= 8; leaf *= 2)
            build_with_and_check("soup", &soup, w, leaf, RT_BUILD_WALD);
    test_wald_builder(&soup);
    rt_mesh_free(&soup);

    /* special shapes: one triangle (single-leaf root), identical triangles
     * (all centroids coincide: middle splits), degenerate triangles */
    rt_mesh one;
    tbt_soup(1, 9, &one);
    build_and_check("one_triangle", &one, 4, 4);
    build_and_check("one_triangle", &one, 2, 1);
    rt_mesh_free(&one);
    rt_mesh same;
    tbt_soup(100, 3, &same);
    for (uint32_t i = 0; i < same.ntris; i++)
        for (int k = 0; k < 3; k++)
            same.tris[3 * i + k] = (uint32_t)k;   /* every triangle = triangle 0 */
    build_and_check("identical", &same, 2, 1);
    build_and_check("identical", &same, 4, 3);
    for (uint32_t i = 0; i < same.ntris; i++)
        same.tris[3 * i + 1] = same.tris[3 * i + 2] = same.tris[3 * i] = i % 7;   /* points */
    build_and_check("points", &same, 8, 2);
    rt_mesh_free(&same);

    unsigned nb = rt_builtin_count();
    for (unsigned i = 0; i < nb; i++) {
        if (tb_is_sanitized() && i > 0)
            break;
        rt_mesh m;
        char err[256];
        if (!rt_builtin_generate(rt_builtin_name(i), &m, NULL, err, sizeof err)) {
            tb_begin("bvh_builtin_generate");
            TB_CHECK(false, "%s", err);
            tb_end();
            continue;
        }
        build_and_check(rt_builtin_name(i), &m, 2, 4);
        build_and_check(rt_builtin_name(i), &m, 4, 4);
        rt_mesh_free(&m);
    }
}

static void test_bad_params(void)
{
    tb_begin("bvh_bad_params_rejected_naming_parameter_and_range");
    rt_mesh m;
    tbt_soup(10, 1, &m);
    struct {
        const char *field;
        int which;
        double value;
        const char *want1, *want2;
    } cases[] = {
        {"width", 0, 1, "width", "2..8"},     {"width", 0, 9, "width", "2..8"},
        {"leaf_size", 1, 0, "leaf_size", "1..255"}, {"leaf_size", 1, 256, "leaf_size", "1..255"},
        {"bins", 2, 3, "bins", "4..256"},     {"bins", 2, 257, "bins", "4..256"},
        {"cost_node", 3, 0, "cost_node", "(0, 1e6]"}, {"cost_node", 3, NAN, "cost_node", "(0, 1e6]"},
        {"cost_tri", 4, -1, "cost_tri", "(0, 1e6]"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        rt_bvh_params p;
        rt_bvh_params_default(&p);
        switch (cases[i].which) {
        case 0: p.width = (int)cases[i].value; break;
        case 1: p.leaf_size = (int)cases[i].value; break;
        case 2: p.bins = (int)cases[i].value; break;
        case 3: p.cost_node = (float)cases[i].value; break;
        default: p.cost_tri = (float)cases[i].value; break;
        }
        rt_bvh_image img;
        char err[256] = "";
        bool ok = rt_bvh_build(&m, &p, &img, NULL, err, sizeof err);
        TB_CHECK(!ok && strstr(err, cases[i].want1) && strstr(err, cases[i].want2), "%s = %g: ok %d, '%s'",
                 cases[i].field, cases[i].value, ok, err);
        if (ok)
            rt_bvh_image_free(&img);
        TB_CHECK(img.bytes == NULL && img.size == 0, "output not zeroed on failure");
    }
    rt_bvh_params p;
    rt_bvh_params_default(&p);
    rt_bvh_image img;
    char err[256] = "";
    m.tris[4] = 1000;
    TB_CHECK(!rt_bvh_build(&m, &p, &img, NULL, err, sizeof err) && strstr(err, "triangle 1") && strstr(err, "1000"),
             "bad index: '%s'", err);
    m.tris[4] = 4;
    m.verts[7].y = NAN;
    TB_CHECK(!rt_bvh_build(&m, &p, &img, NULL, err, sizeof err) && strstr(err, "vertex 7"), "NaN vertex: '%s'", err);
    m.verts[7].y = INFINITY;
    TB_CHECK(!rt_bvh_build(&m, &p, &img, NULL, err, sizeof err) && strstr(err, "finite"), "inf vertex: '%s'", err);
    rt_mesh_free(&m);
    TB_CHECK(!rt_bvh_build(&m, &p, &img, NULL, err, sizeof err) && strstr(err, "no triangles"), "empty: '%s'", err);
    rt_bvh_params_default(&p);
    TB_CHECK(p.width == 4 && p.leaf_size == 4 && p.bins == 16 && p.cost_node == 1.0f && p.cost_tri == 1.0f,
             "defaults");
    tb_end();
}

static void test_determinism(void)
{
    tb_begin("bvh_deterministic_same_bytes_and_hash");
    rt_mesh m;
    char err[256];
    const bool gen = rt_builtin_generate("forest", &m, NULL, err, sizeof err);
    if (TB_CHECK(gen, "%s", err)) {
        rt_bvh_params p;
        rt_bvh_params_default(&p);
        rt_bvh_image a, b, c;
        TB_CHECK(rt_bvh_build(&m, &p, &a, NULL, err, sizeof err), "%s", err);
        TB_CHECK(rt_bvh_build(&m, &p, &b, NULL, err, sizeof err), "%s", err);
        TB_CHECK(a.hash == b.hash && a.size == b.size && memcmp(a.bytes, b.bytes, a.size) == 0, "two builds differ");
        p.width = 2;
        TB_CHECK(rt_bvh_build(&m, &p, &c, NULL, err, sizeof err), "%s", err);
        TB_CHECK(c.hash != a.hash, "width 2 and 4 hash equal");
        rt_bvh_image_free(&c);
        p.width = 4, p.leaf_size = 5;
        TB_CHECK(rt_bvh_build(&m, &p, &c, NULL, err, sizeof err), "%s", err);
        TB_CHECK(c.hash != a.hash, "leaf sizes 4 and 5 hash equal");
        rt_bvh_image_free(&c);
        m.verts[0].x += 1e-3f;
        rt_bvh_params_default(&p);
        TB_CHECK(rt_bvh_build(&m, &p, &c, NULL, err, sizeof err), "%s", err);
        TB_CHECK(c.hash != a.hash, "moved vertex, same hash");
        rt_bvh_image_free(&a), rt_bvh_image_free(&b), rt_bvh_image_free(&c);
        rt_mesh_free(&m);
    }
    tb_end();
}

/* The collapse rule on a hand-made BVH2 with known areas:
 *   0: root -> 1 (A, inner, big), 2 (B, inner, small)
 *   A -> 3, 4 (leaves); B -> 5 (inner, tiny), 6 (leaf); 5 -> 7, 8 (leaves) */
static void test_collapse_rule(void)
{
    tb_begin("mbvh_collapse_largest_area_first_in_place");
    rt_bvh2_node nodes[9];
    memset(nodes, 0, sizeof nodes);
    const float sz[9] = {10, 8, 4, 3, 3, 1, 2, 0.5f, 0.5f};
    for (int i = 0; i < 9; i++)
        for (int a = 0; a < 3; a++)
            nodes[i].lo[a] = 0, nodes[i].hi[a] = sz[i];
    nodes[0].first = 1, nodes[1].first = 3, nodes[2].first = 5, nodes[5].first = 7;
    for (int i = 3; i < 9; i++)
        if (i != 5)
            nodes[i].count = 1;
    const rt_bvh2 b = {nodes, 9, NULL, 0};
    uint32_t out[RT_WIDTH_MAX];
    int k = rt_mbvh_collapse_children(&b, 0, 2, out);
    TB_CHECK(k == 2 && out[0] == 1 && out[1] == 2, "width 2: %d [%u %u]", k, out[0], out[1]);
    k = rt_mbvh_collapse_children(&b, 0, 3, out);
    TB_CHECK(k == 3 && out[0] == 3 && out[1] == 4 && out[2] == 2, "width 3: A (largest) opened in place");
    k = rt_mbvh_collapse_children(&b, 0, 4, out);
    TB_CHECK(k == 4 && out[0] == 3 && out[1] == 4 && out[2] == 5 && out[3] == 6, "width 4: then B");
    k = rt_mbvh_collapse_children(&b, 0, 8, out);
    TB_CHECK(k == 5 && out[2] == 7 && out[3] == 8 && out[4] == 6, "width 8: stops when only leaves are left (%d)", k);
    /* B larger than A: B is opened first */
    for (int a = 0; a < 3; a++)
        nodes[2].hi[a] = 9;
    k = rt_mbvh_collapse_children(&b, 0, 3, out);
    TB_CHECK(k == 3 && out[0] == 1 && out[1] == 5 && out[2] == 6, "width 3, B largest: [%u %u %u]", out[0], out[1],
             out[2]);
    tb_end();
}

/* Wald records against a direct barycentric computation (double, Cramer's
 * rule in 3D): rays through known barycentric points of random triangles. */
static void test_wald_precompute(void)
{
    tb_begin("wald_records_match_direct_barycentrics");
    rt_rng r;
    rt_rng_seed(&r, 11, 0);
    int bad = 0, tested = 0;
    double worst_uv = 0, worst_t = 0;
    for (int i = 0; i < 20000; i++) {
        rt_vec3 v[3];
        for (int k = 0; k < 3; k++)
            v[k] = (rt_vec3){tbt_uniform(&r, -2, 2), tbt_uniform(&r, -2, 2), tbt_uniform(&r, -2, 2)};
        rt_tri48 t;
        rt_wald_precompute(v[0], v[1], v[2], (uint32_t)i, &t);
        if (t.flags)
            continue;   /* random vertices: (almost) never degenerate */
        float b = tbt_uniform(&r, 0.02f, 0.96f), c = tbt_uniform(&r, 0.02f, 0.96f);
        if (b + c > 0.98f)
            b = 0.98f - b, c = 0.98f - c;   /* reflect into the triangle */
        const double P[3] = {v[0].x + b * ((double)v[1].x - v[0].x) + c * ((double)v[2].x - v[0].x),
                             v[0].y + b * ((double)v[1].y - v[0].y) + c * ((double)v[2].y - v[0].y),
                             v[0].z + b * ((double)v[1].z - v[0].z) + c * ((double)v[2].z - v[0].z)};
        const float org[3] = {tbt_uniform(&r, -5, 5), tbt_uniform(&r, -5, 5), tbt_uniform(&r, -5, 5)};
        const float dir[3] = {(float)(P[0] - org[0]), (float)(P[1] - org[1]), (float)(P[2] - org[2])};
        /* direct computation: solve org + t dir = v0 + u e1 + w e2 (double) */
        const double e1[3] = {(double)v[1].x - v[0].x, (double)v[1].y - v[0].y, (double)v[1].z - v[0].z};
        const double e2[3] = {(double)v[2].x - v[0].x, (double)v[2].y - v[0].y, (double)v[2].z - v[0].z};
        const double s[3] = {org[0] - (double)v[0].x, org[1] - (double)v[0].y, org[2] - (double)v[0].z};
        const double d[3] = {dir[0], dir[1], dir[2]};
        const double pv[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
        const double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
        const double nn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        const double cosang = fabs(det) / (sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) *
                                           sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]));
        if (cosang < 0.05)
            continue;   /* grazing: badly conditioned for any float method */
        const double u = (s[0] * pv[0] + s[1] * pv[1] + s[2] * pv[2]) / det;
        const double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
        const double w = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
        const double tt = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
        float th, uh, vh;
        tested++;
        if (!rt_wald_test(&t, org, dir, 0.0f, FLT_MAX, &th, &uh, &vh)) {
            if (bad++ == 0)
                fprintf(stderr, "miss: b %g c %g det %g u %g w %g t %g\n", b, c, det, u, w, tt);
            continue;
        }
        worst_uv = fmax(worst_uv, fmax(fabs(uh - u), fabs(vh - w)));
        worst_t = fmax(worst_t, fabs(th - tt) / tt);
        /* a point well outside edge 1 (beta < 0) must miss */
        const double Q[3] = {P[0] - 0.05 * e1[0] * 2 - b * e1[0], P[1] - 0.05 * e1[1] * 2 - b * e1[1],
                             P[2] - 0.05 * e1[2] * 2 - b * e1[2]};
        const float dq[3] = {(float)(Q[0] - org[0]), (float)(Q[1] - org[1]), (float)(Q[2] - org[2])};
        if (rt_wald_test(&t, org, dq, 0.0f, FLT_MAX, &th, &uh, &vh) && bad++ == 0)
            fprintf(stderr, "false hit: b %g c %g u %g v %g\n", b, c, uh, vh);
    }
    TB_CHECK(tested > 10000, "only %d triangles tested", tested);
    TB_CHECK(bad == 0, "%d of %d rays: hit/miss wrong", bad, tested);
    fprintf(stderr, "Wald vs direct: worst |du|,|dv| %.3g, worst relative dt %.3g\n", worst_uv, worst_t);
    TB_CHECK(worst_uv < 1e-4 && worst_t < 1e-5, "worst |du|,|dv| %.3g, worst relative dt %.3g", worst_uv, worst_t);
    tb_end();

    tb_begin("wald_degenerate_triangles_flagged_never_hit");
    const rt_vec3 a = {0, 0, 0}, b = {1, 0, 0}, c = {2, 0, 0}, d = {0, 1, 0};
    rt_tri48 t;
    const float org[3] = {0.5f, -1, 0.01f}, dir[3] = {0, 1, 0};
    float th, uh, vh;
    rt_wald_precompute(a, b, c, 1, &t);   /* collinear */
    TB_CHECK(t.flags == RT_TRI_FLAG_DEGENERATE && !rt_wald_test(&t, org, dir, 0, FLT_MAX, &th, &uh, &vh),
             "collinear");
    rt_wald_precompute(a, a, d, 2, &t);   /* repeated vertex */
    TB_CHECK(t.flags == RT_TRI_FLAG_DEGENERATE && t.prim == 2, "repeated vertex");
    rt_wald_precompute(d, d, d, 3, &t);   /* point */
    TB_CHECK(t.flags == RT_TRI_FLAG_DEGENERATE, "point");
    const rt_vec3 sliver = {1, 1e-39f, 0};
    rt_wald_precompute(a, b, sliver, 4, &t);   /* 1/det overflows float */
    TB_CHECK(t.flags == RT_TRI_FLAG_DEGENERATE, "vanishing triangle not flagged");
    rt_wald_precompute(a, b, d, 5, &t);
    const float o2[3] = {0.25f, 0.25f, 1}, d2[3] = {0, 0, -1};
    TB_CHECK(t.flags == 0 && t.k == 2 && rt_wald_test(&t, o2, d2, 0, FLT_MAX, &th, &uh, &vh) && th == 1.0f &&
                 uh == 0.25f && vh == 0.25f,
             "unit triangle: t %g u %g v %g", (double)th, (double)uh, (double)vh);
    TB_CHECK(!rt_wald_test(&t, o2, d2, 1.0f, FLT_MAX, &th, &uh, &vh) && !rt_wald_test(&t, o2, d2, 0, 1.0f, &th, &uh, &vh),
             "t must be strictly inside (tmin, tmax)");
    tb_end();
}

int main(void)
{
    test_collapse_rule();
    test_wald_precompute();
    test_bad_params();
    test_determinism();
    test_widths_and_leaves();
    return tb_finish();
}
