/* embree_check.c — see embree_check.h. The error bounds follow the standard
 * model of float arithmetic (|fl(x op y) - x op y| <= eps |x op y|, Higham,
 * "Accuracy and Stability of Numerical Algorithms", ch. 2), summed term by
 * term over rt_wald_test's expressions and doubled to cover Embree's own
 * rounding on the other side of the comparison. */
#include "tracer/check/embree_check.h"

#include <embree3/rtcore.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tracer/bvh/bvh_layout.h"
#include "tracer/io/scene_error.h"
#include "tracer/bvh/wald_tri.h"

struct rt_embree {
    RTCDevice device;
    RTCScene scene;
    double build_seconds;
};

rt_embree *rt_embree_create(const rt_mesh *mesh, unsigned flags, char *err, size_t errlen)
{
    rt_embree *e = calloc(1, sizeof *e);
    if (!e) {
        rt_scene_errorf(err, errlen, "Embree: out of memory");
        return NULL;
    }
    e->device = rtcNewDevice("threads=1");
    if (!e->device) {
        rt_scene_errorf(err, errlen, "Embree: rtcNewDevice failed (error %d)", (int)rtcGetDeviceError(NULL));
        free(e);
        return NULL;
    }
    e->scene = rtcNewScene(e->device);
    rtcSetSceneFlags(e->scene, (flags & RT_EMBREE_ROBUST) ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
    RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    /* Embree-owned buffers: Embree may read 16 bytes past the last vertex. */
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                       mesh->nverts);
    unsigned *ix = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                           mesh->ntris);
    if (!v || !ix) {
        rt_scene_errorf(err, errlen, "Embree: cannot allocate buffers for %u vertices, %u triangles (error %d)",
                        mesh->nverts, mesh->ntris, (int)rtcGetDeviceError(e->device));
        rtcReleaseGeometry(g);
        rt_embree_free(e);
        return NULL;
    }
    for (uint32_t i = 0; i < mesh->nverts; i++)
        v[3 * i] = mesh->verts[i].x, v[3 * i + 1] = mesh->verts[i].y, v[3 * i + 2] = mesh->verts[i].z;
    memcpy(ix, mesh->tris, 3 * sizeof(unsigned) * (size_t)mesh->ntris);
    rtcCommitGeometry(g);
    rtcAttachGeometry(e->scene, g);
    rtcReleaseGeometry(g);
    struct timespec t0, t1;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t0);
    rtcCommitScene(e->scene);
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t1);
    e->build_seconds = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    const enum RTCError code = rtcGetDeviceError(e->device);
    if (code != RTC_ERROR_NONE) {
        rt_scene_errorf(err, errlen, "Embree: building the scene failed (error %d)", (int)code);
        rt_embree_free(e);
        return NULL;
    }
    return e;
}

void rt_embree_free(rt_embree *e)
{
    if (!e)
        return;
    if (e->scene)
        rtcReleaseScene(e->scene);
    if (e->device)
        rtcReleaseDevice(e->device);
    free(e);
}

double rt_embree_build_seconds(const rt_embree *e) { return e->build_seconds; }

void rt_embree_intersect(const rt_embree *e, const rt_ray *ray, rt_hit *hit)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRayHit rh;
    rh.ray.org_x = ray->org.x, rh.ray.org_y = ray->org.y, rh.ray.org_z = ray->org.z;
    rh.ray.dir_x = ray->dir.x, rh.ray.dir_y = ray->dir.y, rh.ray.dir_z = ray->dir.z;
    rh.ray.tnear = nextafterf(ray->tmin, INFINITY);
    rh.ray.tfar = nextafterf(ray->tmax, -INFINITY);
    rh.ray.time = 0.0f;
    rh.ray.mask = UINT32_MAX;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(e->scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
        hit->prim = RT_NO_HIT;
        hit->t = ray->tmax;
        hit->u = hit->v = 0.0f;
    } else {
        hit->prim = rh.hit.primID;
        hit->t = rh.ray.tfar;
        hit->u = rh.hit.u;
        hit->v = rh.hit.v;
    }
}

