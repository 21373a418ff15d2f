/* tb_tracelog_codec.c — trace log codec on synthetic trees: hand-built
 * memory images (widths 2, 4, 8, random triangles, median splits) traversed
 * by a small independent implementation of traverse.h's algorithm written
 * here, so these cases need no BVH builder. Round trip of every event and
 * ray field; every single-byte flip and every truncation of a small log is
 * rejected with a message naming the file and a byte offset; mutations of
 * the decompressed records re-packed with valid CRCs never crash and are
 * either rejected or read back identically; a log is rejected against an
 * image with another hash, and against a forged image of equal hash; the
 * writer rejects event streams that are no traversal of the image. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "testbench/tb.h"
#include "testbench/tracer/tb_tracer_util.h"
#include "tracer/trace/camera.h"
#include "tracer/util/rng.h"
#include "tracer/log/trace_log.h"
#include "tracer/log/trace_log_format.h"

/* ---------- a synthetic memory image ---------- */

typedef struct syn_tri {
    float v[3][3];
} syn_tri;

typedef struct syn_builder {
    const syn_tri *tris;
    uint32_t *idx;         /* triangle order, permuted into leaf order */
    uint8_t *nodes;
    uint32_t nnodes, cap;
    int width, leaf_size;
} syn_builder;

static void tri_bounds(const syn_tri *t, float lo[3], float hi[3])
{
    for (int a = 0; a < 3; a++) {
        lo[a] = fminf(t->v[0][a], fminf(t->v[1][a], t->v[2][a]));
        hi[a] = fmaxf(t->v[0][a], fmaxf(t->v[1][a], t->v[2][a]));
    }
}

static int g_axis;
static const syn_tri *g_tris;
static int cmp_centroid(const void *pa, const void *pb)
{
    const syn_tri *a = &g_tris[*(const uint32_t *)pa], *b = &g_tris[*(const uint32_t *)pb];
    float ca = a->v[0][g_axis] + a->v[1][g_axis] + a->v[2][g_axis];
    float cb = b->v[0][g_axis] + b->v[1][g_axis] + b->v[2][g_axis];
    if (ca != cb)
        return ca < cb ? -1 : 1;
    return *(const uint32_t *)pa < *(const uint32_t *)pb ? -1 : 1;
}

/* Builds node for idx[first, first+n) (n > leaf_size); returns its index. */
static uint32_t syn_node(syn_builder *b, uint32_t first, uint32_t n)
{
    uint32_t me = b->nnodes++;
    uint32_t nb = rt_node_bytes(b->width);
    if (b->nnodes > b->cap) {
        b->cap = b->cap ? 2 * b->cap : 64;
        b->nodes = realloc(b->nodes, (size_t)b->cap * nb);
    }
    /* split along the largest extent into `width` equal parts */
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = 0; i < n; i++) {
        float l[3], h[3];
        tri_bounds(&b->tris[b->idx[first + i]], l, h);
        for (int a = 0; a < 3; a++)
            lo[a] = fminf(lo[a], l[a]), hi[a] = fmaxf(hi[a], h[a]);
    }
    g_axis = 0;
    for (int a = 1; a < 3; a++)
        if (hi[a] - lo[a] > hi[g_axis] - lo[g_axis])
            g_axis = a;
    g_tris = b->tris;
    qsort(b->idx + first, n, sizeof(uint32_t), cmp_centroid);
    int parts = (uint32_t)b->width < n ? b->width : (int)n;
    rt_child ch[RT_WIDTH_MAX];
    for (int c = 0; c < b->width; c++) {
        memset(&ch[c], 0, sizeof ch[c]);
        if (c >= parts) {
            for (int a = 0; a < 3; a++)
                ch[c].lo[a] = INFINITY, ch[c].hi[a] = -INFINITY;
            ch[c].meta = RT_META_EMPTY;
            continue;
        }
        uint32_t s = first + (uint32_t)((uint64_t)n * (uint32_t)c / (uint32_t)parts);
        uint32_t e = first + (uint32_t)((uint64_t)n * (uint32_t)(c + 1) / (uint32_t)parts);
        for (int a = 0; a < 3; a++)
            ch[c].lo[a] = INFINITY, ch[c].hi[a] = -INFINITY;
        for (uint32_t i = s; i < e; i++) {
            float l[3], h[3];
            tri_bounds(&b->tris[b->idx[i]], l, h);
            for (int a = 0; a < 3; a++)
                ch[c].lo[a] = fminf(ch[c].lo[a], l[a]), ch[c].hi[a] = fmaxf(ch[c].hi[a], h[a]);
        }
        if (e - s <= (uint32_t)b->leaf_size) {
            ch[c].ref = s;   /* leaf order = idx order */
            ch[c].meta = e - s;
        } else {
            ch[c].ref = syn_node(b, s, e - s);
            ch[c].meta = 0;
        }
    }
    for (int c = 0; c < b->width; c++)
        memcpy(b->nodes + (size_t)me * nb + (size_t)c * RT_SLOT_BYTES, &ch[c], sizeof ch[c]);
    return me;
}

