/* trace_log_write.c — the trace log writer (contract in trace_log.h, byte
 * layout in trace_log_format.h). Each ray's events are buffered, walked
 * against the image's nodes to recover the traversal's decisions (which
 * children were hit, in which order; cull and closest-hit bits), and those
 * decisions are appended to the current block; full blocks are deflated. The
 * walk doubles as a structural check of the event stream: events that are not
 * a traversal of this image are an error, never a silently wrong log. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

#include "tracer/log/trace_log.h"
#include "tracer/trace/bounce.h"
#include "tracer/trace/camera.h"
#include "tracer/log/trace_log_format.h"

typedef struct tlog_buf {
    uint8_t *p;
    size_t len, cap;
    bool oom;
} tlog_buf;

static void buf_reserve(tlog_buf *b, size_t extra)
{
    if (b->oom || b->len + extra <= b->cap)
        return;
    size_t cap = b->cap ? b->cap : 4096;
    while (cap < b->len + extra)
        cap *= 2;
    uint8_t *p = realloc(b->p, cap);
    if (!p) {
        b->oom = true;
        return;
    }
    b->p = p;
    b->cap = cap;
}
static void buf_put(tlog_buf *b, const void *data, size_t n)
{
    if (n == 0)
        return;
    buf_reserve(b, n);
    if (b->oom)
        return;
    memcpy(b->p + b->len, data, n);
    b->len += n;
}
static void buf_u8(tlog_buf *b, uint8_t v) { buf_put(b, &v, 1); }
static void buf_u32(tlog_buf *b, uint32_t v)
{
    uint8_t x[4];
    rt_tlog_put_u32(x, v);
    buf_put(b, x, 4);
}
static void buf_varint(tlog_buf *b, uint64_t v)
{
    uint8_t x[10];
    int n = 0;
    do {
        x[n] = (uint8_t)(v & 0x7f);
        v >>= 7;
        if (v)
            x[n] |= 0x80;
        n++;
    } while (v);
    buf_put(b, x, (size_t)n);
}

typedef struct stack_entry {
    uint32_t ref, count;
} stack_entry;

struct rt_tlog_writer {
    FILE *f;
    char *path, *tmp;
    const rt_bvh_image *img;
    rt_trv_params trv;
    rt_tlog_info info;
    /* the current ray */
    rt_ray ray;
    rt_trv_event *ev;
    size_t nev, evcap;
    bool ev_oom, in_ray, broken;
    /* per-ray scratch */
    tlog_buf codes, bits;
    size_t nbits;
    stack_entry *stack;
    /* the current block */
    tlog_buf raw, comp;
    uint32_t block_rays;
    uint64_t block_first;
    uint32_t prev_pixel, prev_bits[6];
    /* ray derivation */
    bool has_cam;
    rt_camera cam;
    rt_ray prev_ray;
    rt_hit prev_hit, cur_hit;
    bool prev_complete;     /* the previous ray ended with DONE: its hit is known */
    uint32_t block_bytes;
    rt_tlog_totals tot;
    uint64_t offset;   /* bytes written so far */
};

