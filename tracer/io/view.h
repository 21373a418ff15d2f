/* view.h — named pinhole cameras as written in views.txt files.
 *
 * Format (../shared/scenes/README.md, "views.txt format"), one view a line:
 *   view <name> eye <x> <y> <z> at <x> <y> <z> up <x> <y> <z> fov <deg>
 * name: letters, digits, '-', '_' (1..63 chars), unique in the list; numbers
 * finite; 0 < fov < 180; up not parallel to at - eye; eye != at. Blank lines
 * and lines starting with '#' are ignored; CRLF accepted. The first view is
 * the default. Errors name the file and line (see scene_error.h). */
#ifndef RTSIM_TRACER_VIEW_H
#define RTSIM_TRACER_VIEW_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "tracer/io/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RT_VIEW_NAME_MAX 64

typedef struct rt_view {
    char name[RT_VIEW_NAME_MAX];
    rt_vec3 eye, at, up;
    float fov_deg;           /* full vertical field of view */
} rt_view;

typedef struct rt_views {
    rt_view *v;              /* n views, v[0] = default */
    uint32_t n;
} rt_views;

/* Parses one views line (without its newline) into *out. Returns false with
 * "FILE:LINE: ..." in err. Blank/comment lines are not views: the caller
 * skips them (rt_views_line_is_blank). */
bool rt_view_parse_line(const char *line, const char *file, unsigned lineno,
                        rt_view *out, char *err, size_t errlen);
bool rt_views_line_is_blank(const char *line);

/* Checks a view's geometry (fov range, eye != at, up not parallel). */
bool rt_view_validate(const rt_view *v, const char *file, unsigned lineno,
                      char *err, size_t errlen);

/* Parses a whole text (NUL-terminated); `file` names it in messages. At least
 * one view is required. On failure *out is left empty. */
bool rt_views_parse_text(const char *text, const char *file, rt_views *out,
                         char *err, size_t errlen);
/* Reads and parses a views file. */
bool rt_views_load(const char *path, rt_views *out, char *err, size_t errlen);

/* Appends a copy of *v (name must not already be present). */
bool rt_views_add(rt_views *vs, const rt_view *v, char *err, size_t errlen);
/* The view called name, or NULL. */
const rt_view *rt_views_find(const rt_views *vs, const char *name);
void rt_views_free(rt_views *vs);

#ifdef __cplusplus
}
#endif

#endif
