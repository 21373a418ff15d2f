/* frame.h — the bridge between the software ray tracer (tracer/) and
 * the accelerator model (model/), shared by cli/rtsim.c and the system
 * testbench: the model may not include the tracer, so the rays are made here
 * and handed in through accel_source callbacks.
 *
 * Contract: rtsim_frame_init() loads nothing itself; it takes a loaded scene
 * and a built BVH image and a camera, and provides
 *   - primary rays in the machine's pixel order (sched.pixel_order and
 *     sched.tile, tracer/trace/pixel_order.h): primary ray k is the camera ray of
 *     pixel rtsim_frame_pixel(f, k); everything that counts rays "in order"
 *     (the fidelity levels' bands, windows and lattices) counts these k;
 *   - for diffuse runs the bounce ray of each completed ray (bounce.h, the
 *     same seed convention as the tracer, so paths do not depend on the order
 *     the hardware completes rays in),
 *   - for occlusion runs (rtsim_frame_occlusion) the occlusion rays only:
 *     the primary rays are traced on the host with the reference traversal
 *     and the model gets their AO rays (occlusion.h; samples consecutive per
 *     pixel, pixels in the frame's pixel order), the rays of rt_ray_set_occlusion,
 *   - per-pixel simulated cycles (sum of its rays' latencies) for heatmaps,
 *   - an optional per-ray completion hook.
 * A library of its own (frame/ -> libframe.a): rtsim, the system testbench
 * and the fuzz harness link it; it may use the tracer and the model, and
 * nothing else uses it. */
#ifndef RTSIM_FRAME_FRAME_H
#define RTSIM_FRAME_FRAME_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/accel_config.h"
#include "model/ray/accel_ray.h"
#include "model/ray/scheduler.h"
#include "tracer/trace/bounce.h"
#include "tracer/bvh/bvh.h"
#include "tracer/trace/camera.h"
#include "tracer/trace/occlusion.h"
#include "tracer/trace/pixel_order.h"
#include "tracer/trace/ray.h"
#include "tracer/io/scene.h"
#include "tracer/trace/traverse.h"

typedef void (*rtsim_complete_hook)(void *user, uint32_t uid, const rt_ray *ray, const rt_hit *hit, uint64_t admit,
                                    uint64_t done, bool failed);

typedef struct rtsim_frame {
    const rt_mesh *mesh;
    rt_camera cam;
    uint32_t *order;              /* pixel of the k-th primary ray (pixel_order.h); NULL: scanline */
    bool diffuse;
    uint32_t max_bounces;
    uint64_t seed;
    float *pixel_cycles;          /* width*height, NULL when not kept */
    rtsim_complete_hook hook;
    void *hook_user;
    /* occlusion runs: the pixels whose primary ray hit (in pixel order), their hits */
    uint32_t ao_samples;
    float ao_tmax;
    uint32_t *occ_pixel;
    rt_hit *occ_hit;
    uint32_t occ_n;
} rtsim_frame;

void rtsim_to_model(const rt_ray *r, accel_ray_in *o);
void rtsim_from_model(const accel_ray_in *i, rt_ray *r);
void rtsim_frame_primary(void *user, uint64_t i, accel_ray_in *out);
bool rtsim_frame_bounce(void *user, const accel_ray_in *in, const accel_hit *hit, accel_ray_in *out);
void rtsim_frame_complete(void *user, uint32_t uid, const accel_ray_in *in, const accel_hit *hit,
                                        uint64_t admit, uint64_t done, uint32_t visits, uint32_t tri_tests,
                                        bool failed);
/* The BVH builder's parameters of machine cfg: width machine.branching,
 * the rest from its [bvh] section (model/accel_config.c). */
void rtsim_bvh_params(const rtcfg *cfg, rt_bvh_params *out);
/* The model's view of a tracer memory image. */
accel_image rtsim_image(const rt_bvh_image *img);
/* The reference traversal's parameters as the machine ap runs it (its
 * stack depth and distance stack), for a BVH of the given width. */
void rtsim_trv_params(const accel_params *ap, int width, rt_trv_params *out);
/* Sets up the source; keep_pixels allocates the heatmap buffer. The pixel
 * order comes from cfg's sched.pixel_order and sched.tile (NULL cfg:
 * scanline). */
bool rtsim_frame_init(rtsim_frame *f, const rtcfg *cfg, const rt_mesh *mesh, const rt_view *view, uint32_t width,
                                    uint32_t height, bool diffuse, uint32_t max_bounces, uint64_t seed,
                                    bool keep_pixels, accel_source *src, char *err, size_t errlen);
/* The pixel order of cfg (sched.pixel_order, sched.tile) for a width x height
 * frame, as rt_pixel_order_make() gives it (*order NULL: scanline). */
bool rtsim_pixel_order(const rtcfg *cfg, uint32_t width, uint32_t height, uint32_t **order, char *err,
                       size_t errlen);
/* The pixel (py * width + px) of the frame's k-th primary ray. */
static inline uint32_t rtsim_frame_pixel(const rtsim_frame *f, uint64_t k)
{
    return rt_pixel_at(f->order, k);
}
/* The camera ray of the frame's k-th primary ray. */
rt_ray rtsim_frame_camera_ray(const rtsim_frame *f, uint64_t k);
/* Occlusion ray i: sample i % samples of the i / samples-th hit pixel. */
void rtsim_frame_occlusion_ray(void *user, uint64_t i, accel_ray_in *out);
/* Turns an initialised frame into an occlusion run: traces the primary rays
 * on the host (img, the reference traversal) and makes src feed their
 * `samples` AO rays each (tmax rt_ao_distance) instead of primary rays.
 * False with a message on a stack overflow or out of memory. */
bool rtsim_frame_occlusion(rtsim_frame *f, const rt_bvh_image *img, uint32_t samples,
                                         accel_source *src, char *err, size_t errlen);
void rtsim_frame_free(rtsim_frame *f);

#endif