static void header_bytes(const rt_tlog_writer *w, uint8_t h[RT_TLOG_HEADER_BYTES])
{
    memset(h, 0, RT_TLOG_HEADER_BYTES);
    memcpy(h, RT_TLOG_MAGIC, 8);
    rt_tlog_put_u32(h + 8, RT_TLOG_VERSION);
    rt_tlog_put_u32(h + 12, RT_TLOG_HEADER_BYTES);
    rt_tlog_put_u32(h + 16, (uint32_t)w->img->width);
    rt_tlog_put_u32(h + 20, (uint32_t)w->trv.stack_depth);
    rt_tlog_put_u32(h + 24, (w->trv.distance_cull ? RT_TLOG_FLAG_DISTANCE_CULL : 0u) |
                                (w->has_cam ? RT_TLOG_FLAG_CAMERA : 0u));
    rt_tlog_put_u32(h + 28, w->img->nnodes);
    rt_tlog_put_u32(h + 32, w->img->ntris);
    rt_tlog_put_u32(h + 36, w->info.ray_kind);
    rt_tlog_put_u64(h + 40, w->img->hash);
    rt_tlog_put_u64(h + 48, w->info.mesh_hash);
    rt_tlog_put_u64(h + 56, w->tot.rays);
    rt_tlog_put_u32(h + 64, w->info.res_width);
    rt_tlog_put_u32(h + 68, w->info.res_height);
    rt_tlog_put_u32(h + 72, w->info.max_bounces);
    rt_tlog_put_u64(h + 80, w->info.seed);
    if (w->has_cam) {
        const rt_view *v = &w->info.view;
        const float f[10] = {v->eye.x, v->eye.y, v->eye.z, v->at.x, v->at.y, v->at.z, v->up.x, v->up.y, v->up.z, v->fov_deg};
        for (int i = 0; i < 10; i++)
            rt_tlog_put_u32(h + 88 + 4 * i, rt_tlog_float_bits(f[i]));
    }
    rt_tlog_put_u32(h + 132, (uint32_t)crc32(0L, h, 132));
}

static void free_writer(rt_tlog_writer *w)
{
    free(w->path);
    free(w->tmp);
    free(w->ev);
    free(w->codes.p);
    free(w->bits.p);
    free(w->stack);
    free(w->raw.p);
    free(w->comp.p);
    free(w);
}

rt_tlog_writer *rt_tlog_writer_open(const char *path, const rt_bvh_image *img, const rt_trv_params *trv,
                                    const rt_tlog_info *info, char *err, size_t errlen)
{
    if (!img || img->width < RT_WIDTH_MIN || img->width > RT_WIDTH_MAX || img->nnodes == 0) {
        snprintf(err, errlen, "%s: trace log needs a built BVH image (width %d..%d)", path, RT_WIDTH_MIN,
                 RT_WIDTH_MAX);
        return NULL;
    }
    if (trv->stack_depth < 1 || trv->stack_depth > 4096) {
        snprintf(err, errlen, "%s: stack depth %d out of range 1..4096", path, trv->stack_depth);
        return NULL;
    }
    if (info->ray_kind > RT_TLOG_RAYS_OTHER) {
        snprintf(err, errlen, "%s: ray kind %u out of range 0..2", path, info->ray_kind);
        return NULL;
    }
    rt_tlog_writer *w = calloc(1, sizeof *w);
    if (!w) {
        snprintf(err, errlen, "%s: out of memory", path);
        return NULL;
    }
    w->img = img;
    w->trv = *trv;
    w->info = *info;
    if (info->has_view) {
        char cerr[300];
        if (!rt_camera_init(&w->cam, &info->view, info->res_width, info->res_height, cerr, sizeof cerr)) {
            snprintf(err, errlen, "%s: camera for ray derivation: %s", path, cerr);
            free_writer(w);
            return NULL;
        }
        w->has_cam = true;
    }
    size_t pl = strlen(path);
    w->path = malloc(pl + 1);
    w->tmp = malloc(pl + 32);
    w->stack = calloc((size_t)trv->stack_depth + 2, sizeof *w->stack);
    if (!w->path || !w->tmp || !w->stack) {
        snprintf(err, errlen, "%s: out of memory", path);
        free_writer(w);
        return NULL;
    }
    memcpy(w->path, path, pl + 1);
    snprintf(w->tmp, pl + 32, "%s.tmp.%ld", path, (long)getpid());
    w->f = fopen(w->tmp, "wb");
    if (!w->f) {
        snprintf(err, errlen, "%s: cannot write (temporary %s)", path, w->tmp);
        free_writer(w);
        return NULL;
    }
    uint8_t h[RT_TLOG_HEADER_BYTES];
    header_bytes(w, h);
    if (fwrite(h, 1, sizeof h, w->f) != sizeof h) {
        snprintf(err, errlen, "%s: write failed", path);
        rt_tlog_writer_abort(w);
        return NULL;
    }
    w->offset = sizeof h;
    w->block_bytes = RT_TLOG_BLOCK_DEFAULT;
    w->tot.stream_hash = RT_TLOG_FNV_OFFSET;
    return w;
}

