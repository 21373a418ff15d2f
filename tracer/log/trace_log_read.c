/* trace_log_read.c — the trace log reader (contract in trace_log.h, byte
 * layout in trace_log_format.h). It reads block by block, checks every CRC,
 * size and field, and replays each ray's recorded decisions on the image
 * with the box and triangle arithmetic of bvh_layout.h to regenerate the
 * event stream (the distances are not stored). Each recorded decision must
 * agree with the arithmetic, so a log applied to another image, or damaged
 * in a way the CRCs miss, is rejected, never misread. All reads are bounds-
 * checked: garbage yields a message, never a crash or a huge allocation. */
#include <errno.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

#include "tracer/log/trace_log.h"
#include "tracer/trace/bounce.h"
#include "tracer/trace/camera.h"
#include "tracer/log/trace_log_format.h"

typedef struct stack_entry {
    uint32_t ref, count;
    float t;
} stack_entry;

struct rt_tlog_reader {
    FILE *f;
    char *path;
    const rt_bvh_image *img;
    const rt_mesh *mesh;
    rt_tlog_header hdr;
    bool has_cam;
    rt_camera cam;
    rt_ray prev_ray;
    rt_hit prev_hit;
    bool prev_complete;
    uint64_t off;          /* file offset of the next unread byte */
    int state;             /* 0 reading, 1 finished, -1 failed */
    char msg[4096 + 512];  /* the failure, repeated by later calls: the whole path (PATH_MAX) and why */
    /* the current block */
    uint8_t *raw, *comp;
    size_t raw_cap, comp_cap, raw_len, pos;
    uint64_t block_off;
    uint32_t rays_left, block_rays;
    uint32_t prev_pixel, prev_bits[6];
    /* replay */
    stack_entry *stack;
    rt_trv_event *ev;
    size_t nev, evcap;
    bool ev_oom;
    rt_tlog_totals tot;
};

