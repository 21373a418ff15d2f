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
    return fid_subset_open_series(s, job, cfg, map, n, NULL, 0, NULL, err, errlen);
}

int fid_subset_open_series(fid_subset *s, const fid_job *job, const rtcfg *cfg, const uint32_t *map, uint32_t n,
                           const char *tag, uint32_t piece, const char *phase, char *err, size_t errlen)
{
    memset(s, 0, sizeof *s);
    accel_top_opts o = {0};
    if (job->series_dir && tag) {
        char path[RTCFG_PATH_MAX];
        const int len = snprintf(path, sizeof path, "%s/%s-%06u.csv", job->series_dir, tag, piece);
        if (len < 0 || (size_t)len >= sizeof path) {   /* refused, never cut (docs/kernel.md) */
            snprintf(err, errlen, "--series: the scratch path under %s is longer than %d characters",
                     job->series_dir, RTCFG_PATH_MAX - 1);
            fid_subset_close(s);
            return 2;
        }
        if (!(s->series_f = fopen(path, "w")) ||
            !(s->series = accel_series_create(s->series_f, job->series_interval, false))) {
            snprintf(err, errlen, "--series: cannot write %s", path);
            fid_subset_close(s);
            return 2;
        }
        accel_series_label(s->series, piece, phase);
        o.series = s->series;
    }
    if (!rtsim_frame_init(&s->frame, cfg, job->mesh, job->view, job->width, job->height, job->diffuse, job->bounces,
                          job->seed, false, &s->src, err, errlen))
        return fid_subset_close(s), 2;
    s->map = map;
    s->src.user = s;
    s->src.primary = sub_primary;
    s->src.bounce = sub_bounce;
    s->src.complete = sub_complete;
    if (map)
        s->src.primary_count = n;
    accel_image aimg = rtsim_image(job->img);
    s->top = accel_top_create(cfg, &aimg, &s->src, &o, err, errlen);
    if (!s->top) {
        fid_subset_close(s);
        return 2;
    }
    return 0;
}

int fid_subset_close(fid_subset *s)
{
    int rc = 0;
    if (s->top)
        accel_top_destroy(s->top);
    s->top = NULL;
    accel_series_destroy(s->series);
    s->series = NULL;
    if (s->series_f && (ferror(s->series_f) | fclose(s->series_f)))
        rc = -1;
    s->series_f = NULL;
    rtsim_frame_free(&s->frame);
    return rc;
}
