/* mesh.h — a triangle scene in memory, as every loader and generator returns it.
 *
 * Contract: positions are float xyz triples; triangles index them (0-based,
 * all indices < nverts, checked by the producer). Triangle i of the mesh is
 * "primitive i" everywhere else (BVH leaves, hits, Embree's primID), so the
 * order is part of the result and producers must be deterministic. Degenerate
 * triangles are kept (they never hit) so primitive ids match the file. */
#ifndef RTSIM_TRACER_MESH_H
#define RTSIM_TRACER_MESH_H

#include <stddef.h>
#include <stdint.h>

typedef struct rt_vec3 {
    float x, y, z;
} rt_vec3;

typedef struct rt_mesh {
    rt_vec3 *verts;      /* nverts positions */
    uint32_t *tris;      /* 3 * ntris vertex indices */
    uint32_t nverts;
    uint32_t ntris;
} rt_mesh;

/* Frees the arrays and zeroes the struct; safe on a zeroed mesh. */
void rt_mesh_free(rt_mesh *m);

#endif
