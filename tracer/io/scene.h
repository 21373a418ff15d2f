/* scene.h — a scene = triangle mesh + named views; loading by name or path.
 *
 * A SCENE argument (docs/design.md "Command-line conventions") is one of
 *   - a built-in name (builtin.h): interior, hairball, city, forest
 *     (also accepted as "builtin:NAME");
 *   - a mesh file: *.obj, *.ply, optionally *.gz (obj_load.h, ply_load.h);
 *     its views come from a views.txt in the same folder when present,
 *     else one default view framing the mesh bounds is made (named "auto");
 *   - a scene description file *.scene (format in docs/tracer-io.md):
 *       mesh <builtin name | path relative to the .scene file>
 *       views <path relative to the .scene file>     (optional)
 *       view <name> eye ... at ... up ... fov ...     (views.txt syntax)
 *     Views given in the file (views/view lines, in order) replace the mesh's
 *     own; with none, the mesh's own views (built-in or views.txt) are used.
 * Contract: on failure returns false with "FILE:LINE: ..." and leaves *out
 * zeroed; a loaded scene has >= 1 triangle and >= 1 view (v[0] = default). */
#ifndef RTSIM_TRACER_SCENE_H
#define RTSIM_TRACER_SCENE_H

#include <stdbool.h>
#include <stddef.h>

#include "tracer/io/mesh.h"
#include "tracer/io/view.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RT_SCENE_NAME_MAX 256

typedef struct rt_scene {
    rt_mesh mesh;
    rt_views views;
    char name[RT_SCENE_NAME_MAX];   /* the built-in name or the file's base name */
} rt_scene;

/* Loads SCENE (name or path, see above). */
bool rt_scene_load(const char *scene, rt_scene *out, char *err, size_t errlen);

/* Loads a mesh file by extension (.obj/.ply, optionally .gz) with no views. */
bool rt_mesh_load(const char *path, rt_mesh *out, char *err, size_t errlen);

/* Replaces the scene's views with those of a views file (--views FILE). */
bool rt_scene_set_views_file(rt_scene *s, const char *path, char *err, size_t errlen);

/* The view called name, or the default view when name is NULL; NULL with a
 * message listing the available names when there is no such view. */
const rt_view *rt_scene_view(const rt_scene *s, const char *name, char *err, size_t errlen);

void rt_scene_free(rt_scene *s);

#ifdef __cplusplus
}
#endif

#endif
