/* rtsim_estimate.h — rtsim's run-time estimate (runs that would
 * take hours say so before they start): rays, simulated cycles and host
 * time for the chosen fidelity, from a sample of the frame traced with the
 * reference traversal and the figures of model/data/estimate.ini (the
 * formula and its calibration are there and in docs/accel.md).
 *
 * Contract: rtsim_estimate_load() reads the figures (a missing or broken
 * file is an error naming it); rtsim_estimate_frame() traces the sample and
 * fills the estimate; both deterministic (fixed pixels, the frame's seed).
 * Header-only (static functions) because cli/ builds one binary per .c. */
#ifndef RTSIM_CLI_RTSIM_ESTIMATE_H
#define RTSIM_CLI_RTSIM_ESTIMATE_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "frame/frame.h"
#include "config/config.h"
#include "config/ini_file.h"
#include "tracer/trace/bounce.h"
#include "tracer/trace/traverse.h"

typedef struct rtsim_estimate_params {
    double sample_pixels, overhead, primary_mcps, diffuse_mcps, exhaustive_factor, announce_s, progress_s;
} rtsim_estimate_params;

typedef struct rtsim_estimate {
    double rays, cycles, host_s;
    double visits_per_ray, tests_per_ray;
} rtsim_estimate;

static const char *const rtsim_estimate_keys[] = {"sample_pixels",         "overhead",          "primary_mcycles_per_s",
                                                  "diffuse_mcycles_per_s", "exhaustive_factor", "announce_seconds",
                                                  "progress_seconds"};
#define RTSIM_ESTIMATE_NKEYS 7

static double *rtsim_estimate_field(rtsim_estimate_params *p, int i)
{
    double *fields[RTSIM_ESTIMATE_NKEYS] = {&p->sample_pixels, &p->overhead,          &p->primary_mcps, &p->diffuse_mcps,
                                            &p->exhaustive_factor, &p->announce_s, &p->progress_s};
    return fields[i];
}

static int rtsim_estimate_ini(ini_file *f, void *user, const char *section, const char *name, const char *value)
{
    const int i = ini_file_key_index(f, section, name, rtsim_estimate_keys, RTSIM_ESTIMATE_NKEYS);
    if (i < 0)
        return -1;
    double v;
    if (ini_file_number(value, &v) || !(v > 0))
        return ini_file_error(f, "%s = '%s' invalid, allowed a number > 0", name, value);
    *rtsim_estimate_field(user, i) = v;
    return 0;
}

/* Reads DATA_DIR/estimate.ini (every key of [estimate] is needed). */
static inline bool rtsim_estimate_load(rtsim_estimate_params *p, char *err, size_t errlen)
{
    char path[RTCFG_PATH_MAX];
    memset(p, 0, sizeof *p);
    if (snprintf(path, sizeof path, "%s/estimate.ini", rtcfg_data_dir()) >= (int)sizeof path) {
        snprintf(err, errlen, "%s/estimate.ini: path longer than %d characters", rtcfg_data_dir(), RTCFG_PATH_MAX - 1);
        return false;
    }
    static const ini_file_opts opts = {.what = "a run-time estimate", .section = "estimate"};
    if (ini_file_read(path, &opts, rtsim_estimate_ini, p, err, errlen))
        return false;
    for (int i = 0; i < RTSIM_ESTIMATE_NKEYS; i++)
        if (!*rtsim_estimate_field(p, i)) {
            snprintf(err, errlen, "%s: missing key %s in [estimate] (a number > 0)", path, rtsim_estimate_keys[i]);
            return false;
        }
    return true;
}

/* Traces the sample: a fixed set of pixels spread over the image, each with
 * its bounce path when the frame is diffuse. */
static inline void rtsim_estimate_frame(const rtsim_estimate_params *p, const rtsim_frame *f, const rt_bvh_image *img,
                                        const rt_trv_params *tp, uint32_t trv_count, bool exhaustive,
                                        rtsim_estimate *out)
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
    double per_ray = out->visits_per_ray / (double)(trv_count ? trv_count : 1);
    if (out->tests_per_ray > per_ray)
        per_ray = out->tests_per_ray;
    out->cycles = out->rays * per_ray * p->overhead;
    double mcps = (f->diffuse ? p->diffuse_mcps : p->primary_mcps) * (exhaustive ? p->exhaustive_factor : 1.0);
    out->host_s = out->cycles / (mcps * 1e6);
}

/* "1.2 h", "35 min", "12 s". */
static inline void rtsim_estimate_duration(double s, char *buf, size_t len)
{
    if (s >= 3600)
        snprintf(buf, len, "%.1f h", s / 3600);
    else if (s >= 60)
        snprintf(buf, len, "%.0f min", s / 60);
    else
        snprintf(buf, len, "%.0f s", s);
}

#endif
