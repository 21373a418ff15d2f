/* builtin.c — see builtin.h: the registry of built-in scenes. */
#include "tracer/io/builtin.h"

#include <stdlib.h>
#include <string.h>

#include "tracer/io/builtin_geom.h"
#include "tracer/io/scene_error.h"

static const struct {
    const char *name;
    void (*generate)(rt_mesh_builder *, rt_views *);
} builtins[] = {
    {"interior", rt_builtin_interior},
    {"hairball", rt_builtin_hairball},
    {"city", rt_builtin_city},
    {"forest", rt_builtin_forest},
};
enum { NBUILTINS = sizeof builtins / sizeof builtins[0] };

unsigned rt_builtin_count(void) { return NBUILTINS; }

const char *rt_builtin_name(unsigned i) { return i < NBUILTINS ? builtins[i].name : NULL; }

bool rt_builtin_exists(const char *name)
{
    for (unsigned i = 0; i < NBUILTINS; i++)
        if (strcmp(builtins[i].name, name) == 0)
            return true;
    return false;
}

bool rt_builtin_generate(const char *name, rt_mesh *mesh, rt_views *views, char *err, size_t errlen)
{
    if (mesh)
        memset(mesh, 0, sizeof *mesh);
    if (views)
        views->v = NULL, views->n = 0;
    for (unsigned i = 0; i < NBUILTINS; i++) {
        if (strcmp(builtins[i].name, name) != 0)
            continue;
        rt_mesh_builder b;
        memset(&b, 0, sizeof b);
        builtins[i].generate(&b, views);
        if (b.oom) {
            rt_mesh_free(&b.m);
            if (views)
                rt_views_free(views);
            rt_scene_errorf(err, errlen, "built-in scene %s: out of memory", name);
            return false;
        }
        if (mesh)
            *mesh = b.m;
        else
            rt_mesh_free(&b.m);
        return true;
    }
    rt_scene_errorf(err, errlen, "unknown built-in scene '%s'; allowed interior, hairball, city, forest",
                    name);
    return false;
}