static int fail(rt_tlog_reader *r, char *err, size_t errlen, uint64_t off, const char *fmt, ...)
{
    char why[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    snprintf(r->msg, sizeof r->msg, "%s: byte %" PRIu64 ": %s", r->path, off, why);
    snprintf(err, errlen, "%s", r->msg);
    r->state = -1;
    return -1;
}

/* Reads exactly n bytes at the current offset; false when the file ends. */
static bool read_exact(rt_tlog_reader *r, void *buf, size_t n, size_t *got)
{
    *got = fread(buf, 1, n, r->f);
    r->off += *got;
    return *got == n;
}

static bool grow(uint8_t **p, size_t *cap, size_t need)
{
    if (need <= *cap)
        return true;
    uint8_t *q = realloc(*p, need);
    if (!q)
        return false;
    *p = q;
    *cap = need;
    return true;
}

rt_tlog_reader *rt_tlog_reader_open(const char *path, const rt_bvh_image *img, const rt_mesh *mesh,
                                    rt_tlog_header *hdr, char *err, size_t errlen)
{
    rt_tlog_reader *r = calloc(1, sizeof *r);
    size_t pl = strlen(path);
    if (!r || !(r->path = malloc(pl + 1))) {
        free(r);
        snprintf(err, errlen, "%s: out of memory", path);
        return NULL;
    }
    memcpy(r->path, path, pl + 1);
    r->img = img;
    r->mesh = mesh;
    r->tot.stream_hash = RT_TLOG_FNV_OFFSET;
    r->f = fopen(path, "rb");
    if (!r->f) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        rt_tlog_reader_close(r);
        return NULL;
    }
    /* a folder opens like a file on Linux and reads as empty: it would be
     * called a truncated log */
    struct stat st;
    if (fstat(fileno(r->f), &st) == 0 && S_ISDIR(st.st_mode)) {
        snprintf(err, errlen, "%s: is a folder, not a trace log", path);
        rt_tlog_reader_close(r);
        return NULL;
    }
    uint8_t h[RT_TLOG_HEADER_BYTES];
    size_t got;
    int bad = 0;
    if (!read_exact(r, h, sizeof h, &got)) {
        if (memcmp(h, RT_TLOG_MAGIC, got < 8 ? got : 8) != 0)
            bad = fail(r, err, errlen, 0, "not a trace log (magic is not %s)", RT_TLOG_MAGIC);
        else
            bad = fail(r, err, errlen, got, "truncated header (%zu of %u bytes)", got, RT_TLOG_HEADER_BYTES);
    } else if (memcmp(h, RT_TLOG_MAGIC, 8) != 0) {
        bad = fail(r, err, errlen, 0, "not a trace log (magic is not %s)", RT_TLOG_MAGIC);
    } else if (rt_tlog_get_u32(h + 8) != RT_TLOG_VERSION) {
        bad = fail(r, err, errlen, 8, "format version %u, this reader reads version %u", rt_tlog_get_u32(h + 8),
                   RT_TLOG_VERSION);
    } else if (rt_tlog_get_u32(h + 132) != (uint32_t)crc32(0L, h, 132)) {
        bad = fail(r, err, errlen, 132, "header checksum mismatch (header corrupt)");
    }
    if (bad) {
        rt_tlog_reader_close(r);
        return NULL;
    }
    rt_tlog_header *H = &r->hdr;
    H->version = rt_tlog_get_u32(h + 8);
    H->bvh_width = rt_tlog_get_u32(h + 16);
    H->stack_depth = rt_tlog_get_u32(h + 20);
    uint32_t flags = rt_tlog_get_u32(h + 24);
    H->distance_cull = (flags & RT_TLOG_FLAG_DISTANCE_CULL) != 0;
    H->nnodes = rt_tlog_get_u32(h + 28);
    H->ntris = rt_tlog_get_u32(h + 32);
    H->info.ray_kind = rt_tlog_get_u32(h + 36);
    H->image_hash = rt_tlog_get_u64(h + 40);
    H->info.mesh_hash = rt_tlog_get_u64(h + 48);
    H->ray_count = rt_tlog_get_u64(h + 56);
    H->info.res_width = rt_tlog_get_u32(h + 64);
    H->info.res_height = rt_tlog_get_u32(h + 68);
    H->info.max_bounces = rt_tlog_get_u32(h + 72);
    H->info.seed = rt_tlog_get_u64(h + 80);
    if (rt_tlog_get_u32(h + 12) != RT_TLOG_HEADER_BYTES)
        bad = fail(r, err, errlen, 12, "header size %u, expected %u", rt_tlog_get_u32(h + 12), RT_TLOG_HEADER_BYTES);
    else if (H->bvh_width < RT_WIDTH_MIN || H->bvh_width > RT_WIDTH_MAX)
        bad = fail(r, err, errlen, 16, "BVH width %u out of range %d..%d", H->bvh_width, RT_WIDTH_MIN, RT_WIDTH_MAX);
    else if (H->stack_depth < 1 || H->stack_depth > 4096)
        bad = fail(r, err, errlen, 20, "stack depth %u out of range 1..4096", H->stack_depth);
    else if (flags & ~(RT_TLOG_FLAG_DISTANCE_CULL | RT_TLOG_FLAG_CAMERA))
        bad = fail(r, err, errlen, 24, "unknown flags 0x%x", flags);
    else if (H->info.ray_kind > RT_TLOG_RAYS_OTHER)
        bad = fail(r, err, errlen, 36, "ray kind %u out of range 0..2", H->info.ray_kind);
    else if (rt_tlog_get_u32(h + 76) != 0 || rt_tlog_get_u32(h + 128) != 0)
        bad = fail(r, err, errlen, 76, "reserved header fields are not zero");
    else if (mesh && rt_mesh_hash(mesh) != H->info.mesh_hash)
        bad = fail(r, err, errlen, 48, "log is for mesh hash %016" PRIx64 ", the given mesh has hash %016" PRIx64,
                   H->info.mesh_hash, rt_mesh_hash(mesh));
    else if (!img)
        ;   /* header only (rt_tlog_read_header) */
    else if (H->image_hash != img->hash)
        bad = fail(r, err, errlen, 40,
                   "log is for BVH image hash %016" PRIx64 ", the given image has hash %016" PRIx64
                   " (other scene, BVH type or build parameters)",
                   H->image_hash, img->hash);
    else if (H->bvh_width != (uint32_t)img->width || H->nnodes != img->nnodes || H->ntris != img->ntris)
        bad = fail(r, err, errlen, 16, "log is for a width-%u BVH of %u nodes and %u triangles, the image has %d, %u, %u",
                   H->bvh_width, H->nnodes, H->ntris, img->width, img->nnodes, img->ntris);
    if (!bad) {
        float f[10];
        bool zero = true;
        for (int i = 0; i < 10; i++) {
            f[i] = rt_tlog_bits_float(rt_tlog_get_u32(h + 88 + 4 * i));
            zero = zero && rt_tlog_get_u32(h + 88 + 4 * i) == 0;
        }
        H->info.has_view = (flags & RT_TLOG_FLAG_CAMERA) != 0;
        if (H->info.has_view) {
            rt_view *v = &H->info.view;
            memset(v, 0, sizeof *v);
            snprintf(v->name, sizeof v->name, "log");
            v->eye = (rt_vec3){f[0], f[1], f[2]};
            v->at = (rt_vec3){f[3], f[4], f[5]};
            v->up = (rt_vec3){f[6], f[7], f[8]};
            v->fov_deg = f[9];
            char cerr[300];
            if (!rt_camera_init(&r->cam, v, H->info.res_width, H->info.res_height, cerr, sizeof cerr))
                bad = fail(r, err, errlen, 88, "camera: %s", cerr);
            r->has_cam = !bad;
        } else if (!zero) {
            bad = fail(r, err, errlen, 88, "camera fields set without the camera flag");
        }
    }
    if (!bad) {
        r->stack = calloc((size_t)H->stack_depth + 2, sizeof *r->stack);
        if (!r->stack)
            bad = fail(r, err, errlen, 0, "out of memory");
    }
    if (bad) {
        rt_tlog_reader_close(r);
        return NULL;
    }
    if (hdr)
        *hdr = *H;
    return r;
}