bool rt_embree_occluded(const rt_embree *e, const rt_ray *ray)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRay r;
    r.org_x = ray->org.x, r.org_y = ray->org.y, r.org_z = ray->org.z;
    r.dir_x = ray->dir.x, r.dir_y = ray->dir.y, r.dir_z = ray->dir.z;
    r.tnear = nextafterf(ray->tmin, INFINITY);   /* the same open interval as rt_embree_intersect */
    r.tfar = nextafterf(ray->tmax, -INFINITY);
    r.time = 0.0f;
    r.mask = UINT32_MAX;
    r.id = 0;
    r.flags = 0;
    rtcOccluded1(e->scene, &ctx, &r);
    return r.tfar == -INFINITY;   /* Embree's mark of an occluded ray */
}

const char *rt_embree_cause_name(rt_embree_cause c)
{
    static const char *names[RT_EMBREE_CAUSES] = {"same", "tie", "coplanar", "gap", "edge", "t_round", "other"};
    return (unsigned)c < RT_EMBREE_CAUSES ? names[c] : "?";
}

/* Exact-ish (double) analysis of ray against primitive p: plane distance,
 * barycentrics at that point, and float error bounds of rt_wald_test. */
typedef struct prim_exact {
    double t, beta, gamma;   /* t = NAN for a ray parallel to the plane */
    double err_bary, err_t;
} prim_exact;

static prim_exact analyse(const rt_mesh *m, const rt_ray *r, uint32_t p)
{
    prim_exact x = {NAN, NAN, NAN, 0.0, 0.0};
    const uint32_t *ix = m->tris + 3 * (size_t)p;
    const rt_vec3 va = m->verts[ix[0]], vb = m->verts[ix[1]], vc = m->verts[ix[2]];
    const double A[3] = {va.x, va.y, va.z};
    const double e1[3] = {(double)vb.x - va.x, (double)vb.y - va.y, (double)vb.z - va.z};
    const double e2[3] = {(double)vc.x - va.x, (double)vc.y - va.y, (double)vc.z - va.z};
    const double O[3] = {r->org.x, r->org.y, r->org.z}, D[3] = {r->dir.x, r->dir.y, r->dir.z};
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                         e1[0] * e2[1] - e1[1] * e2[0]};
    const double den = n[0] * D[0] + n[1] * D[1] + n[2] * D[2];
    if (den == 0.0)
        return x;
    x.t = (n[0] * (A[0] - O[0]) + n[1] * (A[1] - O[1]) + n[2] * (A[2] - O[2])) / den;
    rt_tri48 w;
    rt_wald_precompute(va, vb, vc, p, &w);
    const int k = (int)w.k, u = (k + 1) % 3, v = (k + 2) % 3;
    const double det = n[k];
    const double pu = O[u] + x.t * D[u] - A[u], pv = O[v] + x.t * D[v] - A[v];
    x.beta = (pu * e2[v] - pv * e2[u]) / det;
    x.gamma = (e1[u] * pv - e1[v] * pu) / det;
    /* float error bounds of rt_wald_test's expressions (a few eps per term) */
    const double eps = 4.0 * FLT_EPSILON;
    const double nd = 1.0 / fabs((double)D[k] + w.n_u * D[u] + w.n_v * D[v]);
    x.err_t = eps * (fabs(w.n_d) + fabs(O[k]) + fabs(w.n_u * O[u]) + fabs(w.n_v * O[v])) * nd
            + eps * fabs(x.t) * (1.0 + nd * (fabs(D[k]) + fabs(w.n_u * D[u]) + fabs(w.n_v * D[v])));
    const double hu = O[u] + x.t * D[u], hv = O[v] + x.t * D[v];
    const double err_hu = eps * (fabs(O[u]) + fabs(x.t * D[u])) + fabs(D[u]) * x.err_t;
    const double err_hv = eps * (fabs(O[v]) + fabs(x.t * D[v])) + fabs(D[v]) * x.err_t;
    const double eb = eps * (fabs(hv * w.b_nu) + fabs(hu * w.b_nv) + fabs(w.b_d)) + fabs(w.b_nu) * err_hv
                    + fabs(w.b_nv) * err_hu;
    const double ec = eps * (fabs(hu * w.c_nu) + fabs(hv * w.c_nv) + fabs(w.c_d)) + fabs(w.c_nu) * err_hu
                    + fabs(w.c_nv) * err_hv;
    x.err_bary = 2.0 * (eb + ec);
    x.err_t *= 2.0;
    return x;
}

