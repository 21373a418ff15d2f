/* obj_load.h — Wavefront OBJ reader (positions and faces only).
 *
 * Accepts `v x y z [w ...]` (extra values ignored), `f` with index forms
 * v, v/vt, v//vn, v/vt/vn, positive (1-based) or negative (relative to the
 * elements defined so far) indices, polygons fan-triangulated
 * (v0,v[i],v[i+1]) in file order, `#` comments, blank lines, CRLF. `vt`/`vn`
 * are counted only to check references; o, g, s, usemtl, mtllib, l, p and
 * other statements are ignored; a UTF-8 byte order mark is skipped. Positive
 * indices may refer to elements defined later in the file (checked at the
 * end); negative ones count back from the elements defined so far. Errors:
 * "FILE:LINE: ..." (bad number, index out of range, face with fewer than 3
 * vertices). Input may be gzip-compressed (any name). */
#ifndef RTSIM_TRACER_OBJ_LOAD_H
#define RTSIM_TRACER_OBJ_LOAD_H

#include <stdbool.h>
#include <stddef.h>

#include "tracer/io/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Parses OBJ text of `len` bytes (need not be NUL-terminated); `file` names
 * it in messages. On success *out owns new arrays; on failure it is zeroed. */
bool rt_obj_parse(const char *text, size_t len, const char *file, rt_mesh *out,
                  char *err, size_t errlen);
/* Reads (gunzipping if needed) and parses an OBJ file. */
bool rt_obj_load(const char *path, rt_mesh *out, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif
