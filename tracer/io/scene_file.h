/* scene_file.h — reading whole files, transparently gunzipped (zlib gz* API).
 *
 * Contract: returns a malloc'ed buffer of the (decompressed) bytes plus a NUL
 * after the last byte (not counted in *len), or NULL with "FILE: reason" in
 * err (cannot open, is a folder, read error, corrupt or truncated gzip data,
 * more than max bytes). what names the kind of file in messages ("mesh
 * file"). At most max bytes (decompressed) are kept: a regular file larger
 * than max is refused before it is read, a stream (pipe, FIFO, /dev/zero)
 * or a gzip file is read until it passes max, so an endless input ends in a
 * refusal, not in a hang or an out-of-memory exit. The file is opened once
 * (a FIFO is read once). */
#ifndef RTSIM_TRACER_SCENE_FILE_H
#define RTSIM_TRACER_SCENE_FILE_H

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Bounds of what rt_read_file_gz keeps of one file (decompressed bytes). */
#define RT_MESH_MAX_BYTES ((size_t)4 << 30)   /* an OBJ or PLY mesh: 4 GiB */
#define RT_TEXT_MAX_BYTES ((size_t)16 << 20)  /* a views or .scene file: 16 MiB */

unsigned char *rt_read_file_gz(const char *path, const char *what, size_t max, size_t *len, char *err,
                               size_t errlen);

/* True when path ends with suffix (ASCII case-insensitive). */
bool rt_path_has_suffix(const char *path, const char *suffix);

#ifdef __cplusplus
}
#endif

#endif