void rt_tlog_reader_close(rt_tlog_reader *r)
{
    if (!r)
        return;
    if (r->f)
        fclose(r->f);
    free(r->path);
    free(r->raw);
    free(r->comp);
    free(r->stack);
    free(r->ev);
    free(r);
}

void rt_tlog_reader_totals(const rt_tlog_reader *r, rt_tlog_totals *t) { *t = r->tot; }

/* ---- blocks and the end record ---- */

static int read_end(rt_tlog_reader *r, const uint8_t *first4, char *err, size_t errlen)
{
    uint64_t at = r->off - 4;
    uint8_t e[RT_TLOG_END_BYTES];
    memcpy(e, first4, 4);
    size_t got;
    if (!read_exact(r, e + 4, sizeof e - 4, &got))
        return fail(r, err, errlen, r->off, "truncated end record (%zu of %u bytes)", got + 4, RT_TLOG_END_BYTES);
    if (rt_tlog_get_u32(e + 104) != (uint32_t)crc32(0L, e, 104))
        return fail(r, err, errlen, at + 104, "end record checksum mismatch");
    if (rt_tlog_get_u32(e + 4) != 0)
        return fail(r, err, errlen, at + 4, "end record reserved field is not zero");
    static const char *names[12] = {"blocks", "rays", "visits", "pushes", "pops", "culls",
                                    "leaves", "tri_tests", "hits", "overflows", "events", "stream_hash"};
    const uint64_t have[12] = {r->tot.blocks, r->tot.rays,   r->tot.visits, r->tot.pushes,
                               r->tot.pops,   r->tot.culls,  r->tot.leaves, r->tot.tri_tests,
                               r->tot.hits,   r->tot.overflows, r->tot.events, r->tot.stream_hash};
    for (int k = 0; k < 12; k++) {
        uint64_t v = rt_tlog_get_u64(e + 8 + 8 * k);
        if (v != have[k])
            return fail(r, err, errlen, at + 8 + 8 * (uint64_t)k,
                        "end record says %s = %" PRIu64 ", the records give %" PRIu64
                        "%s",
                        names[k], v, have[k], k == 11 ? " (replayed events differ from the traced ones)" : "");
    }
    if (r->hdr.ray_count != r->tot.rays)
        return fail(r, err, errlen, 56, "header says %" PRIu64 " rays, the log holds %" PRIu64, r->hdr.ray_count,
                    r->tot.rays);
    int c = fgetc(r->f);
    if (c != EOF)
        return fail(r, err, errlen, r->off, "trailing bytes after the end record");
    r->tot.file_bytes = r->off;
    r->state = 1;
    return 0;
}

static int read_block(rt_tlog_reader *r, const uint8_t *first4, char *err, size_t errlen)
{
    uint64_t at = r->off - 4;
    uint8_t h[RT_TLOG_BLOCK_HEADER_BYTES];
    memcpy(h, first4, 4);
    size_t got;
    if (!read_exact(r, h + 4, sizeof h - 4, &got))
        return fail(r, err, errlen, r->off, "truncated block header (%zu of %u bytes)", got + 4,
                    RT_TLOG_BLOCK_HEADER_BYTES);
    if (rt_tlog_get_u32(h + 28) != (uint32_t)crc32(0L, h, 28))
        return fail(r, err, errlen, at + 28, "block header checksum mismatch");
    uint32_t nrays = rt_tlog_get_u32(h + 4), raw_len = rt_tlog_get_u32(h + 16), comp_len = rt_tlog_get_u32(h + 20);
    uint64_t first = rt_tlog_get_u64(h + 8);
    if (nrays == 0)
        return fail(r, err, errlen, at + 4, "block with no rays");
    if (first != r->tot.rays)
        return fail(r, err, errlen, at + 8, "block starts at ray %" PRIu64 ", expected ray %" PRIu64, first,
                    r->tot.rays);
    if (raw_len == 0 || raw_len > RT_TLOG_BLOCK_RAW_MAX)
        return fail(r, err, errlen, at + 16, "block size %u out of range 1..%u", raw_len, RT_TLOG_BLOCK_RAW_MAX);
    if (comp_len == 0 || comp_len > compressBound(raw_len))
        return fail(r, err, errlen, at + 20, "compressed size %u out of range 1..%lu", comp_len,
                    (unsigned long)compressBound(raw_len));
    if (!grow(&r->comp, &r->comp_cap, comp_len) || !grow(&r->raw, &r->raw_cap, raw_len))
        return fail(r, err, errlen, at, "out of memory");
    if (!read_exact(r, r->comp, comp_len, &got))
        return fail(r, err, errlen, r->off, "truncated block (%zu of %u compressed bytes)", got, comp_len);
    if (rt_tlog_get_u32(h + 24) != (uint32_t)crc32(0L, r->comp, comp_len))
        return fail(r, err, errlen, at + 24, "block checksum mismatch (block data corrupt)");
    uLongf dlen = raw_len;
    int zr = uncompress(r->raw, &dlen, r->comp, comp_len);
    if (zr != Z_OK || dlen != raw_len)
        return fail(r, err, errlen, at + RT_TLOG_BLOCK_HEADER_BYTES, "block data does not inflate to %u bytes (%s)",
                    raw_len, zr == Z_OK ? "size differs" : zError(zr));
    r->raw_len = raw_len;
    r->pos = 0;
    r->block_off = at;
    r->rays_left = r->block_rays = nrays;
    r->tot.blocks++;
    return 1;
}