void rt_tlog_writer_set_block_bytes(rt_tlog_writer *w, uint32_t bytes)
{
    w->block_bytes = bytes < 256 ? 256 : bytes > (16u << 20) ? (16u << 20) : bytes;
}

void rt_tlog_ray_begin(rt_tlog_writer *w, const rt_ray *ray)
{
    w->ray = *ray;
    w->nev = 0;
    w->in_ray = true;
}

void rt_tlog_event(void *user, const rt_trv_event *ev)
{
    rt_tlog_writer *w = user;
    if (w->nev == w->evcap) {
        size_t cap = w->evcap ? 2 * w->evcap : 1024;
        rt_trv_event *p = realloc(w->ev, cap * sizeof *p);
        if (!p) {
            w->ev_oom = true;
            return;
        }
        w->ev = p;
        w->evcap = cap;
    }
    if (!w->ev_oom)
        w->ev[w->nev++] = *ev;
}

static void put_bit(rt_tlog_writer *w, bool bit)
{
    if (w->nbits % 8 == 0)
        buf_u8(&w->bits, 0);
    if (bit && !w->bits.oom)
        w->bits.p[w->nbits / 8] |= (uint8_t)(1u << (w->nbits % 8));
    w->nbits++;
}

/* Slot of node whose child is (ref, count) with the given leafness, or -1. */
static int match_slot(const uint8_t *node, int width, uint32_t ref, uint32_t count, bool leaf)
{
    for (int c = 0; c < width; c++) {
        rt_child ch;
        rt_node_child(node, c, &ch);
        if (rt_child_empty(&ch))
            continue;
        if (rt_child_is_leaf(&ch) == leaf && ch.ref == ref && (!leaf || rt_child_count(&ch) == count))
            return c;
    }
    return -1;
}

static const char *kind_name(unsigned k)
{
    static const char *names[] = {"VISIT", "PUSH", "POP", "CULL", "LEAF", "TRI", "DONE"};
    return k <= RT_EV_DONE ? names[k] : "unknown";
}

#define WALK_FAIL(...)                                                                               \
    do {                                                                                             \
        char why_[200];                                                                              \
        snprintf(why_, sizeof why_, __VA_ARGS__);                                                    \
        snprintf(err, errlen, "%s: ray %llu, event %zu: %s", w->path, (unsigned long long)w->tot.rays, \
                 i, why_);                                                                           \
        return false;                                                                                \
    } while (0)

/* Walks the buffered events of the current ray, recording its decisions into
 * w->codes / w->bits and its counts into *c. */
