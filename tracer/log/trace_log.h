/* trace_log.h — compact binary trace logs of the reference traversal: per ray
 * its event stream (tracer/trace/traverse.h: VISIT, PUSH, POP, CULL, LEAF, TRI,
 * DONE) plus ray id, pixel and bounce, tied to the memory image it was traced
 * on (rt_bvh_image.hash) and checked by CRC32 blocks and an end record.
 *
 * What is stored (full field tables in docs/tracer-log.md): the ray itself and
 * the traversal's decisions — per node visit the set of hit children and their
 * order, per stack pop whether the distance stack culled the entry, per
 * triangle test whether it became the closest hit. Everything else (node and
 * triangle indices, PUSH/POP/CULL/LEAF/DONE events, every distance t) follows
 * from the decisions, the node/triangle bytes of the image and the ray, so it
 * is re-derived on read with the arithmetic of bvh_layout.h, and every
 * recorded decision is checked against that arithmetic: a log is only ever
 * read together with the image it belongs to. Records are grouped in blocks
 * compressed with zlib deflate; an end record holds totals and a 64-bit hash
 * of the whole event stream.
 *
 * Writer: rt_tlog_writer_open, then per ray rt_tlog_ray_begin, the events
 * (rt_tlog_event is an rt_trv_event_fn), rt_tlog_ray_end; rt_tlog_writer_close
 * writes the end record and renames the temp file to the final name (never a
 * partial log under the final name); rt_tlog_writer_abort removes it.
 * Reader: rt_tlog_reader_open validates the header against the caller's image,
 * rt_tlog_read_ray returns the rays in order with their events; after the last
 * one it validates the end record. Every rejection is one line
 * "FILE: byte OFFSET: what is wrong". Garbage never crashes the reader. */
#ifndef RTSIM_TRACER_TRACE_LOG_H
#define RTSIM_TRACER_TRACE_LOG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "tracer/bvh/bvh.h"
#include "tracer/trace/ray.h"
#include "tracer/trace/traverse.h"
#include "tracer/io/view.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RT_TLOG_MAGIC "RTSIMTLG"     /* 8 bytes at offset 0 */
#define RT_TLOG_VERSION 1u
#define RT_TLOG_HEADER_BYTES 136u

enum rt_tlog_ray_kind { RT_TLOG_RAYS_PRIMARY = 0, RT_TLOG_RAYS_DIFFUSE = 1, RT_TLOG_RAYS_OTHER = 2 };

/* Header fields the writer is given (image-derived ones are filled in from
 * the image and the traversal parameters).
 * Ray derivation: a ray that equals, bit for bit, the camera's primary ray
 * of its pixel (view given, res_width x res_height) or rt_bounce_ray of the
 * ray logged just before it (mesh given, seed, max_bounces) is stored as
 * "derived" in a byte or two instead of its 32 bytes of floats: log a path's
 * rays one after the other (primary, bounce 1, ...) to profit. A log with
 * bounce-derived rays can only be read with the mesh. */
typedef struct rt_tlog_info {
    uint64_t mesh_hash;          /* rt_mesh_hash of the scene */
    uint32_t res_width, res_height;
    uint32_t ray_kind;           /* rt_tlog_ray_kind */
    uint32_t max_bounces;
    uint64_t seed;
    bool has_view;               /* view holds the camera of the primary rays */
    rt_view view;                /* name not stored */
    const rt_mesh *mesh;         /* writer only: enables bounce derivation (must outlive the writer) */
} rt_tlog_info;

/* The header as read back. */
typedef struct rt_tlog_header {
    uint32_t version;
    uint32_t bvh_width;          /* N of the image */
    uint32_t stack_depth;
    bool distance_cull;
    uint32_t nnodes, ntris;
    uint64_t image_hash;
    uint64_t ray_count;
    rt_tlog_info info;
} rt_tlog_header;