/* Wald's precomputed projection (Wald 2004, sec. 7.1) of triangle A, B, C. */
static void wald_precompute(const syn_tri *t, uint32_t prim, rt_tri48 *o)
{
    const float *A = t->v[0], *B = t->v[1], *C = t->v[2];
    float c[3], bb[3], N[3];
    for (int a = 0; a < 3; a++)
        c[a] = B[a] - A[a], bb[a] = C[a] - A[a];
    N[0] = bb[1] * c[2] - bb[2] * c[1];
    N[1] = bb[2] * c[0] - bb[0] * c[2];
    N[2] = bb[0] * c[1] - bb[1] * c[0];
    int k = 0;
    for (int a = 1; a < 3; a++)
        if (fabsf(N[a]) > fabsf(N[k]))
            k = a;
    int u = (k + 1) % 3, v = (k + 2) % 3;
    memset(o, 0, sizeof *o);
    o->k = (uint32_t)k;
    o->prim = prim;
    float den = bb[u] * c[v] - bb[v] * c[u];
    if (N[k] == 0 || den == 0) {
        o->flags = 1;
        return;
    }
    o->n_u = N[u] / N[k];
    o->n_v = N[v] / N[k];
    o->n_d = (N[0] * A[0] + N[1] * A[1] + N[2] * A[2]) / N[k];
    float r = 1.0f / den;
    o->b_nu = bb[u] * r;
    o->b_nv = -bb[v] * r;
    o->b_d = (bb[v] * A[u] - bb[u] * A[v]) * r;
    o->c_nu = c[v] * r;
    o->c_nv = -c[u] * r;
    o->c_d = (c[u] * A[v] - c[v] * A[u]) * r;
}

static void syn_image(rt_bvh_image *img, int width, int leaf_size, uint32_t ntris, uint64_t seed)
{
    rt_rng g;
    rt_rng_seed(&g, seed, 3);
    syn_tri *tris = malloc(ntris * sizeof *tris);
    for (uint32_t i = 0; i < ntris; i++) {
        float cx = rt_rng_float(&g) * 10, cy = rt_rng_float(&g) * 10, cz = rt_rng_float(&g) * 10;
        for (int v = 0; v < 3; v++) {
            tris[i].v[v][0] = cx + rt_rng_float(&g) - 0.5f;
            tris[i].v[v][1] = cy + rt_rng_float(&g) - 0.5f;
            tris[i].v[v][2] = cz + rt_rng_float(&g) - 0.5f;
        }
    }
    syn_builder b = {tris, malloc(ntris * sizeof(uint32_t)), NULL, 0, 0, width, leaf_size};
    for (uint32_t i = 0; i < ntris; i++)
        b.idx[i] = i;
    syn_node(&b, 0, ntris);
    memset(img, 0, sizeof *img);
    img->width = width;
    img->node_bytes = rt_node_bytes(width);
    img->nnodes = b.nnodes;
    img->ntris = ntris;
    img->node_base = 0;
    img->tri_base = ((uint64_t)b.nnodes * img->node_bytes + 4095) / 4096 * 4096;
    img->size = img->tri_base + (uint64_t)ntris * RT_TRI_BYTES;
    img->bytes = calloc(1, img->size);
    memcpy(img->bytes, b.nodes, (size_t)b.nnodes * img->node_bytes);
    for (uint32_t i = 0; i < ntris; i++) {
        rt_tri48 t;
        wald_precompute(&tris[b.idx[i]], b.idx[i], &t);
        memcpy(img->bytes + img->tri_base + (uint64_t)i * RT_TRI_BYTES, &t, sizeof t);
    }
    uint64_t h = RT_TLOG_FNV_OFFSET;
    h = rt_tlog_fnv(h, img->bytes, (size_t)img->size);
    img->hash = h ^ (uint64_t)width;
    free(b.idx);
    free(b.nodes);
    free(tris);
}

/* ---------- an independent traversal (traverse.h's algorithm) ---------- */