/* ---- ray records ---- */

typedef struct cursor {
    const uint8_t *p;
    size_t pos, end;
} cursor;

static bool cur_u8(cursor *c, uint8_t *v)
{
    if (c->pos >= c->end)
        return false;
    *v = c->p[c->pos++];
    return true;
}
static bool cur_u32(cursor *c, uint32_t *v)
{
    if (c->end - c->pos < 4)
        return false;
    *v = rt_tlog_get_u32(c->p + c->pos);
    c->pos += 4;
    return true;
}
static bool cur_varint(cursor *c, uint64_t *v)
{
    uint64_t x = 0;
    for (int shift = 0; shift < 64; shift += 7) {
        uint8_t b;
        if (!cur_u8(c, &b))
            return false;
        if (shift == 63 && b > 1)
            return false;
        x |= (uint64_t)(b & 0x7f) << shift;
        if (!(b & 0x80)) {
            *v = x;
            return true;
        }
    }
    return false;
}

typedef struct replay {
    rt_tlog_reader *r;
    cursor codes;
    size_t codes_end;
    const uint8_t *bits;
    uint64_t nbits, bitpos;
    uint64_t max_events;    /* stop after this many events (overflowed ray) */
    bool stopped;
    rt_trv_counts counts;
} replay;

static void emit(replay *rp, uint8_t kind, uint32_t a, uint32_t b, float t)
{
    rt_tlog_reader *r = rp->r;
    if (rp->stopped)
        return;
    if (r->nev >= rp->max_events) {
        rp->stopped = true;
        return;
    }
    if (r->nev == r->evcap) {
        size_t cap = r->evcap ? 2 * r->evcap : 1024;
        rt_trv_event *p = realloc(r->ev, cap * sizeof *p);
        if (!p) {
            r->ev_oom = true;
            rp->stopped = true;
            return;
        }
        r->ev = p;
        r->evcap = cap;
    }
    rt_trv_event *e = &r->ev[r->nev++];
    memset(e, 0, sizeof *e);
    e->kind = kind;
    e->a = a;
    e->b = b;
    e->t = t;
}

static int take_bit(replay *rp)
{
    if (rp->bitpos >= rp->nbits)
        return -1;
    int b = (rp->bits[rp->bitpos / 8] >> (rp->bitpos % 8)) & 1;
    rp->bitpos++;
    return b;
}

#define RFAIL(...) return fail(r, err, errlen, at, __VA_ARGS__)

/* Replays one ray's decisions; events land in r->ev. at = the record's
 * offset for messages (file offset of its block + raw position). */