/* Totals over the whole log (also the end record's content). */
typedef struct rt_tlog_totals {
    uint64_t rays, visits, pushes, pops, culls, leaves, tri_tests, hits, overflows;
    uint64_t rays_camera, rays_bounce;   /* rays stored as derived (not in the end record) */
    uint64_t events;
    uint64_t stream_hash;         /* FNV-1a 64 over every ray's fields and its events' kind, a, b, t bits */
    uint64_t blocks;
    uint64_t file_bytes;         /* size of the finished file */
} rt_tlog_totals;

typedef struct rt_tlog_writer rt_tlog_writer;

/* Opens PATH (written as PATH.tmp.PID, renamed by close). The image must
 * outlive the writer. NULL with a message on a bad parameter or I/O error. */
rt_tlog_writer *rt_tlog_writer_open(const char *path, const rt_bvh_image *img, const rt_trv_params *trv,
                                    const rt_tlog_info *info, char *err, size_t errlen);
/* Raw (uncompressed) bytes after which a block is compressed and written;
 * default RT_TLOG_BLOCK_DEFAULT, 256..16 MiB (tests use small blocks). */
#define RT_TLOG_BLOCK_DEFAULT (256u * 1024u)
void rt_tlog_writer_set_block_bytes(rt_tlog_writer *w, uint32_t bytes);
/* Starts the record of the next ray (ray id = number of rays before it). */
void rt_tlog_ray_begin(rt_tlog_writer *w, const rt_ray *ray);
/* Event callback for rt_trace_ray (user = the writer). */
void rt_tlog_event(void *user, const rt_trv_event *ev);
/* Ends the ray's record. overflowed = rt_trace_ray returned false. False
 * when the events are not a traversal of this image (message says why);
 * the writer is then unusable (abort it). */
bool rt_tlog_ray_end(rt_tlog_writer *w, bool overflowed, char *err, size_t errlen);
/* Flushes, writes the end record, patches the header's ray count, renames
 * to the final name and frees the writer (also on failure). */
bool rt_tlog_writer_close(rt_tlog_writer *w, rt_tlog_totals *totals, char *err, size_t errlen);
/* Discards the temp file and frees the writer (NULL allowed). */
void rt_tlog_writer_abort(rt_tlog_writer *w);

typedef struct rt_tlog_reader rt_tlog_reader;

/* Opens a log and validates its header (magic, version, fields, CRC) and
 * that it belongs to img (hash, width, node and triangle counts) and, when
 * mesh is given, to mesh (rt_mesh_hash); mesh may be NULL unless the log has
 * bounce-derived rays (then reading one is an error naming the problem).
 * img NULL: header checks only (rt_tlog_read_ray then fails). */
rt_tlog_reader *rt_tlog_reader_open(const char *path, const rt_bvh_image *img, const rt_mesh *mesh,
                                    rt_tlog_header *hdr, char *err, size_t errlen);

/* One ray read back: its id, the ray, the derived hit and counts. */
typedef struct rt_tlog_ray {
    uint64_t id;
    rt_ray ray;
    rt_hit hit;                  /* prim, t; u = v = 0 (not logged) */
    rt_trv_counts counts;
    bool overflowed;
} rt_tlog_ray;

/* Reads the next ray, calling fn (may be NULL) for each of its events in
 * order. Returns 1 for a ray, 0 at the end of a valid log (end record
 * checked against everything read), -1 on error (message in err; further
 * calls keep returning -1). */
int rt_tlog_read_ray(rt_tlog_reader *r, rt_tlog_ray *out, rt_trv_event_fn fn, void *user, char *err,
                     size_t errlen);
/* Totals of what has been read so far (equal to the end record after 0). */
void rt_tlog_reader_totals(const rt_tlog_reader *r, rt_tlog_totals *t);
void rt_tlog_reader_close(rt_tlog_reader *r);

/* Reads and validates only the header (img not needed): e.g. to learn the
 * BVH width a log was written for. */
bool rt_tlog_read_header(const char *path, rt_tlog_header *hdr, char *err, size_t errlen);

/* Reads and validates a whole log against img; totals on success. */
bool rt_tlog_verify(const char *path, const rt_bvh_image *img, const rt_mesh *mesh, rt_tlog_header *hdr,
                    rt_tlog_totals *totals, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif
