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

#ifdef __cplusplus
extern "C" {
#endif

/* Frees the arrays and zeroes the struct; safe on a zeroed mesh. */
void rt_mesh_free(rt_mesh *m);

/* Axis-aligned bounds of all vertices (lo = hi = 0 for an empty mesh). */
void rt_mesh_bounds(const rt_mesh *m, rt_vec3 *lo, rt_vec3 *hi);

/* 64-bit FNV-1a hash (Fowler/Noll/Vo) of the counts, vertex bits and indices:
 * equal meshes hash equal; used to check determinism. */
uint64_t rt_mesh_hash(const rt_mesh *m);

/* Unit geometric normal of triangle `prim`, n = normalize(cross(v1-v0, v2-v0))
 * (vertex order as stored); (0,0,0) for a degenerate triangle. */
rt_vec3 rt_mesh_tri_normal(const rt_mesh *m, uint32_t prim);

#ifdef __cplusplus
}
#endif

#endif
