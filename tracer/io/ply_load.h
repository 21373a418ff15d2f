/* ply_load.h — PLY reader (Turk 1994 format as written by common tools).
 *
 * Formats ascii, binary_little_endian, binary_big_endian 1.0. Element
 * `vertex` must have properties x, y, z (any scalar type, any order, extra
 * properties such as normals/colors ignored). Element `face` must have a list
 * property `vertex_indices` (or `vertex_index`) with an integer count type
 * and integer index type; faces of n >= 3 vertices are fan-triangulated,
 * fewer is an error; indices must be < vertex count. Other elements and
 * properties are skipped; `comment`/`obj_info` ignored. Bytes after the last
 * element are ignored. Errors: "FILE:LINE: ..." for the header and ASCII
 * body, "FILE: byte N (element E index I): ..." for binary bodies. Input may
 * be gzip-compressed (any name). */
#ifndef RTSIM_TRACER_PLY_LOAD_H
#define RTSIM_TRACER_PLY_LOAD_H

#include <stdbool.h>
#include <stddef.h>

#include "tracer/io/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Parses PLY data of `len` bytes; `file` names it in messages. On success
 * *out owns new arrays; on failure it is zeroed. */
bool rt_ply_parse(const unsigned char *data, size_t len, const char *file, rt_mesh *out,
                  char *err, size_t errlen);
/* Reads (gunzipping if needed) and parses a PLY file. */
bool rt_ply_load(const char *path, rt_mesh *out, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif
