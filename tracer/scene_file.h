/* scene_file.h — reading whole files, transparently gunzipped (zlib gz* API).
 *
 * Contract: returns a malloc'ed buffer of the (decompressed) bytes plus a NUL
 * after the last byte (not counted in *len), or NULL with "FILE: reason" in
 * err (cannot open, read error, corrupt or truncated gzip data). */
#ifndef RTSIM_TRACER_SCENE_FILE_H
#define RTSIM_TRACER_SCENE_FILE_H

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

unsigned char *rt_read_file_gz(const char *path, size_t *len, char *err, size_t errlen);

/* True when path ends with suffix (ASCII case-insensitive). */
bool rt_path_has_suffix(const char *path, const char *suffix);

#ifdef __cplusplus
}
#endif

#endif