static bool walk_events(rt_tlog_writer *w, bool overflowed, rt_trv_counts *c, uint64_t *nvisits, bool *hit,
                        char *err, size_t errlen)
{
    const rt_trv_event *e = w->ev;
    const size_t n = w->nev;
    const rt_bvh_image *img = w->img;
    size_t i = 0, sp = 0;
    bool tgt_leaf = false;
    uint32_t tgt_ref = 0, tgt_count = 0, best = RT_NO_HIT;
    memset(c, 0, sizeof *c);
    *nvisits = 0;
    for (;;) {
        if (i == n) {
            if (overflowed)
                return true;
            WALK_FAIL("events end before DONE");
        }
        if (!tgt_leaf) {
            if (e[i].kind != RT_EV_VISIT || e[i].a != tgt_ref)
                WALK_FAIL("expected VISIT of node %u, got %s %u", tgt_ref, kind_name(e[i].kind), e[i].a);
            if (tgt_ref >= img->nnodes)
                WALK_FAIL("node %u out of range (image has %u)", tgt_ref, img->nnodes);
            const uint8_t *node = rt_bvh_node_ptr(img, tgt_ref);
            i++;
            c->visits++;
            size_t j = i;
            while (j < n && e[j].kind == RT_EV_PUSH)
                j++;
            int order[RT_WIDTH_MAX], k = 0;
            uint32_t mask = 0;
            bool has_target = j < n && (e[j].kind == RT_EV_VISIT || e[j].kind == RT_EV_LEAF);
            if (j == n && overflowed) {
                /* the stack overflowed among this visit's pushes: no code, the
                 * reader derives the order from the distances */
                for (size_t p = i; p < j; p++) {
                    if (sp > (size_t)w->trv.stack_depth)
                        WALK_FAIL("PUSH beyond the stack depth %d", w->trv.stack_depth);
                    w->stack[sp].ref = e[p].a;
                    w->stack[sp].count = e[p].b;
                    sp++;
                }
                c->pushes += (uint32_t)(j - i);
                return true;
            }
            if (has_target) {
                int s = match_slot(node, img->width, e[j].a, e[j].b, e[j].kind == RT_EV_LEAF);
                if (s < 0)
                    WALK_FAIL("%s %u/%u is no child of node %u", kind_name(e[j].kind), e[j].a, e[j].b, tgt_ref);
                order[k++] = s;
                mask |= 1u << s;
            } else if (j > i) {
                WALK_FAIL("PUSH without a next node or leaf");
            }
            for (size_t p = j; p > i; p--) {
                const rt_trv_event *pe = &e[p - 1];
                int s = match_slot(node, img->width, pe->a, pe->b, pe->b != 0);
                if (s < 0 || (mask & (1u << s)))
                    WALK_FAIL("PUSH %u/%u is no (other) child of node %u", pe->a, pe->b, tgt_ref);
                order[k++] = s;
                mask |= 1u << s;
            }
            for (size_t p = i; p < j; p++) {
                if (sp >= (size_t)w->trv.stack_depth)
                    WALK_FAIL("PUSH beyond the stack depth %d", w->trv.stack_depth);
                w->stack[sp].ref = e[p].a;
                w->stack[sp].count = e[p].b;
                sp++;
                c->pushes++;
                if (sp > c->max_stack)
                    c->max_stack = (uint32_t)sp;
            }
            buf_u8(&w->codes, (uint8_t)mask);
            if (k >= 2) {
                int ranked[RT_WIDTH_MAX];
                /* rank slots among the hit ones: the order is a permutation of them */
                for (int a = 0; a < k; a++) {
                    ranked[a] = 0;
                    for (int b = 0; b < k; b++)
                        ranked[a] += order[b] < order[a];
                }
                uint32_t idx = rt_tlog_lehmer_encode(ranked, k);
                buf_u8(&w->codes, (uint8_t)idx);
                if (k > 5)
                    buf_u8(&w->codes, (uint8_t)(idx >> 8));
            }
            (*nvisits)++;
            i = j;
            if (has_target) {
                tgt_leaf = e[j].kind == RT_EV_LEAF;
                tgt_ref = e[j].a;
                tgt_count = e[j].b;
                continue;
            }
        } else {
            if (e[i].kind != RT_EV_LEAF || e[i].a != tgt_ref || e[i].b != tgt_count)
                WALK_FAIL("expected LEAF %u/%u, got %s %u/%u", tgt_ref, tgt_count, kind_name(e[i].kind), e[i].a,
                          e[i].b);
            if ((uint64_t)tgt_ref + tgt_count > img->ntris)
                WALK_FAIL("leaf triangles %u+%u out of range (image has %u)", tgt_ref, tgt_count, img->ntris);
            i++;
            c->leaves++;
            for (uint32_t t = 0; t < tgt_count; t++, i++) {
                if (i == n && overflowed)
                    return true;
                if (i == n || e[i].kind != RT_EV_TRI || e[i].a != tgt_ref + t || e[i].b > 1)
                    WALK_FAIL("expected TRI %u of the leaf", tgt_ref + t);
                put_bit(w, e[i].b != 0);
                if (e[i].b)
                    best = e[i].a;
                c->tri_tests++;
            }
        }
        /* the stack pops until a target or DONE */
        for (;;) {
            if (i == n) {
                if (overflowed)
                    return true;
                WALK_FAIL("events end before DONE");
            }
            if (sp == 0) {
                uint32_t prim = RT_NO_HIT;
                if (best != RT_NO_HIT) {
                    rt_tri48 tri;
                    rt_tri_decode(rt_bvh_tri_ptr(img, best), &tri);
                    prim = tri.prim;
                }
                if (e[i].kind != RT_EV_DONE || e[i].a != prim)
                    WALK_FAIL("expected DONE with primitive %u, got %s %u", prim, kind_name(e[i].kind), e[i].a);
                if (i + 1 != n)
                    WALK_FAIL("events after DONE");
                if (overflowed)
                    WALK_FAIL("overflow reported for a completed traversal");
                *hit = prim != RT_NO_HIT;
                w->cur_hit.prim = prim;
                w->cur_hit.t = e[i].t;
                w->cur_hit.u = w->cur_hit.v = 0.0f;
                return true;
            }
            const stack_entry top = w->stack[--sp];
            bool cull = e[i].kind == RT_EV_CULL;
            if ((e[i].kind != RT_EV_POP && !cull) || e[i].a != top.ref || e[i].b != top.count)
                WALK_FAIL("expected POP/CULL of %u/%u, got %s %u/%u", top.ref, top.count, kind_name(e[i].kind),
                          e[i].a, e[i].b);
            if (cull && !w->trv.distance_cull)
                WALK_FAIL("CULL without the distance stack");
            if (w->trv.distance_cull)
                put_bit(w, cull);
            i++;
            if (cull) {
                c->culls++;
                continue;
            }
            c->pops++;
            tgt_leaf = top.count != 0;
            tgt_ref = top.ref;
            tgt_count = top.count;
            break;
        }
    }
}