static bool near_edge(const prim_exact *x)
{
    if (isnan(x->t))
        return false;
    const double a = 1.0 - x->beta - x->gamma;
    const double m = fmin(a, fmin(x->beta, x->gamma));
    return fabs(m) <= x->err_bary;
}

/* The exact hit point is inside the triangle by more than the error bound. */
static bool inside(const prim_exact *x)
{
    if (isnan(x->t))
        return false;
    return fmin(1.0 - x->beta - x->gamma, fmin(x->beta, x->gamma)) > x->err_bary;
}

/* Whether q's vertices lie in p's plane up to float rounding of coordinates. */
static bool coplanar(const rt_mesh *m, uint32_t p, uint32_t q)
{
    const uint32_t *ip = m->tris + 3 * (size_t)p, *iq = m->tris + 3 * (size_t)q;
    double P[3][3], Q[3][3], scale = 0.0;
    for (int k = 0; k < 3; k++) {
        const rt_vec3 a = m->verts[ip[k]], b = m->verts[iq[k]];
        P[k][0] = a.x, P[k][1] = a.y, P[k][2] = a.z;
        Q[k][0] = b.x, Q[k][1] = b.y, Q[k][2] = b.z;
        for (int c = 0; c < 3; c++)
            scale = fmax(scale, fmax(fabs(P[k][c]), fabs(Q[k][c])));
    }
    const double e1[3] = {P[1][0] - P[0][0], P[1][1] - P[0][1], P[1][2] - P[0][2]};
    const double e2[3] = {P[2][0] - P[0][0], P[2][1] - P[0][1], P[2][2] - P[0][2]};
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (len == 0.0)
        return false;
    const double tol = 4.0 * FLT_EPSILON * scale;
    for (int k = 0; k < 3; k++) {
        const double d = (n[0] * (Q[k][0] - P[0][0]) + n[1] * (Q[k][1] - P[0][1]) + n[2] * (Q[k][2] - P[0][2])) / len;
        if (fabs(d) > tol)
            return false;
    }
    return true;
}

static float wald_prim(const rt_mesh *m, const rt_ray *r, uint32_t p, bool *hit)
{
    rt_tri48 w;
    rt_wald_precompute_prim(m, p, &w);
    const float org[3] = {r->org.x, r->org.y, r->org.z}, dir[3] = {r->dir.x, r->dir.y, r->dir.z};
    float t = NAN, u, v;
    *hit = rt_wald_test(&w, org, dir, r->tmin, r->tmax, &t, &u, &v);
    return t;
}

rt_embree_cause rt_embree_classify(const rt_mesh *mesh, const rt_ray *ray, const rt_hit *ours, const rt_hit *ref)
{
    const bool oh = ours->prim != RT_NO_HIT, eh = ref->prim != RT_NO_HIT;
    if (!oh && !eh)
        return RT_EMBREE_SAME;
    if (oh && eh && ours->prim == ref->prim) {
        const double dt = fabs((double)ours->t - ref->t);
        if (dt <= 1e-5 * fmax(fabs(ours->t), fabs(ref->t)))
            return RT_EMBREE_SAME;
        const prim_exact x = analyse(mesh, ray, ours->prim);
        return dt <= x.err_t ? RT_EMBREE_SAME : RT_EMBREE_OTHER;
    }
    prim_exact xo = {NAN, NAN, NAN, 0, 0}, xe = xo;
    if (oh)
        xo = analyse(mesh, ray, ours->prim);
    if (eh)
        xe = analyse(mesh, ray, ref->prim);
    if (oh && eh && !isnan(xo.t) && !isnan(xe.t) && fabs(xo.t - xe.t) <= 1e-6 * fmax(fabs(xo.t), fabs(xe.t)))
        return coplanar(mesh, ours->prim, ref->prim) && inside(&xo) && inside(&xe) ? RT_EMBREE_COPLANAR
                                                                                     : RT_EMBREE_TIE;
    if (eh && (!oh || ref->t < ours->t)) {
        /* Embree found P before our hit (or we missed): why did we not take P? */
        bool whit;
        const float tw = wald_prim(mesh, ray, ref->prim, &whit);
        if (!whit)
            return near_edge(&xe) ? RT_EMBREE_GAP : RT_EMBREE_OTHER;
        if (!oh || tw < ours->t)
            return RT_EMBREE_OTHER;   /* our test hits P closer: traversal lost it */
        /* our arithmetic puts Q no farther than P */
        if (xo.t <= xe.t)
            return near_edge(&xo) ? RT_EMBREE_EDGE : RT_EMBREE_OTHER;   /* Q truly first: Embree missed Q */
        return (xo.t - xe.t) <= xo.err_t + xe.err_t ? RT_EMBREE_T_ROUND : RT_EMBREE_OTHER;
    }
    /* we hit Q before Embree's hit (or Embree missed) */
    if (eh && !isnan(xe.t) && !isnan(xo.t) && xe.t < xo.t) {
        /* P truly first: our distance order is off, or our test dropped P */
        bool whit;
        (void)wald_prim(mesh, ray, ref->prim, &whit);
        if (!whit)
            return near_edge(&xe) ? RT_EMBREE_GAP : RT_EMBREE_OTHER;
        return (xo.t - xe.t) <= xo.err_t + xe.err_t ? RT_EMBREE_T_ROUND : RT_EMBREE_OTHER;
    }
    return near_edge(&xo) ? RT_EMBREE_EDGE : RT_EMBREE_OTHER;
}

