/* trace_log_format.h — internal to trace_log_write.c / trace_log_read.c: the
 * byte layout of a trace log (docs/tracer-log.md has the same tables) and the
 * small codecs both sides share: little-endian fields, LEB128 varints, the
 * Lehmer code of a hit order, the event hash.
 *
 * File = header (RT_TLOG_HEADER_BYTES) + blocks + end record.
 * Header:  0 magic[8] | 8 version | 12 header_bytes | 16 bvh_width | 20 stack_depth
 *          24 flags (bit 0 distance cull) | 28 nnodes | 32 ntris | 36 ray_kind
 *          40 image_hash u64 | 48 mesh_hash u64 | 56 ray_count u64 | 64 res_width
 *          68 res_height | 72 max_bounces | 76 reserved 0 | 80 seed u64
 *          88 camera: eye xyz, at xyz, up xyz, fov (10 float32; flags bit 1 = present)
 *          128 reserved 0 | 132 crc32 of bytes 0..131           (u32 unless noted)
 * Block:   0 "RTLB" | 4 nrays | 8 first_ray_id u64 | 16 raw_len | 20 comp_len
 *          24 crc32 of the payload | 28 crc32 of bytes 0..27 | 32 payload
 *          (zlib stream of raw_len bytes of ray records)
 * End:     0 "RTLE" | 4 reserved 0 | 8 blocks u64 | 16 rays | 24 visits | 32 pushes
 *          40 pops | 48 culls | 56 leaves | 64 tri_tests | 72 hits | 80 overflows
 *          88 events | 96 stream_hash (all u64; FNV-1a of rays and events, below) | 104 crc32 of bytes 0..103; then EOF.
 * Ray record (raw, in a block; "prev" = the previous ray of the log, 0 for
 * the first):
 *   varint zigzag(pixel - prev pixel)
 *   u8 flags: bits 0..2 bounce (7 = a u8 bounce follows), bit 3 tmin bits
 *      follow, bit 4 tmax bits follow (absent: tmin = 0, tmax = RT_RAY_TMAX),
 *      bit 5 the stack overflowed (a varint event count follows), bits 6..7
 *      source: 0 stored, 1 the camera's primary ray of the pixel, 2
 *      rt_bounce_ray of the previous ray (derived: no float fields follow)
 *   [u8 bounce] [6 x u32: org, dir float bits XOR the previous stored ray's
 *   [u32 tmin] [u32 tmax]]   (stored rays only)
 *   [varint events]   varint n_visits   varint n_bits
 *   n_visits codes: u8 mask of hit slots; when >= 2 are hit, the Lehmer index
 *      of their order (closest first) among them in slot order: u8 for up to
 *      5 hits, u16 for more
 *   ceil(n_bits / 8) bytes: decision bits LSB first, in event order: per
 *      stack pop with the distance stack on, 1 = culled; per triangle test,
 *      1 = it became the closest hit. */
#ifndef RTSIM_TRACER_TRACE_LOG_FORMAT_H
#define RTSIM_TRACER_TRACE_LOG_FORMAT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "tracer/trace/ray.h"
#include "tracer/trace/traverse.h"

#define RT_TLOG_BLOCK_MAGIC 0x424C5452u    /* "RTLB" little-endian */
#define RT_TLOG_END_MAGIC 0x454C5452u      /* "RTLE" */
#define RT_TLOG_BLOCK_HEADER_BYTES 32u
#define RT_TLOG_END_BYTES 108u
#define RT_TLOG_BLOCK_RAW_MAX (64u * 1024u * 1024u)  /* reader's limit on one block's raw size */
#define RT_TLOG_FLAG_DISTANCE_CULL 1u
#define RT_TLOG_FLAG_CAMERA 2u
#define RT_TLOG_RF_BOUNCE_MASK 7u
#define RT_TLOG_RF_TMIN 8u
#define RT_TLOG_RF_TMAX 16u
#define RT_TLOG_RF_OVERFLOW 32u
#define RT_TLOG_RF_SOURCE_SHIFT 6
#define RT_TLOG_SRC_STORED 0u
#define RT_TLOG_SRC_CAMERA 1u
#define RT_TLOG_SRC_BOUNCE 2u