static bool flush_block(rt_tlog_writer *w, char *err, size_t errlen)
{
    if (w->block_rays == 0)
        return true;
    uLongf bound = compressBound((uLong)w->raw.len);
    w->comp.len = 0;
    buf_reserve(&w->comp, RT_TLOG_BLOCK_HEADER_BYTES + bound);
    if (w->comp.oom || w->raw.oom) {
        snprintf(err, errlen, "%s: out of memory", w->path);
        return false;
    }
    uLongf clen = bound;
    if (compress2(w->comp.p + RT_TLOG_BLOCK_HEADER_BYTES, &clen, w->raw.p, (uLong)w->raw.len, 6) != Z_OK) {
        snprintf(err, errlen, "%s: zlib compression failed", w->path);
        return false;
    }
    uint8_t *h = w->comp.p;
    rt_tlog_put_u32(h, RT_TLOG_BLOCK_MAGIC);
    rt_tlog_put_u32(h + 4, w->block_rays);
    rt_tlog_put_u64(h + 8, w->block_first);
    rt_tlog_put_u32(h + 16, (uint32_t)w->raw.len);
    rt_tlog_put_u32(h + 20, (uint32_t)clen);
    rt_tlog_put_u32(h + 24, (uint32_t)crc32(0L, h + RT_TLOG_BLOCK_HEADER_BYTES, (uInt)clen));
    rt_tlog_put_u32(h + 28, (uint32_t)crc32(0L, h, 28));
    size_t total = RT_TLOG_BLOCK_HEADER_BYTES + clen;
    if (fwrite(h, 1, total, w->f) != total) {
        snprintf(err, errlen, "%s: write failed", w->path);
        return false;
    }
    w->offset += total;
    w->tot.blocks++;
    w->raw.len = 0;
    w->block_rays = 0;
    return true;
}

