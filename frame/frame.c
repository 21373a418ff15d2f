/* frame.c — the tracer-to-model bridge (contract in frame.h). */
#include "frame/frame.h"


void rtsim_to_model(const rt_ray *r, accel_ray_in *o)
{
    o->org[0] = r->org.x, o->org[1] = r->org.y, o->org[2] = r->org.z;
    o->dir[0] = r->dir.x, o->dir[1] = r->dir.y, o->dir[2] = r->dir.z;
    o->tmin = r->tmin, o->tmax = r->tmax;
    o->pixel = r->pixel;
    o->bounce = r->bounce;
    o->occlusion = r->occlusion;
}

void rtsim_from_model(const accel_ray_in *i, rt_ray *r)
{
    r->org = (rt_vec3){i->org[0], i->org[1], i->org[2]};
    r->dir = (rt_vec3){i->dir[0], i->dir[1], i->dir[2]};
    r->tmin = i->tmin, r->tmax = i->tmax;
    r->pixel = i->pixel;
    r->bounce = i->bounce;
    r->occlusion = i->occlusion;
}

rt_ray rtsim_frame_camera_ray(const rtsim_frame *f, uint64_t k)
{
    const uint32_t p = rtsim_frame_pixel(f, k);
    return rt_camera_primary_ray(&f->cam, p % f->cam.width, p / f->cam.width);
}

void rtsim_frame_primary(void *user, uint64_t i, accel_ray_in *out)
{
    rtsim_frame *f = user;
    rt_ray r = rtsim_frame_camera_ray(f, i);
    rtsim_to_model(&r, out);
}

bool rtsim_frame_bounce(void *user, const accel_ray_in *in, const accel_hit *hit, accel_ray_in *out)
{
    rtsim_frame *f = user;
    if (!f->diffuse)
        return false;
    rt_ray r, next;
    rtsim_from_model(in, &r);
    rt_hit h = {hit->t, hit->u, hit->v, hit->prim};
    if (!rt_bounce_ray(f->mesh, &r, &h, f->seed, f->max_bounces, &next))
        return false;
    rtsim_to_model(&next, out);
    return true;
}

void rtsim_frame_complete(void *user, uint32_t uid, const accel_ray_in *in, const accel_hit *hit,
                                        uint64_t admit, uint64_t done, uint32_t visits, uint32_t tri_tests,
                                        bool failed)
{
    (void)visits, (void)tri_tests;
    rtsim_frame *f = user;
    if (f->pixel_cycles && in->pixel < f->cam.width * f->cam.height)
        f->pixel_cycles[in->pixel] += (float)(done - admit);
    if (f->hook) {
        rt_ray r;
        rtsim_from_model(in, &r);
        rt_hit h = {hit->t, hit->u, hit->v, hit->prim};
        f->hook(f->hook_user, uid, &r, &h, admit, done, failed);
    }
}

/* The reference traversal's parameters as the machine runs it (frame.h). */
void rtsim_trv_params(const accel_params *ap, int width, rt_trv_params *out)
{
    rt_trv_params_default(out, width);
    out->stack_depth = (int)ap->trv.core.stack_depth;
    out->distance_cull = ap->trv.core.distance_cull;   /* accel_config: auto = N > 2 */
}

void rtsim_bvh_params(const rtcfg *cfg, rt_bvh_params *out)
{
    rt_bvh_params_default(out);
    out->width = (int)rtcfg_int(cfg, "machine.branching");
    out->builder = rtcfg_enum(cfg, "bvh.builder") == 1 ? RT_BUILD_WALD : RT_BUILD_COLLAPSE;
    out->leaf_size = (int)rtcfg_int(cfg, "bvh.leaf_size");
    out->bins = (int)rtcfg_int(cfg, "bvh.bins");
    out->cost_node = (float)rtcfg_real(cfg, "bvh.cost_node");
    out->cost_tri = (float)rtcfg_real(cfg, "bvh.cost_tri");
}

/* The model's view of a tracer memory image. */
accel_image rtsim_image(const rt_bvh_image *img)
{
    accel_image a = {img->bytes, img->size, img->node_base, img->tri_base, img->width, img->node_bytes, img->nnodes,
                     img->ntris};
    return a;
}

bool rtsim_pixel_order(const rtcfg *cfg, uint32_t width, uint32_t height, uint32_t **order, char *err,
                       size_t errlen)
{
    *order = NULL;
    if (!cfg)
        return true;
    return rt_pixel_order_make((rt_pixel_order_kind)rtcfg_enum(cfg, "sched.pixel_order"),
                               (uint32_t)rtcfg_int(cfg, "sched.tile"), width, height, order, err, errlen);
}