static void emit(rt_trv_event_fn fn, void *u, int kind, uint32_t a, uint32_t b, float t)
{
    rt_trv_event e;
    memset(&e, 0, sizeof e);
    e.kind = (uint8_t)kind;
    e.a = a;
    e.b = b;
    e.t = t;
    fn(u, &e);
}

/* Returns false on stack overflow (events stop before the overflowing push). */
static bool syn_trace(const rt_bvh_image *img, int depth, bool cull, const rt_ray *ray, rt_hit *hit,
                      rt_trv_event_fn fn, void *u)
{
    const float org[3] = {ray->org.x, ray->org.y, ray->org.z}, dir[3] = {ray->dir.x, ray->dir.y, ray->dir.z};
    rt_ray_prep p;
    rt_ray_prepare(org, dir, &p);
    struct { uint32_t ref, cnt; float t; } st[64];
    int sp = 0;
    float closest = ray->tmax;
    uint32_t best = RT_NO_HIT;
    bool leaf = false;
    uint32_t ref = 0, cnt = 0;
    for (;;) {
        bool do_pop = true;
        if (!leaf) {
            emit(fn, u, RT_EV_VISIT, ref, 0, 0);
            const uint8_t *node = rt_bvh_node_ptr(img, ref);
            int ord[RT_WIDTH_MAX], k = 0;
            float tn[RT_WIDTH_MAX];
            rt_child ch[RT_WIDTH_MAX];
            for (int s = 0; s < img->width; s++) {
                rt_node_child(node, s, &ch[s]);
                if (rt_child_empty(&ch[s]) || !rt_slab_test(&p, ch[s].lo, ch[s].hi, ray->tmin, closest, &tn[s]))
                    continue;
                int j = k++;   /* insertion by (tnear, slot) */
                while (j > 0 && tn[s] < tn[ord[j - 1]]) {
                    ord[j] = ord[j - 1];
                    j--;
                }
                ord[j] = s;
            }
            if (k > 0) {
                for (int j = k - 1; j >= 1; j--) {
                    if (sp == depth) {
                        hit->prim = best;
                        hit->t = closest;
                        return false;
                    }
                    st[sp].ref = ch[ord[j]].ref;
                    st[sp].cnt = rt_child_count(&ch[ord[j]]);
                    st[sp].t = tn[ord[j]];
                    emit(fn, u, RT_EV_PUSH, st[sp].ref, st[sp].cnt, st[sp].t);
                    sp++;
                }
                leaf = rt_child_is_leaf(&ch[ord[0]]);
                ref = ch[ord[0]].ref;
                cnt = rt_child_count(&ch[ord[0]]);
                do_pop = false;
            }
        } else {
            emit(fn, u, RT_EV_LEAF, ref, cnt, 0);
            for (uint32_t i = 0; i < cnt; i++) {
                rt_tri48 t;
                rt_tri_decode(rt_bvh_tri_ptr(img, ref + i), &t);
                float th, uu, vv;
                bool h = rt_wald_test(&t, org, dir, ray->tmin, closest, &th, &uu, &vv);
                if (h)
                    closest = th, best = ref + i;
                emit(fn, u, RT_EV_TRI, ref + i, h, closest);
            }
        }
        while (do_pop) {
            if (sp == 0) {
                uint32_t prim = RT_NO_HIT;
                if (best != RT_NO_HIT) {
                    rt_tri48 t;
                    rt_tri_decode(rt_bvh_tri_ptr(img, best), &t);
                    prim = t.prim;
                }
                emit(fn, u, RT_EV_DONE, prim, 0, closest);
                hit->prim = prim;
                hit->t = closest;
                return true;
            }
            sp--;
            if (cull && st[sp].t > closest) {
                emit(fn, u, RT_EV_CULL, st[sp].ref, st[sp].cnt, st[sp].t);
                continue;
            }
            emit(fn, u, RT_EV_POP, st[sp].ref, st[sp].cnt, st[sp].t);
            leaf = st[sp].cnt != 0;
            ref = st[sp].ref;
            cnt = st[sp].cnt;
            break;
        }
    }
}

static rt_ray syn_ray(rt_rng *g, uint32_t i)
{
    rt_ray r;
    memset(&r, 0, sizeof r);
    /* rays from a corner region into the cloud, plus some odd ones */
    r.org.x = -2 + rt_rng_float(g), r.org.y = -2 + rt_rng_float(g) * 14, r.org.z = -2 + rt_rng_float(g) * 14;
    r.dir.x = 1, r.dir.y = rt_rng_float(g) - 0.5f, r.dir.z = rt_rng_float(g) - 0.5f;
    if (i % 17 == 3)
        r.dir.y = 0, r.dir.z = 0;   /* axis-parallel: infinite inverse directions */
    r.tmin = i % 5 == 1 ? 0.25f : 0.0f;
    r.tmax = i % 7 == 2 ? 6.0f : RT_RAY_TMAX;
    r.pixel = i % 11 == 4 ? 100000u + i : i / 2;
    r.bounce = (uint8_t)(i % 13 == 0 ? 9 : i % 3);
    return r;
}

