/* subset.c — the cycle model on a pixel subset (see subset.h). */
#include "fidelity/subset.h"

static void sub_primary(void *u, uint64_t i, accel_ray_in *out)
{
    fid_subset *s = u;
    rtsim_frame_primary(&s->frame, s->map ? s->map[i] : i, out);
}

static bool sub_bounce(void *u, const accel_ray_in *in, const accel_hit *hit, accel_ray_in *out)
{
    return rtsim_frame_bounce(&((fid_subset *)u)->frame, in, hit, out);
}

static void sub_complete(void *u, uint32_t uid, const accel_ray_in *in, const accel_hit *hit, uint64_t admit,
                         uint64_t done, uint32_t visits, uint32_t tri_tests, bool failed)
{
    rtsim_frame_complete(&((fid_subset *)u)->frame, uid, in, hit, admit, done, visits, tri_tests, failed);
}

int fid_subset_open(fid_subset *s, const fid_job *job, const rtcfg *cfg, const uint32_t *map, uint32_t n, char *err,
                    size_t errlen)
{
    memset(s, 0, sizeof *s);
    if (!rtsim_frame_init(&s->frame, cfg, job->mesh, job->view, job->width, job->height, job->diffuse, job->bounces,
                          job->seed, false, &s->src, err, errlen))
        return 2;
    s->map = map;
    s->src.user = s;
    s->src.primary = sub_primary;
    s->src.bounce = sub_bounce;
    s->src.complete = sub_complete;
    if (map)
        s->src.primary_count = n;
    accel_image aimg = rtsim_image(job->img);
    accel_top_opts o = {0};
    s->top = accel_top_create(cfg, &aimg, &s->src, &o, err, errlen);
    if (!s->top) {
        rtsim_frame_free(&s->frame);
        return 2;
    }
    return 0;
}

void fid_subset_close(fid_subset *s)
{
    if (s->top)
        accel_top_destroy(s->top);
    s->top = NULL;
    rtsim_frame_free(&s->frame);
}
