/* builtin_geom.h — internal: building blocks of the built-in scenes.
 *
 * Contract: a growing mesh whose appends never fail visibly; an allocation
 * failure sets `oom` and later appends do nothing (checked once at the end).
 * Trigonometry comes from det_math.h (no libm), so generated coordinates are
 * bit-for-bit identical on every IEEE-754 platform. */
#ifndef RTSIM_TRACER_BUILTIN_GEOM_H
#define RTSIM_TRACER_BUILTIN_GEOM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "tracer/util/det_math.h"
#include "tracer/io/mesh.h"
#include "tracer/io/view.h"

#define RT_PI 3.14159265358979323846

typedef struct rt_mesh_builder {
    rt_mesh m;
    size_t vcap, tcap;
    bool oom;
} rt_mesh_builder;


uint32_t rt_mb_vert(rt_mesh_builder *b, double x, double y, double z);
void rt_mb_tri(rt_mesh_builder *b, uint32_t a, uint32_t c, uint32_t d);
/* Quad p0 p1 p2 p3 (in order around it) as triangles (p0,p1,p2), (p0,p2,p3). */
void rt_mb_quad(rt_mesh_builder *b, const double p0[3], const double p1[3], const double p2[3],
                const double p3[3]);
/* Axis-aligned box: 8 vertices, 12 triangles. */
void rt_mb_box(rt_mesh_builder *b, double x0, double y0, double z0, double x1, double y1, double z1);
/* Vertical cylinder (axis +Y) with `sides` facets and `rings` height steps,
 * no caps: 2*sides*rings triangles. */
void rt_mb_cylinder(rt_mesh_builder *b, double cx, double y0, double cz, double radius,
                    double height, int sides, int rings);
/* Vertical cone from radius r at y0 to a point at y0+height: `sides` triangles. */
void rt_mb_cone(rt_mesh_builder *b, double cx, double y0, double cz, double radius, double height,
                int sides);

/* Appends a view (name unique) to vs; sets oom on failure. */
void rt_mb_view(rt_mesh_builder *b, rt_views *vs, const char *name, double ex, double ey,
                double ez, double ax, double ay, double az, double fov);

/* The four generators (builtin_<name>.c); *views may be NULL. */
void rt_builtin_interior(rt_mesh_builder *b, rt_views *views);
void rt_builtin_hairball(rt_mesh_builder *b, rt_views *views);
void rt_builtin_city(rt_mesh_builder *b, rt_views *views);
void rt_builtin_forest(rt_mesh_builder *b, rt_views *views);

#endif