static int replay_ray(replay *rp, const rt_ray *ray, rt_hit *hit, uint64_t at, char *err, size_t errlen)
{
    rt_tlog_reader *r = rp->r;
    const rt_bvh_image *img = r->img;
    const int width = img->width;
    const float org[3] = {ray->org.x, ray->org.y, ray->org.z}, dir[3] = {ray->dir.x, ray->dir.y, ray->dir.z};
    rt_ray_prep prep;
    rt_ray_prepare(org, dir, &prep);
    float closest = ray->tmax;
    uint32_t best = RT_NO_HIT;
    size_t sp = 0;
    bool tgt_leaf = false;
    uint32_t tgt_ref = 0, tgt_count = 0;
    rt_trv_counts *c = &rp->counts;
    while (!rp->stopped) {
        if (!tgt_leaf) {
            if (tgt_ref >= img->nnodes)
                RFAIL("node %u out of range (image has %u nodes)", tgt_ref, img->nnodes);
            const uint8_t *node = rt_bvh_node_ptr(img, tgt_ref);
            emit(rp, RT_EV_VISIT, tgt_ref, 0, 0.0f);
            c->visits++;
            /* an overflowed ray's last visit may end among its pushes: no code
             * was recorded for it and the order comes from the distances */
            bool derive = rp->max_events != UINT64_MAX && rp->codes.pos == rp->codes_end;
            uint8_t mask = 0;
            if (!derive && (!cur_u8(&rp->codes, &mask) || rp->codes.pos > rp->codes_end))
                RFAIL("more node visits than recorded");
            /* the box tests, in slot order */
            rt_child ch[RT_WIDTH_MAX];
            float tn[RT_WIDTH_MAX];
            uint32_t hitmask = 0;
            for (int s = 0; s < width; s++) {
                rt_node_child(node, s, &ch[s]);
                if (rt_child_empty(&ch[s]))
                    break;   /* used slots come first (bvh_layout.h) */
                c->box_tests++;
                if (rt_slab_test(&prep, ch[s].lo, ch[s].hi, ray->tmin, closest, &tn[s]))
                    hitmask |= 1u << s;
            }
            if (derive)
                mask = (uint8_t)hitmask;
            if (mask != hitmask)
                RFAIL("visit of node %u: log says children 0x%x are hit, the box tests give 0x%x (log does not match "
                      "this image or ray)",
                      tgt_ref, mask, hitmask);
            int k = rt_tlog_popcount(mask);
            int sorted[RT_WIDTH_MAX], order[RT_WIDTH_MAX], n = 0;
            for (int s = 0; s < width; s++)
                if (mask & (1u << s))
                    sorted[n++] = s;
            /* the hardware's order: by (tnear, slot) ascending */
            int want[RT_WIDTH_MAX];
            memcpy(want, sorted, sizeof(int) * (size_t)k);
            for (int a = 1; a < k; a++) {
                int x = want[a], b = a;
                while (b > 0 && tn[x] < tn[want[b - 1]]) {
                    want[b] = want[b - 1];
                    b--;
                }
                want[b] = x;
            }
            if (derive) {
                memcpy(order, want, sizeof(int) * (size_t)k);
            } else if (k >= 2) {
                uint8_t lo, hi = 0;
                if (!cur_u8(&rp->codes, &lo) || (k > 5 && !cur_u8(&rp->codes, &hi)) || rp->codes.pos > rp->codes_end)
                    RFAIL("visit of node %u: hit order missing", tgt_ref);
                if (!rt_tlog_lehmer_decode((uint32_t)lo | (uint32_t)hi << 8, sorted, k, order))
                    RFAIL("visit of node %u: hit order code %u out of range", tgt_ref, (unsigned)lo | (unsigned)hi << 8);
                if (memcmp(order, want, sizeof(int) * (size_t)k) != 0)
                    RFAIL("visit of node %u: recorded hit order differs from the box distances", tgt_ref);
            } else if (k == 1) {
                order[0] = sorted[0];
            }
            if (k > 0) {
                for (int a = k - 1; a >= 1; a--) {
                    const rt_child *x = &ch[order[a]];
                    if (sp >= (size_t)r->hdr.stack_depth) {
                        /* an overflowed ray may log the push that overflowed */
                        if (rp->max_events != UINT64_MAX && sp == (size_t)r->hdr.stack_depth) {
                            emit(rp, RT_EV_PUSH, x->ref, rt_child_count(x), tn[order[a]]);
                            rp->stopped = true;
                            break;
                        }
                        if (rp->max_events != UINT64_MAX) {
                            rp->stopped = true;
                            break;
                        }
                        RFAIL("stack overflow (depth %u) in a ray not marked as overflowed", r->hdr.stack_depth);
                    }
                    r->stack[sp].ref = x->ref;
                    r->stack[sp].count = rt_child_count(x);
                    r->stack[sp].t = tn[order[a]];
                    sp++;
                    c->pushes++;
                    if (sp > c->max_stack)
                        c->max_stack = (uint32_t)sp;
                    emit(rp, RT_EV_PUSH, x->ref, rt_child_count(x), tn[order[a]]);
                }
                const rt_child *x = &ch[order[0]];
                tgt_leaf = rt_child_is_leaf(x);
                tgt_ref = x->ref;
                tgt_count = rt_child_count(x);
                continue;
            }
        } else {
            if ((uint64_t)tgt_ref + tgt_count > img->ntris)
                RFAIL("leaf triangles %u+%u out of range (image has %u)", tgt_ref, tgt_count, img->ntris);
            emit(rp, RT_EV_LEAF, tgt_ref, tgt_count, 0.0f);
            c->leaves++;
            for (uint32_t i = 0; i < tgt_count && !rp->stopped; i++) {
                rt_tri48 tri;
                rt_tri_decode(rt_bvh_tri_ptr(img, tgt_ref + i), &tri);
                float t, u, v;
                bool h = rt_wald_test(&tri, org, dir, ray->tmin, closest, &t, &u, &v);
                int bit = take_bit(rp);
                if (bit < 0)
                    RFAIL("more decisions than recorded (triangle %u)", tgt_ref + i);
                if (bit != (int)h)
                    RFAIL("triangle %u: log says %s, the triangle test says %s (log does not match this image or ray)",
                          tgt_ref + i, bit ? "hit" : "no hit", h ? "hit" : "no hit");
                if (h) {
                    closest = t;
                    best = tgt_ref + i;
                }
                c->tri_tests++;
                emit(rp, RT_EV_TRI, tgt_ref + i, (uint32_t)h, closest);
            }
        }
        /* pop until a target or DONE */
        for (;;) {
            if (rp->stopped)
                break;
            if (sp == 0) {
                uint32_t prim = RT_NO_HIT;
                if (best != RT_NO_HIT) {
                    rt_tri48 tri;
                    rt_tri_decode(rt_bvh_tri_ptr(img, best), &tri);
                    prim = tri.prim;
                }
                emit(rp, RT_EV_DONE, prim, 0, closest);
                hit->prim = prim;
                hit->t = closest;
                hit->u = hit->v = 0.0f;
                if (rp->max_events != UINT64_MAX && !rp->stopped)
                    RFAIL("ray marked as overflowed completed its traversal");
                return 0;
            }
            stack_entry top = r->stack[--sp];
            bool cull = false;
            if (r->hdr.distance_cull) {
                int bit = take_bit(rp);
                if (bit < 0)
                    RFAIL("more decisions than recorded (stack pop)");
                cull = top.t > closest;
                if (bit != (int)cull)
                    RFAIL("stack entry %u: log says %s, the distances say %s (log does not match this image or ray)",
                          top.ref, bit ? "culled" : "kept", cull ? "culled" : "kept");
            }
            if (cull) {
                c->culls++;
                emit(rp, RT_EV_CULL, top.ref, top.count, top.t);
                continue;
            }
            c->pops++;
            emit(rp, RT_EV_POP, top.ref, top.count, top.t);
            tgt_leaf = top.count != 0;
            tgt_ref = top.ref;
            tgt_count = top.count;
            break;
        }
    }
    /* stopped: an overflowed ray's events end here */
    hit->prim = best == RT_NO_HIT ? RT_NO_HIT : hit->prim;
    if (best != RT_NO_HIT) {
        rt_tri48 tri;
        rt_tri_decode(rt_bvh_tri_ptr(img, best), &tri);
        hit->prim = tri.prim;
    }
    hit->t = closest;
    hit->u = hit->v = 0.0f;
    if (r->ev_oom)
        RFAIL("out of memory");
    return 0;
}