/* The exact distance x->t lies within the error bound of the ray's ends. */
static bool near_ends(const rt_ray *r, const prim_exact *x)
{
    if (isnan(x->t))
        return false;
    return fabs(x->t - (double)r->tmax) <= x->err_t || fabs(x->t - (double)r->tmin) <= x->err_t;
}

rt_embree_cause rt_embree_classify_occlusion(const rt_mesh *mesh, const rt_ray *ray, const rt_hit *ours,
                                             bool embree_occluded, const rt_hit *ref)
{
    const bool occ = ours->prim != RT_NO_HIT;
    if (occ == embree_occluded)
        return RT_EMBREE_SAME;
    if (occ) {
        /* we found Q in the interval, Embree found nothing */
        const prim_exact xo = analyse(mesh, ray, ours->prim);
        if (near_edge(&xo))
            return RT_EMBREE_EDGE;
        return near_ends(ray, &xo) ? RT_EMBREE_T_ROUND : RT_EMBREE_OTHER;
    }
    /* Embree found P, we found nothing */
    if (ref->prim == RT_NO_HIT || ref->prim >= mesh->ntris)
        return RT_EMBREE_OTHER;
    bool whit;
    (void)wald_prim(mesh, ray, ref->prim, &whit);
    if (whit)
        return RT_EMBREE_OTHER;   /* our test takes P: the traversal lost it */
    const prim_exact xe = analyse(mesh, ray, ref->prim);
    if (near_edge(&xe))
        return RT_EMBREE_GAP;
    return near_ends(ray, &xe) ? RT_EMBREE_T_ROUND : RT_EMBREE_OTHER;
}

rt_embree_cause rt_embree_tally_add_occlusion(rt_embree_tally *t, const rt_embree *e, const rt_mesh *mesh,
                                              const rt_ray *ray, const rt_hit *ours)
{
    const bool eo = rt_embree_occluded(e, ray);
    rt_hit ref = {ray->tmax, 0.0f, 0.0f, RT_NO_HIT};
    if (eo != (ours->prim != RT_NO_HIT))
        rt_embree_intersect(e, ray, &ref);
    const rt_embree_cause c = rt_embree_classify_occlusion(mesh, ray, ours, eo, &ref);
    t->rays++;
    t->cause[c]++;
    return c;
}

rt_embree_cause rt_embree_tally_add(rt_embree_tally *t, const rt_mesh *mesh, const rt_ray *ray, const rt_hit *ours,
                                    const rt_hit *ref)
{
    const rt_embree_cause c = rt_embree_classify(mesh, ray, ours, ref);
    t->rays++;
    t->cause[c]++;
    if (c == RT_EMBREE_SAME) {
        const double dt = fabs((double)ours->t - ref->t);
        if (ours->t == ref->t)
            t->exact_t++;
        else if (dt > 1e-5 * fmax(fabs(ours->t), fabs(ref->t)))
            t->t_bound++;
    }
    return c;
}
