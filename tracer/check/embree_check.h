/* embree_check.h — Embree 3 (C API, Debian libembree-dev) as the functional
 * reference: the same mesh in an Embree scene, rtcIntersect1 per ray (and
 * rtcOccluded1 per occlusion ray), and the classification of every
 * difference from our closest hit (or occlusion answer).
 *
 * Contract: the Embree device runs single-threaded ("threads=1") so results
 * and timings are deterministic and comparable with ours. Ray convention: we
 * accept tmin < t < tmax, Embree tnear <= t <= tfar, so rays are passed as
 * tnear = next float above tmin, tfar = next float below tmax (the same set
 * of float distances). RT_EMBREE_ROBUST sets RTC_SCENE_FLAG_ROBUST (the check
 * uses it: watertight triangle and conservative box tests, so the remaining
 * differences are ours); the benchmark times Embree's default (fast) mode.
 *
 * Classification of (ours, Embree) for one ray (rt_embree_classify):
 *   SAME      same primitive (or both miss) and t = t_e up to float rounding:
 *             |t - t_e| <= 1e-5 max(t, t_e), or within the float error bound
 *             of Wald's distance (absolute, ~eps x coordinate magnitude /
 *             cos(incidence): short bounce rays, grazing hits). The tally
 *             counts the bit-identical subset (exact_t) and the one needing
 *             the error bound (t_bound)
 *   TIE       different primitives whose exact (double) ray-plane distances
 *             agree within 1e-6 relative: a hit on (or, within our edge
 *             rounding, next to) a shared edge or vertex
 *   COPLANAR  the same, the two triangles lie in one plane (every vertex
 *             of one within 4 float ulps of the largest coordinate of the
 *             other's plane) and the hit point is inside both (beyond the
 *             error bound below): overlapping coplanar faces, e.g. the
 *             duplicated double-sided walls of real scenes; either answer is
 *             right
 *   GAP       Embree hits P, our Wald test rejects P, and the exact hit point
 *             on P lies within the float error bound of Wald's edge functions
 *             of an edge of P: the watertightness gap of Wald's test
 *   EDGE      we hit Q, which Embree does not report at that distance, and the
 *             exact hit point on Q lies within that error bound of an edge
 *             (our edge test accepted a point just outside by rounding)
 *   T_ROUND   two primitives at different exact distances ordered the
 *             other way by us, within the float error bounds of Wald's
 *             distance computation (depth order flipped by rounding)
 *   OTHER     none of these: unexplained (a bug somewhere) */
#ifndef RTSIM_TRACER_EMBREE_CHECK_H
#define RTSIM_TRACER_EMBREE_CHECK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "tracer/io/mesh.h"
#include "tracer/trace/ray.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rt_embree rt_embree;

enum { RT_EMBREE_ROBUST = 1 };

/* Builds the Embree scene of mesh (copied). NULL with a message on failure. */
rt_embree *rt_embree_create(const rt_mesh *mesh, unsigned flags, char *err, size_t errlen);
void rt_embree_free(rt_embree *e);
/* Process CPU seconds rt_embree_create spent in rtcCommitScene (Embree's
 * build; single-threaded, so equal to wall time on an idle machine). */
double rt_embree_build_seconds(const rt_embree *e);

/* Embree's closest hit for one ray (prim = RT_NO_HIT on a miss; t = tmax then). */
void rt_embree_intersect(const rt_embree *e, const rt_ray *ray, rt_hit *hit);

typedef enum rt_embree_cause {
    RT_EMBREE_SAME,
    RT_EMBREE_TIE,
    RT_EMBREE_COPLANAR,
    RT_EMBREE_GAP,
    RT_EMBREE_EDGE,
    RT_EMBREE_T_ROUND,
    RT_EMBREE_OTHER,
    RT_EMBREE_CAUSES
} rt_embree_cause;

const char *rt_embree_cause_name(rt_embree_cause c);

/* Classifies our hit against Embree's for ray (see the table above). */
rt_embree_cause rt_embree_classify(const rt_mesh *mesh, const rt_ray *ray, const rt_hit *ours, const rt_hit *ref);

typedef struct rt_embree_tally {
    uint64_t rays;
    uint64_t exact_t;   /* SAME with bit-identical t */
    uint64_t t_bound;   /* SAME with |dt| > 1e-5 relative, within the error bound */
    uint64_t cause[RT_EMBREE_CAUSES];
} rt_embree_tally;

/* Occlusion rays (ray->occlusion, traverse.h any-hit): only the answer
 * occluded / not occluded is compared, with Embree's rtcOccluded1 on the
 * same interval. When the answers differ, Embree's closest hit (ref, from
 * rt_embree_intersect) names a primitive it found, and the cause is:
 *   EDGE      we are occluded by Q, Embree is not, and Q's exact hit point
 *             is within the error bound of an edge of Q
 *   GAP       Embree is occluded by P, our Wald test rejects P, and P's exact
 *             hit point is within the error bound of an edge of P
 *   T_ROUND   the exact distance of our Q (or of Embree's P, rejected by
 *             our test) is within the error bound of tmin or tmax: the ray's
 *             end cuts the triangle, rounding decides
 *   OTHER     none of these (for instance our test accepts P: the traversal
 *             lost it): unexplained
 * An agreeing answer is SAME (exact_t and t_bound are not counted). */
bool rt_embree_occluded(const rt_embree *e, const rt_ray *ray);
rt_embree_cause rt_embree_classify_occlusion(const rt_mesh *mesh, const rt_ray *ray, const rt_hit *ours,
                                             bool embree_occluded, const rt_hit *ref);
/* rtcOccluded1 for ray, rtcIntersect1 too when the answers differ, the
 * classification added to the tally; returns the cause. */
rt_embree_cause rt_embree_tally_add_occlusion(rt_embree_tally *t, const rt_embree *e, const rt_mesh *mesh,
                                              const rt_ray *ray, const rt_hit *ours);

/* Adds one ray's comparison to the tally; returns its cause. */
rt_embree_cause rt_embree_tally_add(rt_embree_tally *t, const rt_mesh *mesh, const rt_ray *ray, const rt_hit *ours,
                                    const rt_hit *ref);

#ifdef __cplusplus
}
#endif

#endif
