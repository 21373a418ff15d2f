/* builtin.h — procedural scenes generated in code, so everything runs with no
 * download. Each imitates one of the paper's scenes (Viitanen et al. 2016,
 * section 4) at small size (tens of thousands of triangles):
 *   interior  architectural hall with columns and arches (Crytek Sponza: large triangles)
 *   hairball  dense tangle of thin tubes (Hairball: triangle-heavy)
 *   city      voxel city of boxes, seen from above (Rungholt: box-heavy)
 *   forest    ground with trees and many leaf quads (Fairy Forest: outdoor foliage)
 * Contract: output is bit-for-bit deterministic (fixed-seed PCG32 and
 * libm-free trigonometry), +Y up, and comes with two default views. */
#ifndef RTSIM_TRACER_BUILTIN_H
#define RTSIM_TRACER_BUILTIN_H

#include <stdbool.h>
#include <stddef.h>

#include "tracer/io/mesh.h"
#include "tracer/io/view.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Number of built-in scenes and the name of the i-th (i < count). */
unsigned rt_builtin_count(void);
const char *rt_builtin_name(unsigned i);
/* True when name is a built-in scene name. */
bool rt_builtin_exists(const char *name);

/* Generates built-in scene `name` into *mesh and its default views into
 * *views (either may be NULL). False with a message listing the names when
 * name is unknown, or on allocation failure. */
bool rt_builtin_generate(const char *name, rt_mesh *mesh, rt_views *views,
                         char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif
