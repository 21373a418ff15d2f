/* scene.c — see scene.h. */
#include "tracer/io/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tracer/io/builtin.h"
#include "tracer/io/obj_load.h"
#include "tracer/io/ply_load.h"
#include "tracer/io/scene_error.h"
#include "tracer/io/scene_file.h"

#define SCENE_ALLOWED \
    "a built-in name (interior, hairball, city, forest), or a file ending .obj, .ply " \
    "(optionally .gz) or .scene"

static bool is_obj(const char *p) { return rt_path_has_suffix(p, ".obj") || rt_path_has_suffix(p, ".obj.gz"); }
static bool is_ply(const char *p) { return rt_path_has_suffix(p, ".ply") || rt_path_has_suffix(p, ".ply.gz"); }

bool rt_mesh_load(const char *path, rt_mesh *out, char *err, size_t errlen)
{
    if (is_obj(path))
        return rt_obj_load(path, out, err, errlen);
    if (is_ply(path))
        return rt_ply_load(path, out, err, errlen);
    memset(out, 0, sizeof *out);
    rt_scene_errorf(err, errlen, "%s: unknown mesh file type; allowed .obj, .ply, .obj.gz, .ply.gz",
                    path);
    return false;
}

/* dir/name where dir is the folder of `base` (name unchanged when absolute);
 * false when that does not fit in out[n] (a cut path names another file). */
static bool path_beside(const char *base, const char *name, char *out, size_t n)
{
    const char *slash = strrchr(base, '/');
    int len;
    if (name[0] == '/' || !slash)
        len = snprintf(out, n, "%s", name);
    else
        len = snprintf(out, n, "%.*s/%s", (int)(slash - base), base, name);
    return len >= 0 && (size_t)len < n;
}

/* The file name of path into out[n] (n > 1; a name has at most NAME_MAX =
 * 255 bytes; the precision tells gcc -O3 so: -Wformat-truncation). */
static void base_name(const char *path, char *out, size_t n)
{
    const char *slash = strrchr(path, '/');
    snprintf(out, n, "%.*s", (int)n - 1, slash ? slash + 1 : path);
}

/* The largest coordinate magnitude a scene may use (docs/tracer-io.md,
 * "Coordinate range"). A ray-triangle test multiplies three differences of
 * coordinates (Embree's: the triple products of the vertices relative to
 * the ray origin; ours: the plane distance n.A, n ~ extent^2); in float that
 * stays finite while the differences stay below cbrt(FLT_MAX) = 6.98e12.
 * Vertices are kept within 1e12 and view points within 5e12 (the auto view
 * of a scene at the vertex limit sits at most 4.3e12 from the origin: 2.2
 * scene radii from its centre), so a vertex-to-camera difference stays
 * below 6e12 and every product finite. Beyond it hits were lost silently
 * (1e38) and Embree overflowed (1e15: mismatches "other"). */
#define RT_COORD_MAX 1e12
#define RT_VIEW_COORD_MAX 5e12

static bool check_coord(const char *what, const char *name, rt_vec3 p, double limit, char *err, size_t errlen)
{
    const float c[3] = {p.x, p.y, p.z};
    for (int a = 0; a < 3; a++)
        if (!(fabsf(c[a]) <= (float)limit)) {
            rt_scene_errorf(err, errlen,
                            "%s: %s coordinate %g beyond the supported range -%g..%g (float ray-triangle "
                            "arithmetic overflows past it; scale the scene down)",
                            name, what, (double)c[a], limit, limit);
            return false;
        }
    return true;
}

/* Every vertex within +-RT_COORD_MAX, every view point within +-RT_VIEW_COORD_MAX. */
static bool check_range(const rt_mesh *m, const rt_views *vs, const char *name, char *err, size_t errlen)
{
    if (m->nverts) {
        rt_vec3 lo, hi;
        rt_mesh_bounds(m, &lo, &hi);
        if (!check_coord("vertex", name, lo, RT_COORD_MAX, err, errlen) ||
            !check_coord("vertex", name, hi, RT_COORD_MAX, err, errlen))
            return false;
    }
    for (uint32_t i = 0; vs && i < vs->n; i++) {
        char what[96];
        snprintf(what, sizeof what, "view '%.64s' eye", vs->v[i].name);
        if (!check_coord(what, name, vs->v[i].eye, RT_VIEW_COORD_MAX, err, errlen))
            return false;
        snprintf(what, sizeof what, "view '%.64s' at", vs->v[i].name);
        if (!check_coord(what, name, vs->v[i].at, RT_VIEW_COORD_MAX, err, errlen))
            return false;
    }
    return true;
}

/* One view framing the bounding sphere from the +Z side, slightly above,
 * for meshes that come without views (60 degrees, fits the sphere at 16:9). */
