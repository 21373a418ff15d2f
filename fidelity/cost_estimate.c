/* cost_estimate.c — rtsim's run-cost estimate (fidelity/cost_estimate.h). */
#include <stdio.h>
#include <string.h>

#include "config/config.h"
#include "config/ini_file.h"
#include "fidelity/cost_estimate.h"
#include "tracer/trace/bounce.h"

static const char *const cost_keys[] = {"sample_pixels",     "overhead",         "primary_mcycles_per_s",
                                        "diffuse_mcycles_per_s", "exhaustive_factor", "announce_seconds",
                                        "progress_seconds"};
#define COST_NKEYS (int)(sizeof cost_keys / sizeof cost_keys[0])

/* The field of key i of cost_keys. */
static double *cost_field(fid_cost_params *p, int i)
{
    double *fields[COST_NKEYS] = {&p->sample_pixels,     &p->overhead,   &p->primary_mcps, &p->diffuse_mcps,
                                  &p->exhaustive_factor, &p->announce_s, &p->progress_s};
    return fields[i];
}

static int cost_ini(ini_file *f, void *user, const char *section, const char *name, const char *value)
{
    const int i = ini_file_key_index(f, section, name, cost_keys, COST_NKEYS);
    if (i < 0)
        return -1;
    double v;
    if (ini_file_number(value, &v) || !(v > 0))
        return ini_file_error(f, "%s = '%s' invalid, allowed a number > 0", name, value);
    *cost_field(user, i) = v;
    return 0;
}

bool fid_cost_load(fid_cost_params *p, char *err, size_t errlen)
{
    char path[RTCFG_PATH_MAX];
    memset(p, 0, sizeof *p);
    if (snprintf(path, sizeof path, "%s/estimate.ini", rtcfg_data_dir()) >= (int)sizeof path) {
        snprintf(err, errlen, "%s/estimate.ini: path longer than %d characters", rtcfg_data_dir(), RTCFG_PATH_MAX - 1);
        return false;
    }
    static const ini_file_opts opts = {.what = "a run-time estimate", .section = "estimate"};
    if (ini_file_read(path, &opts, cost_ini, p, err, errlen))
        return false;
    for (int i = 0; i < COST_NKEYS; i++)
        if (!*cost_field(p, i)) {
            snprintf(err, errlen, "%s: missing key %s in [estimate] (a number > 0)", path, cost_keys[i]);
            return false;
        }
    return true;
}

double fid_cost_issue_cycles(double visits_per_ray, double tests_per_ray, uint32_t trv_count)
{
    double trv = visits_per_ray / (double)(trv_count ? trv_count : 1);
    return tests_per_ray > trv ? tests_per_ray : trv;
}

void fid_cost_frame(const fid_cost_params *p, const rtsim_frame *f, const rt_bvh_image *img,
                    const rt_trv_params *tp, uint32_t trv_count, bool exhaustive, fid_cost *out)
{
    uint64_t pixels = (uint64_t)f->cam.width * f->cam.height;
    uint64_t n = pixels < (uint64_t)p->sample_pixels ? pixels : (uint64_t)p->sample_pixels;
    double rays = 0, visits = 0, tests = 0;
    for (uint64_t i = 0; i < n; i++) {
        uint64_t px = n ? i * pixels / n : 0;
        rt_ray r = rt_camera_primary_ray(&f->cam, (uint32_t)(px % f->cam.width), (uint32_t)(px / f->cam.width));
        for (;;) {
            rt_hit h;
            rt_trv_counts c;
            memset(&c, 0, sizeof c);
            bool ok = rt_trace_ray(img, tp, &r, &h, &c, NULL, NULL);
            rays += 1, visits += c.visits, tests += c.tri_tests;
            rt_ray next;
            if (!ok || !f->diffuse || !rt_bounce_ray(f->mesh, &r, &h, f->seed, f->max_bounces, &next))
                break;
            r = next;
        }
    }
    memset(out, 0, sizeof *out);
    if (!n)
        return;
    out->rays = rays / (double)n * (double)pixels;
    out->visits_per_ray = visits / rays;
    out->tests_per_ray = tests / rays;
    out->cycles = out->rays * fid_cost_issue_cycles(out->visits_per_ray, out->tests_per_ray, trv_count) * p->overhead;
    double mcps = (f->diffuse ? p->diffuse_mcps : p->primary_mcps) * (exhaustive ? p->exhaustive_factor : 1.0);
    out->host_s = out->cycles / (mcps * 1e6);
}

void fid_cost_duration(double s, char *buf, size_t len)
{
    if (s >= 3600)
        snprintf(buf, len, "%.1f h", s / 3600);
    else if (s >= 60)
        snprintf(buf, len, "%.0f min", s / 60);
    else
        snprintf(buf, len, "%.0f s", s);
}