/* Sets up the source; keep_pixels allocates the heatmap buffer. */
bool rtsim_frame_init(rtsim_frame *f, const rtcfg *cfg, const rt_mesh *mesh, const rt_view *view, uint32_t width,
                                    uint32_t height, bool diffuse, uint32_t max_bounces, uint64_t seed,
                                    bool keep_pixels, accel_source *src, char *err, size_t errlen)
{
    memset(f, 0, sizeof *f);
    if (!rt_camera_init(&f->cam, view, width, height, err, errlen))
        return false;
    if (!rtsim_pixel_order(cfg, width, height, &f->order, err, errlen))
        return false;
    f->mesh = mesh;
    f->diffuse = diffuse;
    f->max_bounces = max_bounces;
    f->seed = seed;
    if (keep_pixels) {
        f->pixel_cycles = calloc((size_t)width * height, sizeof *f->pixel_cycles);
        if (!f->pixel_cycles) {
            snprintf(err, errlen, "out of memory for a %ux%u heatmap", width, height);
            rtsim_frame_free(f);
            return false;
        }
    }
    memset(src, 0, sizeof *src);
    src->user = f;
    src->primary_count = (uint64_t)width * height;
    src->primary = rtsim_frame_primary;
    src->bounce = rtsim_frame_bounce;
    src->complete = rtsim_frame_complete;
    return true;
}

/* Occlusion ray i: sample i % samples of the i / samples-th hit pixel. */
void rtsim_frame_occlusion_ray(void *user, uint64_t i, accel_ray_in *out)
{
    rtsim_frame *f = user;
    const uint32_t j = (uint32_t)(i / f->ao_samples), k = (uint32_t)(i % f->ao_samples);
    const uint32_t px = f->occ_pixel[j] % f->cam.width, py = f->occ_pixel[j] / f->cam.width;
    const rt_ray prim = rt_camera_primary_ray(&f->cam, px, py);
    rt_ray r;
    (void)rt_ao_ray(f->mesh, &prim, &f->occ_hit[j], f->seed, k, f->ao_tmax, &r);   /* true: checked at set-up */
    rtsim_to_model(&r, out);
}

/* Turns an initialised frame into an occlusion run: traces the primary rays
 * on the host (img, the reference traversal) and makes src feed their
 * `samples` AO rays each (tmax rt_ao_distance) instead of primary rays.
 * False with a message on a stack overflow or out of memory. */
bool rtsim_frame_occlusion(rtsim_frame *f, const rt_bvh_image *img, uint32_t samples,
                                         accel_source *src, char *err, size_t errlen)
{
    const uint32_t n = f->cam.width * f->cam.height;
    f->occ_pixel = malloc((size_t)(n ? n : 1) * sizeof *f->occ_pixel);
    f->occ_hit = malloc((size_t)(n ? n : 1) * sizeof *f->occ_hit);
    if (!f->occ_pixel || !f->occ_hit) {
        snprintf(err, errlen, "out of memory for the primary hits of %u pixels", n);
        return false;
    }
    f->ao_samples = samples ? samples : 1;
    f->ao_tmax = rt_ao_distance(f->mesh);
    rt_trv_params tp;
    rt_trv_params_default(&tp, img->width);
    tp.stack_depth = 4096;   /* host-side pre-pass: the largest stack (hits do not depend on it) */
    f->occ_n = 0;
    for (uint32_t k = 0; k < n; k++) {   /* the hit pixels in the frame's pixel order */
        const uint32_t p = rtsim_frame_pixel(f, k);
        const rt_ray prim = rtsim_frame_camera_ray(f, k);
        rt_hit h;
        rt_ray probe;
        if (!rt_trace_ray(img, &tp, &prim, &h, NULL, NULL, NULL)) {
            snprintf(err, errlen, "occlusion rays: stack overflow tracing the primary ray of pixel %u", p);
            return false;
        }
        if (rt_ao_ray(f->mesh, &prim, &h, f->seed, 0, f->ao_tmax, &probe)) {   /* any k: same condition */
            f->occ_pixel[f->occ_n] = p;
            f->occ_hit[f->occ_n++] = h;
        }
    }
    src->occlusion = true;
    src->primary_count = (uint64_t)f->occ_n * f->ao_samples;
    src->primary = rtsim_frame_occlusion_ray;
    return true;
}

void rtsim_frame_free(rtsim_frame *f)
{
    free(f->pixel_cycles);
    free(f->occ_pixel);
    free(f->occ_hit);
    free(f->order);
    f->order = NULL;
    f->pixel_cycles = NULL;
    f->occ_pixel = NULL;
    f->occ_hit = NULL;
}