typedef struct traced {
    rt_ray *rays;
    rt_hit *hits;
    bool *ok;
    tbt_ev_list *ev;
    uint32_t n;
} traced;

static void trace_all(const rt_bvh_image *img, int depth, bool cull, uint32_t n, uint64_t seed, traced *t)
{
    rt_rng g;
    rt_rng_seed(&g, seed, 9);
    t->n = n;
    t->rays = calloc(n, sizeof *t->rays);
    t->hits = calloc(n, sizeof *t->hits);
    t->ok = calloc(n, sizeof *t->ok);
    t->ev = calloc(n, sizeof *t->ev);
    for (uint32_t i = 0; i < n; i++) {
        t->rays[i] = syn_ray(&g, i);
        t->ok[i] = syn_trace(img, depth, cull, &t->rays[i], &t->hits[i], tbt_ev_add, &t->ev[i]);
    }
}

static void traced_free(traced *t)
{
    for (uint32_t i = 0; i < t->n; i++)
        free(t->ev[i].e);
    free(t->rays);
    free(t->hits);
    free(t->ok);
    free(t->ev);
}

static uint32_t g_block_bytes = RT_TLOG_BLOCK_DEFAULT;
static bool write_log(const char *path, const rt_bvh_image *img, int depth, bool cull, const traced *t, char *err,
                      size_t errlen, rt_tlog_totals *tot)
{
    rt_trv_params p = {depth, cull};
    rt_tlog_info info = {0x1234, 0, 0, RT_TLOG_RAYS_OTHER, 4, 1, false, {{0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, 0}, NULL};
    rt_tlog_writer *w = rt_tlog_writer_open(path, img, &p, &info, err, errlen);
    if (!w)
        return false;
    rt_tlog_writer_set_block_bytes(w, g_block_bytes);
    for (uint32_t i = 0; i < t->n; i++) {
        rt_tlog_ray_begin(w, &t->rays[i]);
        for (size_t k = 0; k < t->ev[i].n; k++)
            rt_tlog_event(w, &t->ev[i].e[k]);
        if (!rt_tlog_ray_end(w, !t->ok[i], err, errlen)) {
            rt_tlog_writer_abort(w);
            return false;
        }
    }
    return rt_tlog_writer_close(w, tot, err, errlen);
}

static bool ev_eq(const rt_trv_event *a, const rt_trv_event *b)
{
    return a->kind == b->kind && a->a == b->a && a->b == b->b && memcmp(&a->t, &b->t, 4) == 0;
}

/* Reads the log back and compares everything with t; returns the number of
 * differences (0 = identical), or -1 when the reader rejected it. */
static long read_compare(const char *path, const rt_bvh_image *img, const traced *t, char *err, size_t errlen)
{
    rt_tlog_reader *r = rt_tlog_reader_open(path, img, NULL, NULL, err, errlen);
    if (!r)
        return -1;
    long diffs = 0;
    tbt_ev_list got = {0};
    rt_tlog_ray ray;
    uint32_t i = 0;
    int s;
    while ((s = rt_tlog_read_ray(r, &ray, tbt_ev_add, &got, err, errlen)) == 1) {
        if (i >= t->n) {
            diffs++;
            continue;
        }
        const rt_ray *w = &t->rays[i];
        if (ray.id != i || ray.ray.pixel != w->pixel || ray.ray.bounce != w->bounce ||
            memcmp(&ray.ray.org, &w->org, 12) || memcmp(&ray.ray.dir, &w->dir, 12) ||
            memcmp(&ray.ray.tmin, &w->tmin, 4) || memcmp(&ray.ray.tmax, &w->tmax, 4) || ray.overflowed != !t->ok[i])
            diffs++;
        if (t->ok[i] && (ray.hit.prim != t->hits[i].prim || memcmp(&ray.hit.t, &t->hits[i].t, 4)))
            diffs++;
        if (got.n != t->ev[i].n)
            diffs++;
        for (size_t k = 0; k < got.n && k < t->ev[i].n; k++)
            diffs += !ev_eq(&got.e[k], &t->ev[i].e[k]);
        got.n = 0;
        i++;
    }
    free(got.e);
    rt_tlog_reader_close(r);
    if (s < 0)
        return -1;
    return diffs + (i != t->n);
}

static void spit(const char *path, const unsigned char *b, size_t len)
{
    FILE *f = fopen(path, "wb");
    fwrite(b, 1, len, f);
    fclose(f);
}

static char g_tmp[TB_PATH_MAX];
static const char *tmp_path(const char *name)
{
    const char *d = getenv("RTSIM_TMP");
    tb_pathf(g_tmp, sizeof g_tmp, "%s/%s", d && *d ? d : "/tmp", name);
    return g_tmp;
}

/* ---------- cases ---------- */

static void test_round_trip(void)
{
    static const int widths[3] = {2, 4, 8};
    for (int wi = 0; wi < 3; wi++) {
        for (int cull = 0; cull < 2; cull++) {
            char name[80];
            snprintf(name, sizeof name, "tracelog_synthetic_round_trip_width%d_%s", widths[wi], cull ? "cull" : "nocull");
            tb_begin(name);
            rt_bvh_image img;
            syn_image(&img, widths[wi], 1 + wi, 600, 7 + (uint64_t)wi);
            traced t;
            /* enough rays for several blocks */
            uint32_t n = tb_is_sanitized() ? 1500 : 6000;
            trace_all(&img, 64, cull, n, 11 + (uint64_t)wi, &t);
            char path[TB_PATH_MAX], err[TB_ERR_MAX];
            tb_pathf(path, sizeof path, "%s", tmp_path("syn_rt.tlog"));
            rt_tlog_totals tot;
            g_block_bytes = 16384;   /* several blocks */
            bool ok = write_log(path, &img, 64, cull, &t, err, sizeof err, &tot);
            g_block_bytes = RT_TLOG_BLOCK_DEFAULT;
            if (TB_CHECK(ok, "write: %s", err)) {
                uint64_t evs = 0, visits = 0;
                for (uint32_t i = 0; i < n; i++) {
                    evs += t.ev[i].n;
                    for (size_t k = 0; k < t.ev[i].n; k++)
                        visits += t.ev[i].e[k].kind == RT_EV_VISIT;
                }
                TB_EQ_INT(tot.rays, n);
                TB_EQ_INT(tot.events, evs);
                TB_EQ_INT(tot.visits, visits);
                TB_CHECK(tot.blocks >= 4, "blocks %llu", (unsigned long long)tot.blocks);
                long d = read_compare(path, &img, &t, err, sizeof err);
                TB_CHECK(d == 0, "read back: %ld differences (%s)", d, d < 0 ? err : "");
                rt_tlog_header h;
                rt_tlog_totals rt;
                TB_CHECK(rt_tlog_verify(path, &img, NULL, &h, &rt, err, sizeof err), "verify: %s", err);
                TB_EQ_INT(h.ray_count, n);
                TB_EQ_INT(h.bvh_width, widths[wi]);
                TB_EQ_INT(h.distance_cull, cull);
                TB_EQ_INT(h.info.mesh_hash, 0x1234);
                TB_CHECK(rt.stream_hash == tot.stream_hash && rt.file_bytes == tot.file_bytes, "totals differ");
            }
            remove(path);
            traced_free(&t);
            free(img.bytes);
            tb_end();
        }
    }

    tb_begin("tracelog_synthetic_stack_overflow_rays");
    rt_bvh_image img;
    syn_image(&img, 4, 1, 400, 5);
    traced t;
    trace_all(&img, 2, true, 400, 3, &t);
    uint32_t over = 0;
    for (uint32_t i = 0; i < t.n; i++)
        over += !t.ok[i];
    TB_CHECK(over > 10 && over < t.n, "%u of %u rays overflow a 2-entry stack", over, t.n);
    char err[TB_ERR_MAX];
    rt_tlog_totals tot;
    const char *path = tmp_path("syn_over.tlog");
    if (TB_CHECK(write_log(path, &img, 2, true, &t, err, sizeof err, &tot), "write: %s", err)) {
        TB_EQ_INT(tot.overflows, over);
        long d = read_compare(path, &img, &t, err, sizeof err);
        TB_CHECK(d == 0, "read back: %ld differences (%s)", d, d < 0 ? err : "");
    }
    remove(path);
    traced_free(&t);
    free(img.bytes);
    tb_end();
}

static void test_empty_log(void)
{
    tb_begin("tracelog_zero_rays");
    rt_bvh_image img;
    syn_image(&img, 2, 2, 50, 1);
    traced t = {0};
    char err[TB_ERR_MAX];
    rt_tlog_totals tot, rt;
    const char *path = tmp_path("syn_empty.tlog");
    TB_CHECK(write_log(path, &img, 64, false, &t, err, sizeof err, &tot), "write: %s", err);
    TB_CHECK(rt_tlog_verify(path, &img, NULL, NULL, &rt, err, sizeof err), "verify: %s", err);
    TB_EQ_INT(rt.rays, 0);
    TB_EQ_INT(tot.file_bytes, RT_TLOG_HEADER_BYTES + RT_TLOG_END_BYTES);
    remove(path);
    free(img.bytes);
    tb_end();
}

static void test_corruption(void)
{
    rt_bvh_image img;
    syn_image(&img, 4, 2, 120, 21);
    traced t;
    trace_all(&img, 64, true, 40, 8, &t);
    char err[TB_ERR_MAX];
    rt_tlog_totals tot;
    char path[TB_PATH_MAX], bad[TB_PATH_MAX];
    tb_pathf(path, sizeof path, "%s", tmp_path("syn_small.tlog"));
    tb_pathf(bad, sizeof bad, "%s", tmp_path("syn_bad.tlog"));
    bool ok = write_log(path, &img, 64, true, &t, err, sizeof err, &tot);
    size_t len = 0;
    unsigned char *orig = ok ? (unsigned char *)tb_read_file(path, &len) : NULL;

    tb_begin("tracelog_every_byte_flip_rejected");
    if (TB_CHECK(orig != NULL, "write: %s", err)) {
        unsigned char *b = malloc(len);
        size_t accepted = 0, unnamed = 0;
        for (size_t i = 0; i < len; i++) {
            for (int pattern = 0; pattern < 2; pattern++) {
                memcpy(b, orig, len);
                b[i] ^= pattern ? 0xFF : (unsigned char)(1u << (i % 8));
                spit(bad, b, len);
                if (read_compare(bad, &img, &t, err, sizeof err) >= 0)
                    accepted++;
                else if (!strstr(err, bad) || !strstr(err, "byte "))
                    unnamed++;
            }
        }
        TB_CHECK(accepted == 0, "%zu of %zu flipped logs accepted", accepted, 2 * len);
        TB_CHECK(unnamed == 0, "%zu messages without file name and byte offset (last: %s)", unnamed, err);
        free(b);
    }
    tb_end();

    tb_begin("tracelog_every_truncation_rejected");
    if (TB_CHECK(orig != NULL, "write failed")) {
        size_t accepted = 0;
        for (size_t i = 0; i < len; i++) {
            spit(bad, orig, i);
            if (read_compare(bad, &img, &t, err, sizeof err) >= 0)
                accepted++;
        }
        TB_CHECK(accepted == 0, "%zu truncations accepted", accepted);
        /* and a message for a cut inside the end record */
        spit(bad, orig, len - 3);
        TB_CHECK(read_compare(bad, &img, &t, err, sizeof err) < 0 && strstr(err, "truncated end record"), "got: %s",
                 err);
        /* trailing garbage */
        unsigned char *b = malloc(len + 1);
        memcpy(b, orig, len);
        b[len] = 0;
        spit(bad, b, len + 1);
        TB_CHECK(read_compare(bad, &img, &t, err, sizeof err) < 0 && strstr(err, "trailing"), "got: %s", err);
        free(b);
    }
    tb_end();

    tb_begin("tracelog_garbage_and_foreign_files_rejected");
    {
        rt_rng g;
        rt_rng_seed(&g, 99, 1);
        unsigned char junk[4096];
        size_t accepted = 0;
        for (int round = 0; round < 200; round++) {
            size_t n = rt_rng_below(&g, sizeof junk);
            for (size_t i = 0; i < n; i++)
                junk[i] = (unsigned char)rt_rng_u32(&g);
            if (round % 2 && n >= RT_TLOG_HEADER_BYTES && orig)
                memcpy(junk, orig, RT_TLOG_HEADER_BYTES);   /* a valid header followed by junk */
            spit(bad, junk, n);
            if (read_compare(bad, &img, &t, err, sizeof err) >= 0)
                accepted++;
        }
        TB_CHECK(accepted == 0, "%zu junk files accepted", accepted);
        spit(bad, (const unsigned char *)"hello", 5);
        TB_CHECK(read_compare(bad, &img, &t, err, sizeof err) < 0 && strstr(err, "not a trace log"), "got: %s", err);
        TB_CHECK(read_compare(tmp_path("no-such-file.tlog"), &img, &t, err, sizeof err) < 0 &&
                     strstr(err, "cannot open"),
                 "got: %s", err);
    }
    tb_end();

    tb_begin("tracelog_version_and_header_fields_checked");
    if (TB_CHECK(orig != NULL, "write failed")) {
        unsigned char *b = malloc(len);
        struct { size_t off; uint32_t val; const char *want; } cases[] = {
            {8, 2, "version 2"}, {12, 64, "header size"}, {16, 9, "width 9"}, {20, 0, "stack depth 0"},
            {24, 6, "unknown flags"}, {36, 7, "ray kind 7"}, {76, 1, "reserved"}, {128, 1, "reserved"},
            {100, 1, "camera fields set without the camera flag"}};
        for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
            memcpy(b, orig, len);
            rt_tlog_put_u32(b + cases[c].off, cases[c].val);
            rt_tlog_put_u32(b + 132, (uint32_t)crc32(0L, b, 132));   /* a consistent but wrong header */
            spit(bad, b, len);
            TB_CHECK(read_compare(bad, &img, &t, err, sizeof err) < 0 && strstr(err, cases[c].want),
                     "field at %zu: got: %s", cases[c].off, err);
        }
        /* header ray count disagreeing with the end record */
        memcpy(b, orig, len);
        rt_tlog_put_u64(b + 56, 41);
        rt_tlog_put_u32(b + 132, (uint32_t)crc32(0L, b, 132));
        spit(bad, b, len);
        TB_CHECK(read_compare(bad, &img, &t, err, sizeof err) < 0 && strstr(err, "header says 41 rays"), "got: %s",
                 err);
        free(b);
    }
    tb_end();

    tb_begin("tracelog_mismatched_image_rejected");
    if (TB_CHECK(orig != NULL, "write failed")) {
        rt_bvh_image other;
        syn_image(&other, 4, 2, 120, 22);
        TB_CHECK(read_compare(path, &other, &t, err, sizeof err) < 0 && strstr(err, "hash") && strstr(err, "byte 40"),
                 "other image: %s", err);
        /* a forged image: same hash and counts, one box moved */
        rt_bvh_image forged = img;
        forged.bytes = malloc(img.size);
        memcpy(forged.bytes, img.bytes, img.size);
        rt_child ch;
        memcpy(&ch, forged.bytes, sizeof ch);
        for (int a = 0; a < 3; a++)
            ch.lo[a] += 100.0f, ch.hi[a] += 100.0f;
        memcpy(forged.bytes, &ch, sizeof ch);
        TB_CHECK(read_compare(path, &forged, &t, err, sizeof err) < 0 && strstr(err, "does not match"),
                 "forged image: %s", err);
        free(forged.bytes);
        free(other.bytes);
    }
    tb_end();

    tb_begin("tracelog_repacked_record_mutations_never_misread");
    if (TB_CHECK(orig != NULL, "write failed")) {
        /* the single block of this small log: mutate its decompressed bytes,
         * recompress, fix the CRCs: the reader must reject or read the same */
        TB_EQ_INT(tot.blocks, 1);
        const unsigned char *bh = orig + RT_TLOG_HEADER_BYTES;
        uint32_t raw_len = rt_tlog_get_u32(bh + 16), comp_len = rt_tlog_get_u32(bh + 20);
        unsigned char *raw = malloc(raw_len);
        uLongf dl = raw_len;
        TB_CHECK(uncompress(raw, &dl, bh + 32, comp_len) == Z_OK, "inflate");
        size_t tail = len - RT_TLOG_HEADER_BYTES - 32 - comp_len;
        unsigned char *mut = malloc(raw_len + 16), *file = malloc(len + raw_len + 1024);
        rt_rng g;
        rt_rng_seed(&g, 5, 5);
        size_t misread = 0, rejected = 0, rounds = tb_is_sanitized() ? 600 : 3000;
        for (size_t round = 0; round < rounds; round++) {
            memcpy(mut, raw, raw_len);
            uint32_t mlen = raw_len;
            int kind = (int)(round % 3);
            uint32_t at = rt_rng_below(&g, raw_len);
            if (kind == 0)
                mut[at] ^= (unsigned char)(1u << rt_rng_below(&g, 8));
            else if (kind == 1)
                mut[at] = (unsigned char)rt_rng_u32(&g);
            else
                mlen = at;   /* cut the records short */
            if (mlen == 0)
                continue;
            uLongf cl = compressBound(mlen);
            memcpy(file, orig, RT_TLOG_HEADER_BYTES + 32);
            compress2(file + RT_TLOG_HEADER_BYTES + 32, &cl, mut, mlen, 6);
            unsigned char *h = file + RT_TLOG_HEADER_BYTES;
            rt_tlog_put_u32(h + 16, mlen);
            rt_tlog_put_u32(h + 20, (uint32_t)cl);
            rt_tlog_put_u32(h + 24, (uint32_t)crc32(0L, h + 32, (uInt)cl));
            rt_tlog_put_u32(h + 28, (uint32_t)crc32(0L, h, 28));
            memcpy(h + 32 + cl, orig + len - tail, tail);
            spit(bad, file, RT_TLOG_HEADER_BYTES + 32 + cl + tail);
            long d = read_compare(bad, &img, &t, err, sizeof err);
            if (d < 0)
                rejected++;
            else if (d > 0)
                misread++;
        }
        TB_CHECK(misread == 0, "%zu mutated logs read back differently without an error", misread);
        TB_CHECK(rejected > rounds / 2, "only %zu of %zu mutations rejected", rejected, rounds);
        free(raw);
        free(mut);
        free(file);
    }
    tb_end();

    free(orig);
    remove(path);
    remove(bad);
    traced_free(&t);
    free(img.bytes);
}