bool rt_tlog_ray_end(rt_tlog_writer *w, bool overflowed, char *err, size_t errlen)
{
    if (w->broken) {
        snprintf(err, errlen, "%s: writer failed earlier", w->path);
        return false;
    }
    if (!w->in_ray) {
        snprintf(err, errlen, "%s: rt_tlog_ray_end without rt_tlog_ray_begin", w->path);
        w->broken = true;
        return false;
    }
    w->in_ray = false;
    if (w->ev_oom) {
        snprintf(err, errlen, "%s: out of memory buffering events", w->path);
        w->broken = true;
        return false;
    }
    w->codes.len = 0;
    w->bits.len = 0;
    w->nbits = 0;
    rt_trv_counts c;
    uint64_t nvisits;
    bool hit = false;
    if (!walk_events(w, overflowed, &c, &nvisits, &hit, err, errlen)) {
        w->broken = true;
        return false;
    }
    /* the ray record: derived from the camera or the previous ray when it
     * is bit-identical to what they give, else stored */
    const rt_ray *r = &w->ray;
    uint32_t src = RT_TLOG_SRC_STORED;
    rt_ray cand;
    if (w->has_cam && r->bounce == 0 && r->pixel / w->cam.width < w->cam.height) {
        cand = rt_camera_primary_ray(&w->cam, r->pixel % w->cam.width, r->pixel / w->cam.width);
        if (rt_tlog_same_ray(&cand, r))
            src = RT_TLOG_SRC_CAMERA;
    }
    if (src == RT_TLOG_SRC_STORED && w->info.mesh && w->prev_complete && w->tot.rays > 0 &&
        rt_bounce_ray(w->info.mesh, &w->prev_ray, &w->prev_hit, w->info.seed, w->info.max_bounces, &cand) &&
        rt_tlog_same_ray(&cand, r))
        src = RT_TLOG_SRC_BOUNCE;
    tlog_buf *b = &w->raw;
    buf_varint(b, rt_tlog_zigzag((int64_t)r->pixel - (int64_t)w->prev_pixel));
    w->prev_pixel = r->pixel;
    uint32_t tminb = rt_tlog_float_bits(r->tmin), tmaxb = rt_tlog_float_bits(r->tmax);
    uint8_t flags = r->bounce < RT_TLOG_RF_BOUNCE_MASK ? r->bounce : RT_TLOG_RF_BOUNCE_MASK;
    if (src == RT_TLOG_SRC_STORED && tminb != 0)
        flags |= RT_TLOG_RF_TMIN;
    if (src == RT_TLOG_SRC_STORED && tmaxb != rt_tlog_float_bits(RT_RAY_TMAX))
        flags |= RT_TLOG_RF_TMAX;
    if (overflowed)
        flags |= RT_TLOG_RF_OVERFLOW;
    flags |= (uint8_t)(src << RT_TLOG_RF_SOURCE_SHIFT);
    buf_u8(b, flags);
    if ((flags & RT_TLOG_RF_BOUNCE_MASK) == RT_TLOG_RF_BOUNCE_MASK)
        buf_u8(b, r->bounce);
    if (src == RT_TLOG_SRC_STORED) {
        const float v[6] = {r->org.x, r->org.y, r->org.z, r->dir.x, r->dir.y, r->dir.z};
        for (int k = 0; k < 6; k++) {
            uint32_t bits = rt_tlog_float_bits(v[k]);
            buf_u32(b, bits ^ w->prev_bits[k]);
            w->prev_bits[k] = bits;
        }
        if (flags & RT_TLOG_RF_TMIN)
            buf_u32(b, tminb);
        if (flags & RT_TLOG_RF_TMAX)
            buf_u32(b, tmaxb);
    }
    w->tot.rays_camera += src == RT_TLOG_SRC_CAMERA;
    w->tot.rays_bounce += src == RT_TLOG_SRC_BOUNCE;
    w->prev_ray = *r;
    w->prev_hit = w->cur_hit;
    w->prev_complete = !overflowed;
    if (overflowed)
        buf_varint(b, w->nev);
    buf_varint(b, nvisits);
    buf_varint(b, w->nbits);
    buf_put(b, w->codes.p, w->codes.len);
    buf_put(b, w->bits.p, w->bits.len);
    if (b->oom || w->codes.oom || w->bits.oom) {
        snprintf(err, errlen, "%s: out of memory", w->path);
        w->broken = true;
        return false;
    }
    if (b->len > RT_TLOG_BLOCK_RAW_MAX / 2) {
        snprintf(err, errlen, "%s: ray %llu: record too large", w->path, (unsigned long long)w->tot.rays);
        w->broken = true;
        return false;
    }
    w->tot.stream_hash = rt_tlog_hash_ray(w->tot.stream_hash, r);
    for (size_t k = 0; k < w->nev; k++)
        w->tot.stream_hash = rt_tlog_hash_event(w->tot.stream_hash, &w->ev[k]);
    if (w->block_rays == 0)
        w->block_first = w->tot.rays;
    w->block_rays++;
    w->tot.rays++;
    w->tot.visits += c.visits;
    w->tot.pushes += c.pushes;
    w->tot.pops += c.pops;
    w->tot.culls += c.culls;
    w->tot.leaves += c.leaves;
    w->tot.tri_tests += c.tri_tests;
    w->tot.hits += hit;
    w->tot.overflows += overflowed;
    w->tot.events += w->nev;
    if (b->len >= w->block_bytes && !flush_block(w, err, errlen)) {
        w->broken = true;
        return false;
    }
    return true;
}