/* Bit-exact equality of two rays (all fields). */
static inline bool rt_tlog_same_ray(const rt_ray *a, const rt_ray *b)
{
    return memcmp(&a->org, &b->org, sizeof a->org) == 0 && memcmp(&a->dir, &b->dir, sizeof a->dir) == 0 &&
           memcmp(&a->tmin, &b->tmin, 4) == 0 && memcmp(&a->tmax, &b->tmax, 4) == 0 && a->pixel == b->pixel &&
           a->bounce == b->bounce;
}

static inline void rt_tlog_put_u32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}
static inline void rt_tlog_put_u64(uint8_t *p, uint64_t v)
{
    for (int i = 0; i < 8; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}
static inline uint32_t rt_tlog_get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static inline uint64_t rt_tlog_get_u64(const uint8_t *p)
{
    return (uint64_t)rt_tlog_get_u32(p) | (uint64_t)rt_tlog_get_u32(p + 4) << 32;
}
static inline uint32_t rt_tlog_float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    return u;
}
static inline float rt_tlog_bits_float(uint32_t u)
{
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* Lehmer index of order[0..k) (distinct values), ranked among themselves:
 * 0 for ascending order, k! - 1 for descending. */
static inline uint32_t rt_tlog_lehmer_encode(const int *order, int k)
{
    uint32_t idx = 0;
    for (int i = 0; i < k; i++) {
        uint32_t smaller = 0;
        for (int j = i + 1; j < k; j++)
            smaller += order[j] < order[i];
        idx = idx * (uint32_t)(k - i) + smaller;
    }
    return idx;
}
static inline uint32_t rt_tlog_factorial(int k)
{
    uint32_t f = 1;
    for (int i = 2; i <= k; i++)
        f *= (uint32_t)i;
    return f;
}
/* Inverse of the above on the sorted values vals[0..k): order[i] = vals[...];
 * false when idx >= k!. */
static inline bool rt_tlog_lehmer_decode(uint32_t idx, const int *vals, int k, int *order)
{
    if (idx >= rt_tlog_factorial(k))
        return false;
    int digits[RT_WIDTH_MAX];
    for (int i = k - 1; i >= 0; i--) {
        uint32_t base = (uint32_t)(k - i);
        digits[i] = (int)(idx % base);
        idx /= base;
    }
    int left[RT_WIDTH_MAX], nleft = k;
    memcpy(left, vals, sizeof(int) * (size_t)k);
    for (int i = 0; i < k; i++) {
        int d = digits[i];
        order[i] = left[d];
        memmove(left + d, left + d + 1, sizeof(int) * (size_t)(nleft - d - 1));
        nleft--;
    }
    return true;
}

/* FNV-1a 64 (Fowler/Noll/Vo) over the stream: each ray's pixel, bounce,
 * org, dir, tmin, tmax bits, then each of its events' kind, a, b, t bits. */
#define RT_TLOG_FNV_OFFSET 0xcbf29ce484222325ull
static inline uint64_t rt_tlog_fnv(uint64_t h, const uint8_t *b, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        h ^= b[i];
        h *= 0x100000001b3ull;
    }
    return h;
}
static inline uint64_t rt_tlog_hash_event(uint64_t h, const rt_trv_event *ev)
{
    uint8_t b[13];
    b[0] = ev->kind;
    rt_tlog_put_u32(b + 1, ev->a);
    rt_tlog_put_u32(b + 5, ev->b);
    rt_tlog_put_u32(b + 9, rt_tlog_float_bits(ev->t));
    return rt_tlog_fnv(h, b, sizeof b);
}
static inline uint64_t rt_tlog_hash_ray(uint64_t h, const rt_ray *r)
{
    uint8_t b[37];
    const float v[8] = {r->org.x, r->org.y, r->org.z, r->dir.x, r->dir.y, r->dir.z, r->tmin, r->tmax};
    rt_tlog_put_u32(b, r->pixel);
    b[4] = r->bounce;
    for (int i = 0; i < 8; i++)
        rt_tlog_put_u32(b + 5 + 4 * i, rt_tlog_float_bits(v[i]));
    return rt_tlog_fnv(h, b, sizeof b);
}

static inline uint64_t rt_tlog_zigzag(int64_t v) { return ((uint64_t)v << 1) ^ (uint64_t)(v >> 63); }
static inline int64_t rt_tlog_unzigzag(uint64_t u) { return (int64_t)(u >> 1) ^ -(int64_t)(u & 1); }

/* Popcount of a slot mask. */
static inline int rt_tlog_popcount(uint32_t m)
{
    int n = 0;
    for (; m; m &= m - 1)
        n++;
    return n;
}

#endif