static bool auto_view(const rt_mesh *m, rt_views *vs, char *err, size_t errlen)
{
    rt_vec3 lo, hi;
    rt_mesh_bounds(m, &lo, &hi);
    double c[3] = {0.5 * ((double)lo.x + hi.x), 0.5 * ((double)lo.y + hi.y), 0.5 * ((double)lo.z + hi.z)};
    double dx = (double)hi.x - lo.x, dy = (double)hi.y - lo.y, dz = (double)hi.z - lo.z;
    double r = 0.5 * sqrt(dx * dx + dy * dy + dz * dz);
    if (!(r > 0))
        r = 1;
    double fov = 60.0, dist = 1.1 * r / sin(fov * M_PI / 360.0);
    double d[3] = {0.3, 0.4, 1.0}, dl = sqrt(0.09 + 0.16 + 1.0);
    rt_view v;
    memset(&v, 0, sizeof v);
    snprintf(v.name, sizeof v.name, "auto");
    v.eye = (rt_vec3){(float)(c[0] + dist * d[0] / dl), (float)(c[1] + dist * d[1] / dl),
                      (float)(c[2] + dist * d[2] / dl)};
    v.at = (rt_vec3){(float)c[0], (float)c[1], (float)c[2]};
    v.up = (rt_vec3){0, 1, 0};
    v.fov_deg = (float)fov;
    return rt_views_add(vs, &v, err, errlen);
}

/* A mesh (built-in or file) with its own views. */
static bool load_geometry(const char *what, rt_scene *s, char *err, size_t errlen)
{
    const char *name = strncmp(what, "builtin:", 8) == 0 ? what + 8 : what;
    if (rt_builtin_exists(name) || name != what) {
        /* built-in names are short; a longer one is rejected by rt_builtin_generate */
        snprintf(s->name, sizeof s->name, "%.*s", (int)sizeof s->name - 1, name);
        return rt_builtin_generate(name, &s->mesh, &s->views, err, errlen);
    }
    if (!is_obj(what) && !is_ply(what)) {
        rt_scene_errorf(err, errlen, "unknown scene '%s'; allowed " SCENE_ALLOWED, what);
        return false;
    }
    if (!rt_mesh_load(what, &s->mesh, err, errlen) || !check_range(&s->mesh, NULL, what, err, errlen))
        return false;
    base_name(what, s->name, sizeof s->name);
    char vpath[4096];
    if (path_beside(what, "views.txt", vpath, sizeof vpath) && access(vpath, F_OK) == 0)
        return rt_views_load(vpath, &s->views, err, errlen);
    return auto_view(&s->mesh, &s->views, err, errlen);
}