bool rt_tlog_writer_close(rt_tlog_writer *w, rt_tlog_totals *totals, char *err, size_t errlen)
{
    if (w->broken || w->in_ray) {
        snprintf(err, errlen, "%s: %s", w->path, w->broken ? "writer failed earlier" : "ray not ended");
        rt_tlog_writer_abort(w);
        return false;
    }
    if (!flush_block(w, err, errlen)) {
        rt_tlog_writer_abort(w);
        return false;
    }
    uint8_t e[RT_TLOG_END_BYTES] = {0};
    rt_tlog_put_u32(e, RT_TLOG_END_MAGIC);
    const uint64_t vals[12] = {w->tot.blocks, w->tot.rays,   w->tot.visits, w->tot.pushes,
                               w->tot.pops,   w->tot.culls,  w->tot.leaves, w->tot.tri_tests,
                               w->tot.hits,   w->tot.overflows, w->tot.events, w->tot.stream_hash};
    for (int k = 0; k < 12; k++)
        rt_tlog_put_u64(e + 8 + 8 * k, vals[k]);
    rt_tlog_put_u32(e + 104, (uint32_t)crc32(0L, e, 104));
    uint8_t h[RT_TLOG_HEADER_BYTES];
    header_bytes(w, h);
    bool ok = fwrite(e, 1, sizeof e, w->f) == sizeof e;
    w->offset += sizeof e;
    ok = ok && fseek(w->f, 0, SEEK_SET) == 0 && fwrite(h, 1, sizeof h, w->f) == sizeof h;
    ok = ok && fflush(w->f) == 0 && !ferror(w->f);
    ok = (fclose(w->f) == 0) && ok;
    w->f = NULL;
    if (!ok || rename(w->tmp, w->path) != 0) {
        snprintf(err, errlen, "%s: write failed", w->path);
        remove(w->tmp);
        free_writer(w);
        return false;
    }
    w->tot.file_bytes = w->offset;
    if (totals)
        *totals = w->tot;
    free_writer(w);
    return true;
}

void rt_tlog_writer_abort(rt_tlog_writer *w)
{
    if (!w)
        return;
    if (w->f)
        fclose(w->f);
    remove(w->tmp);
    free_writer(w);
}