static void test_writer_rejects_non_traversals(void)
{
    tb_begin("tracelog_writer_rejects_inconsistent_events");
    rt_bvh_image img;
    syn_image(&img, 4, 2, 200, 31);
    traced t;
    trace_all(&img, 64, true, 30, 4, &t);
    /* a ray with at least one push */
    uint32_t ri = 0;
    for (uint32_t i = 0; i < t.n; i++)
        for (size_t k = 0; k < t.ev[i].n; k++)
            if (t.ev[i].e[k].kind == RT_EV_PUSH && t.ok[i] && !ri)
                ri = i + 1;
    if (TB_CHECK(ri > 0, "no ray with a push")) {
        tbt_ev_list *l = &t.ev[ri - 1];
        const char *path = tmp_path("syn_reject.tlog");
        for (int mode = 0; mode < 5; mode++) {
            tbt_ev_list m = {malloc(l->n * sizeof *l->e), l->n, l->n};
            memcpy(m.e, l->e, l->n * sizeof *l->e);
            size_t p = 0;
            while (m.e[p].kind != RT_EV_PUSH)
                p++;
            if (mode == 0)
                memmove(m.e + p, m.e + p + 1, (--m.n - p) * sizeof *m.e);   /* a PUSH dropped */
            else if (mode == 1)
                m.e[0].a = 1;                                              /* wrong first node */
            else if (mode == 2)
                m.n--;                                                     /* no DONE */
            else if (mode == 3)
                m.e[m.n - 1].a ^= 1;                                       /* wrong primitive */
            else
                m.e[p].kind = RT_EV_POP;                                   /* a POP where a PUSH belongs */
            rt_trv_params prm = {64, true};
            rt_tlog_info info;
            memset(&info, 0, sizeof info);
            char err[TB_ERR_MAX];
            rt_tlog_writer *w = rt_tlog_writer_open(path, &img, &prm, &info, err, sizeof err);
            rt_tlog_ray_begin(w, &t.rays[ri - 1]);
            for (size_t k = 0; k < m.n; k++)
                rt_tlog_event(w, &m.e[k]);
            bool ok = rt_tlog_ray_end(w, false, err, sizeof err);
            TB_CHECK(!ok && strstr(err, "ray 0, event"), "mode %d: %s", mode, ok ? "accepted" : err);
            TB_CHECK(!rt_tlog_writer_close(w, NULL, err, sizeof err), "close after a failure must fail");
            FILE *f = fopen(path, "rb");
            TB_CHECK(f == NULL, "mode %d: a log was left under the final name", mode);
            if (f)
                fclose(f);
            free(m.e);
        }
    }
    traced_free(&t);
    free(img.bytes);
    tb_end();
}

static void test_lehmer(void)
{
    tb_begin("tracelog_lehmer_code_all_orders");
    int bad = 0;
    for (int k = 1; k <= 8; k++) {
        uint32_t f = rt_tlog_factorial(k);
        int vals[8];
        for (int i = 0; i < k; i++)
            vals[i] = 2 * i + 1;
        for (uint32_t idx = 0; idx < f; idx++) {
            int ord[8];
            if (!rt_tlog_lehmer_decode(idx, vals, k, ord) || rt_tlog_lehmer_encode(ord, k) != idx)
                bad++;
        }
        int ord[8];
        bad += rt_tlog_lehmer_decode(f, vals, k, ord);
    }
    TB_EQ_INT(bad, 0);
    tb_end();
}

int main(void)
{
    test_lehmer();
    test_round_trip();
    test_empty_log();
    test_corruption();
    test_writer_rejects_non_traversals();
    return tb_finish();
}
