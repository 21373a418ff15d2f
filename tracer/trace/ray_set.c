/* ray_set.c — see ray_set.h. */
#include "tracer/trace/ray_set.h"

#include <stdlib.h>
#include <string.h>

#include "tracer/trace/bounce.h"
#include "tracer/trace/camera.h"
#include "tracer/trace/occlusion.h"
#include "tracer/io/scene_error.h"

bool rt_ray_set_primary(const rt_view *view, uint32_t width, uint32_t height, rt_ray_set *out, char *err,
                        size_t errlen)
{
    memset(out, 0, sizeof *out);
    rt_camera cam;
    if (!rt_camera_init(&cam, view, width, height, err, errlen))
        return false;
    out->rays = malloc((size_t)width * height * sizeof *out->rays);
    if (!out->rays) {
        rt_scene_errorf(err, errlen, "ray set: out of memory for %ux%u rays", width, height);
        return false;
    }
    for (uint32_t y = 0; y < height; y++)
        for (uint32_t x = 0; x < width; x++)
            out->rays[out->n++] = rt_camera_primary_ray(&cam, x, y);
    return true;
}

bool rt_ray_set_diffuse(const rt_mesh *mesh, const rt_bvh_image *img, const rt_trv_params *p,
                        const rt_ray_set *primary, uint64_t seed, uint32_t max_bounces, rt_ray_set *out, char *err,
                        size_t errlen)
{
    memset(out, 0, sizeof *out);
    size_t cap = primary->n ? primary->n : 1;
    out->rays = malloc(cap * sizeof *out->rays);
    if (!out->rays) {
        rt_scene_errorf(err, errlen, "ray set: out of memory");
        return false;
    }
    /* generation g occupies [gen_begin, gen_end) of the source array */
    const rt_ray *src = primary->rays;
    uint32_t gen_begin = 0, gen_end = primary->n;
    bool from_primary = true;
    for (uint32_t b = 0; b < max_bounces && gen_begin < gen_end; b++) {
        const uint32_t next_begin = out->n;
        for (uint32_t i = gen_begin; i < gen_end; i++) {
            const rt_ray r = src[i];
            rt_hit h;
            if (!rt_trace_ray(img, p, &r, &h, NULL, NULL, NULL)) {
                rt_scene_errorf(err, errlen, "ray set: stack overflow (depth %d) tracing the ray of pixel %u, bounce %u",
                                p->stack_depth, r.pixel, (unsigned)r.bounce);
                rt_ray_set_free(out);
                return false;
            }
            rt_ray nr;
            if (!rt_bounce_ray(mesh, &r, &h, seed, max_bounces, &nr))
                continue;
            if (out->n == cap) {
                cap *= 2;
                rt_ray *g = realloc(out->rays, cap * sizeof *g);
                if (!g) {
                    rt_scene_errorf(err, errlen, "ray set: out of memory for %zu rays", cap);
                    rt_ray_set_free(out);
                    return false;
                }
                out->rays = g;
            }
            out->rays[out->n++] = nr;
            if (!from_primary)
                src = out->rays;   /* realloc may have moved the source generation */
        }
        src = out->rays;
        from_primary = false;
        gen_begin = next_begin, gen_end = out->n;
    }
    return true;
}

bool rt_ray_set_occlusion(const rt_mesh *mesh, const rt_bvh_image *img, const rt_trv_params *p,
                          const rt_ray_set *primary, uint64_t seed, uint32_t samples, float ao_tmax, rt_ray_set *out,
                          char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    const size_t cap = (size_t)primary->n * samples;
    out->rays = malloc((cap ? cap : 1) * sizeof *out->rays);
    if (!out->rays) {
        rt_scene_errorf(err, errlen, "ray set: out of memory for %zu occlusion rays", cap);
        return false;
    }
    for (uint32_t i = 0; i < primary->n; i++) {
        const rt_ray *r = &primary->rays[i];
        rt_hit h;
        if (!rt_trace_ray(img, p, r, &h, NULL, NULL, NULL)) {
            rt_scene_errorf(err, errlen, "ray set: stack overflow (depth %d) tracing the ray of pixel %u",
                            p->stack_depth, r->pixel);
            rt_ray_set_free(out);
            return false;
        }
        for (uint32_t k = 0; k < samples; k++)
            if (rt_ao_ray(mesh, r, &h, seed, k, ao_tmax, &out->rays[out->n]))
                out->n++;
    }
    return true;
}

void rt_ray_set_free(rt_ray_set *s)
{
    free(s->rays);
    memset(s, 0, sizeof *s);
}