static bool load_scene_file(const char *path, rt_scene *s, char *err, size_t errlen)
{
    size_t len;
    unsigned char *buf = rt_read_file_gz(path, "scene file", RT_TEXT_MAX_BYTES, &len, err, errlen);
    if (!buf)
        return false;
    bool ok = false, have_mesh = false;
    rt_views own = {NULL, 0};
    unsigned lineno = 0;
    char *p = (char *)buf;
    if (len >= 3 && buf[0] == 0xef && buf[1] == 0xbb && buf[2] == 0xbf)
        p += 3;   /* UTF-8 byte order mark */
    if (memchr(buf, 0, len)) {
        rt_scene_errorf(err, errlen, "%s: contains a NUL byte; a scene file is text", path);
        goto done;
    }
    while (*p) {
        lineno++;
        char *eol = strchr(p, '\n');
        if (eol)
            *eol = 0;
        char *line = p;
        p = eol ? eol + 1 : p + strlen(p);
        size_t n = strlen(line);
        while (n && (line[n - 1] == '\r' || line[n - 1] == ' ' || line[n - 1] == '\t'))
            line[--n] = 0;
        while (*line == ' ' || *line == '\t')
            line++;
        if (*line == 0 || *line == '#')
            continue;
        char *arg = line + strcspn(line, " \t");
        if (*arg)
            *arg++ = 0;
        while (*arg == ' ' || *arg == '\t')
            arg++;
        if (strcmp(line, "mesh") == 0) {
            if (have_mesh) {
                rt_scene_errorf(err, errlen, "%s:%u: second 'mesh' line; a scene has one mesh", path, lineno);
                goto done;
            }
            if (!*arg) {
                rt_scene_errorf(err, errlen, "%s:%u: 'mesh' needs a built-in name or a path", path, lineno);
                goto done;
            }
            char mpath[4096];
            const bool builtin = strncmp(arg, "builtin:", 8) == 0 || rt_builtin_exists(arg);
            const bool fits = builtin ? snprintf(mpath, sizeof mpath, "%s", arg) < (int)sizeof mpath
                                      : path_beside(path, arg, mpath, sizeof mpath);
            if (!fits) {
                rt_scene_errorf(err, errlen, "%s:%u: mesh path longer than %zu characters", path, lineno,
                                sizeof mpath - 1);
                goto done;
            }
            if (!builtin && !is_obj(mpath) && !is_ply(mpath)) {
                rt_scene_errorf(err, errlen,
                                "%s:%u: mesh '%s': allowed a built-in name (interior, hairball, city, "
                                "forest) or a path ending .obj, .ply (optionally .gz)",
                                path, lineno, arg);
                goto done;
            }
            char sub[1024];
            if (!load_geometry(mpath, s, sub, sizeof sub)) {
                rt_scene_errorf(err, errlen, "%s:%u: %s", path, lineno, sub);
                goto done;
            }
            have_mesh = true;
        } else if (strcmp(line, "views") == 0) {
            char vpath[4096];
            rt_views vs;
            if (!*arg) {
                rt_scene_errorf(err, errlen, "%s:%u: 'views' needs a path", path, lineno);
                goto done;
            }
            if (!path_beside(path, arg, vpath, sizeof vpath)) {
                rt_scene_errorf(err, errlen, "%s:%u: views path longer than %zu characters", path, lineno,
                                sizeof vpath - 1);
                goto done;
            }
            if (!rt_views_load(vpath, &vs, err, errlen))
                goto done;
            for (uint32_t i = 0; i < vs.n; i++) {
                char sub[512];
                if (!rt_views_add(&own, &vs.v[i], sub, sizeof sub)) {
                    rt_scene_errorf(err, errlen, "%s:%u: %s", path, lineno, sub);
                    rt_views_free(&vs);
                    goto done;
                }
            }
            rt_views_free(&vs);
        } else if (strcmp(line, "view") == 0) {
            char full[1200];
            rt_view v;
            if (snprintf(full, sizeof full, "view %s", arg) >= (int)sizeof full) {
                /* cut, its tail would go unchecked (as views.txt lines, view.c) */
                rt_scene_errorf(err, errlen, "%s:%u: line longer than %zu characters", path, lineno,
                                sizeof full - 1);
                goto done;
            }
            if (!rt_view_parse_line(full, path, lineno, &v, err, errlen))
                goto done;
            char sub[512];
            if (!rt_views_add(&own, &v, sub, sizeof sub)) {
                rt_scene_errorf(err, errlen, "%s:%u: %s", path, lineno, sub);
                goto done;
            }
        } else {
            rt_scene_errorf(err, errlen, "%s:%u: unknown keyword '%s'; allowed mesh, views, view, # comments",
                            path, lineno, line);
            goto done;
        }
    }
    if (!have_mesh) {
        rt_scene_errorf(err, errlen, "%s: no 'mesh' line; a scene file needs 'mesh <name or path>'", path);
        goto done;
    }
    if (own.n) {
        rt_views_free(&s->views);
        s->views = own;
        own = (rt_views){NULL, 0};
    }
    ok = true;
done:
    rt_views_free(&own);
    free(buf);
    return ok;
}

bool rt_scene_load(const char *scene, rt_scene *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    bool ok;
    if (rt_path_has_suffix(scene, ".scene")) {
        ok = load_scene_file(scene, out, err, errlen);
        if (ok)
            base_name(scene, out->name, sizeof out->name);
    } else {
        ok = load_geometry(scene, out, err, errlen);
    }
    if (ok)
        ok = check_range(&out->mesh, &out->views, scene, err, errlen);
    if (ok && out->views.n == 0)
        ok = auto_view(&out->mesh, &out->views, err, errlen);
    if (!ok)
        rt_scene_free(out);
    return ok;
}

bool rt_scene_set_views_file(rt_scene *s, const char *path, char *err, size_t errlen)
{
    rt_views vs;
    if (!rt_views_load(path, &vs, err, errlen))
        return false;
    if (!check_range(&s->mesh, &vs, path, err, errlen)) {
        rt_views_free(&vs);
        return false;
    }
    rt_views_free(&s->views);
    s->views = vs;
    return true;
}

const rt_view *rt_scene_view(const rt_scene *s, const char *name, char *err, size_t errlen)
{
    if (!name)
        return s->views.n ? &s->views.v[0] : NULL;
    const rt_view *v = rt_views_find(&s->views, name);
    if (!v) {
        char list[512] = "";
        size_t n = 0;
        for (uint32_t i = 0; i < s->views.n && n + 1 < sizeof list; i++)
            n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", i ? ", " : "", s->views.v[i].name);
        rt_scene_errorf(err, errlen, "scene %s has no view '%s'; available: %s", s->name, name, list);
    }
    return v;
}

void rt_scene_free(rt_scene *s)
{
    rt_mesh_free(&s->mesh);
    rt_views_free(&s->views);
    memset(s, 0, sizeof *s);
}