int rt_tlog_read_ray(rt_tlog_reader *r, rt_tlog_ray *out, rt_trv_event_fn fn, void *user, char *err,
                     size_t errlen)
{
    if (r->state == -1) {
        snprintf(err, errlen, "%s", r->msg);
        return -1;
    }
    if (r->state == 1)
        return 0;
    if (!r->img)
        return fail(r, err, errlen, 0, "opened for its header only (no BVH image given)");
    while (r->rays_left == 0) {
        if (r->raw_len && r->pos != r->raw_len)
            return fail(r, err, errlen, r->block_off, "block has %zu bytes after its %u rays", r->raw_len - r->pos,
                        r->block_rays);
        uint8_t m[4];
        size_t got;
        if (!read_exact(r, m, 4, &got))
            return fail(r, err, errlen, r->off, "truncated: the file ends without an end record");
        uint32_t magic = rt_tlog_get_u32(m);
        if (magic == RT_TLOG_END_MAGIC)
            return read_end(r, m, err, errlen);
        if (magic != RT_TLOG_BLOCK_MAGIC)
            return fail(r, err, errlen, r->off - 4, "expected a block or the end record, found 0x%08x", magic);
        r->raw_len = 0;
        if (read_block(r, m, err, errlen) < 0)
            return -1;
    }
    cursor c = {r->raw, r->pos, r->raw_len};
    const uint64_t at = r->block_off;   /* records live in the block's compressed data */
    const uint64_t ray_id = r->tot.rays;
#define TRUNC(what)                                                                                             \
    return fail(r, err, errlen, r->block_off,                                                                   \
                "block ray record %u (ray %" PRIu64 "), decompressed byte %zu: %s", r->block_rays - r->rays_left, \
                ray_id, c.pos, what)
    uint64_t zz, nvisits, nbits, nevents = UINT64_MAX;
    uint8_t flags, bounce;
    if (!cur_varint(&c, &zz))
        TRUNC("record truncated (pixel)");
    int64_t pixel = (int64_t)r->prev_pixel + rt_tlog_unzigzag(zz);
    uint64_t npix = (uint64_t)r->hdr.info.res_width * r->hdr.info.res_height;
    if (pixel < 0 || pixel > (int64_t)UINT32_MAX || (npix && (uint64_t)pixel >= npix))
        TRUNC("pixel out of range");
    if (!cur_u8(&c, &flags))
        TRUNC("record truncated (flags)");
    const uint32_t src = (uint32_t)flags >> RT_TLOG_RF_SOURCE_SHIFT;
    if (src > RT_TLOG_SRC_BOUNCE)
        TRUNC("unknown ray source");
    bounce = flags & RT_TLOG_RF_BOUNCE_MASK;
    if (bounce == RT_TLOG_RF_BOUNCE_MASK && (!cur_u8(&c, &bounce) || bounce < RT_TLOG_RF_BOUNCE_MASK))
        TRUNC("bad bounce number");
    uint32_t bits[6], tminb = 0, tmaxb = rt_tlog_float_bits(RT_RAY_TMAX);
    rt_ray derived;
    memset(&derived, 0, sizeof derived);
    if (src != RT_TLOG_SRC_STORED && (flags & (RT_TLOG_RF_TMIN | RT_TLOG_RF_TMAX)))
        TRUNC("derived ray with stored tmin/tmax");
    if (src == RT_TLOG_SRC_STORED) {
        for (int k = 0; k < 6; k++) {
            uint32_t x;
            if (!cur_u32(&c, &x))
                TRUNC("record truncated (ray)");
            bits[k] = x ^ r->prev_bits[k];
        }
        if ((flags & RT_TLOG_RF_TMIN) && !cur_u32(&c, &tminb))
            TRUNC("record truncated (tmin)");
        if ((flags & RT_TLOG_RF_TMAX) && !cur_u32(&c, &tmaxb))
            TRUNC("record truncated (tmax)");
    } else if (src == RT_TLOG_SRC_CAMERA) {
        if (!r->has_cam)
            TRUNC("camera-derived ray in a log without a camera");
        if (bounce != 0)
            TRUNC("camera-derived ray with a bounce number");
        derived = rt_camera_primary_ray(&r->cam, (uint32_t)pixel % r->cam.width, (uint32_t)pixel / r->cam.width);
    } else {
        if (!r->mesh)
            TRUNC("bounce-derived ray: reading this log needs the scene's mesh");
        if (r->tot.rays == 0 || !r->prev_complete ||
            !rt_bounce_ray(r->mesh, &r->prev_ray, &r->prev_hit, r->hdr.info.seed, r->hdr.info.max_bounces, &derived))
            TRUNC("bounce-derived ray without a previous ray that bounces");
        if (derived.pixel != (uint32_t)pixel || derived.bounce != bounce)
            TRUNC("bounce-derived ray's pixel or bounce differs from the previous ray's path");
    }
    if (src != RT_TLOG_SRC_STORED) {
        const float v[6] = {derived.org.x, derived.org.y, derived.org.z, derived.dir.x, derived.dir.y, derived.dir.z};
        for (int k = 0; k < 6; k++)
            bits[k] = rt_tlog_float_bits(v[k]);
        tminb = rt_tlog_float_bits(derived.tmin);
        tmaxb = rt_tlog_float_bits(derived.tmax);
    }
    if ((flags & RT_TLOG_RF_OVERFLOW) && !cur_varint(&c, &nevents))
        TRUNC("record truncated (event count)");
    if (!cur_varint(&c, &nvisits) || !cur_varint(&c, &nbits))
        TRUNC("record truncated (counts)");
    if (nvisits > c.end - c.pos)
        TRUNC("visit count larger than the record");
    /* the codes are self-delimiting given the visit count */
    size_t codes_start = c.pos;
    for (uint64_t v = 0; v < nvisits; v++) {
        uint8_t mask;
        if (!cur_u8(&c, &mask))
            TRUNC("record truncated (visit codes)");
        if (r->hdr.bvh_width < 8 && (mask >> r->hdr.bvh_width))
            TRUNC("hit mask names a slot beyond the BVH width");
        int k = rt_tlog_popcount(mask);
        for (int x = 0; x < (k >= 2) + (k > 5); x++) {
            uint8_t dummy;
            if (!cur_u8(&c, &dummy))
                TRUNC("record truncated (hit order)");
        }
    }
    size_t codes_end = c.pos;
    if (nbits > 8 * (uint64_t)(c.end - c.pos))
        TRUNC("decision bit count larger than the record");
    size_t nbytes = (size_t)((nbits + 7) / 8);
    const uint8_t *bitp = c.p + c.pos;
    if (nbits % 8 && (bitp[nbytes - 1] >> (nbits % 8)))
        TRUNC("unused decision bits are not zero");
    c.pos += nbytes;

    rt_tlog_ray o;
    memset(&o, 0, sizeof o);
    o.id = ray_id;
    o.ray.pixel = (uint32_t)pixel;
    o.ray.bounce = bounce;
    o.ray.org.x = rt_tlog_bits_float(bits[0]);
    o.ray.org.y = rt_tlog_bits_float(bits[1]);
    o.ray.org.z = rt_tlog_bits_float(bits[2]);
    o.ray.dir.x = rt_tlog_bits_float(bits[3]);
    o.ray.dir.y = rt_tlog_bits_float(bits[4]);
    o.ray.dir.z = rt_tlog_bits_float(bits[5]);
    o.ray.tmin = rt_tlog_bits_float(tminb);
    o.ray.tmax = rt_tlog_bits_float(tmaxb);
    o.overflowed = (flags & RT_TLOG_RF_OVERFLOW) != 0;

    replay rp;
    memset(&rp, 0, sizeof rp);
    rp.r = r;
    rp.codes.p = r->raw;
    rp.codes.pos = codes_start;
    rp.codes.end = codes_end;
    rp.codes_end = codes_end;
    rp.bits = bitp;
    rp.nbits = nbits;
    rp.max_events = nevents;
    r->nev = 0;
    if (replay_ray(&rp, &o.ray, &o.hit, at, err, errlen) < 0) {
        /* name the ray in the message */
        char tmp[sizeof r->msg];
        const char *m = r->msg;
        int n = snprintf(tmp, sizeof tmp, " (ray %" PRIu64 ", pixel %u, bounce %u, block record %u)", ray_id,
                         o.ray.pixel, o.ray.bounce, r->block_rays - r->rays_left);
        /* the ray goes after the message; a message too long to take it
         * keeps its own text whole (the path in it is never cut) */
        size_t used = strlen(m);
        if (n > 0 && used + (size_t)n < sizeof r->msg)
            memcpy(r->msg + used, tmp, (size_t)n + 1);
        snprintf(err, errlen, "%s", r->msg);
        return -1;
    }
    if (rp.codes.pos != codes_end ||
        (rp.counts.visits != nvisits && !(o.overflowed && rp.counts.visits == nvisits + 1)))
        TRUNC("fewer node visits than recorded");
    if (rp.bitpos != nbits)
        TRUNC("fewer decisions than recorded");
    if (o.overflowed && r->nev != nevents)
        TRUNC("overflowed ray's event count differs from the replay");
    o.counts = rp.counts;
    r->pos = c.pos;
    r->prev_pixel = o.ray.pixel;
    if (src == RT_TLOG_SRC_STORED)
        memcpy(r->prev_bits, bits, sizeof bits);
    r->prev_ray = o.ray;
    r->prev_hit = o.hit;
    r->prev_complete = !o.overflowed;
    r->tot.rays_camera += src == RT_TLOG_SRC_CAMERA;
    r->tot.rays_bounce += src == RT_TLOG_SRC_BOUNCE;
    r->rays_left--;
    r->tot.rays++;
    r->tot.visits += o.counts.visits;
    r->tot.pushes += o.counts.pushes;
    r->tot.pops += o.counts.pops;
    r->tot.culls += o.counts.culls;
    r->tot.leaves += o.counts.leaves;
    r->tot.tri_tests += o.counts.tri_tests;
    r->tot.hits += o.hit.prim != RT_NO_HIT && !o.overflowed;
    r->tot.overflows += o.overflowed;
    r->tot.events += r->nev;
    r->tot.stream_hash = rt_tlog_hash_ray(r->tot.stream_hash, &o.ray);
    for (size_t k = 0; k < r->nev; k++)
        r->tot.stream_hash = rt_tlog_hash_event(r->tot.stream_hash, &r->ev[k]);
    if (fn)
        for (size_t k = 0; k < r->nev; k++)
            fn(user, &r->ev[k]);
    if (out)
        *out = o;
    return 1;
#undef TRUNC
}

bool rt_tlog_verify(const char *path, const rt_bvh_image *img, const rt_mesh *mesh, rt_tlog_header *hdr,
                    rt_tlog_totals *totals, char *err, size_t errlen)
{
    rt_tlog_reader *r = rt_tlog_reader_open(path, img, mesh, hdr, err, errlen);
    if (!r)
        return false;
    int s;
    while ((s = rt_tlog_read_ray(r, NULL, NULL, NULL, err, errlen)) == 1)
        ;
    if (s == 0 && totals)
        rt_tlog_reader_totals(r, totals);
    rt_tlog_reader_close(r);
    return s == 0;
}

bool rt_tlog_read_header(const char *path, rt_tlog_header *hdr, char *err, size_t errlen)
{
    rt_tlog_reader *r = rt_tlog_reader_open(path, NULL, NULL, hdr, err, errlen);
    rt_tlog_reader_close(r);
    return r != NULL;
}
