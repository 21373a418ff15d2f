/* cost_estimate.h — what a run of rtsim will cost before it starts (runs
 * that would take hours say so first): rays, simulated cycles and host
 * seconds, from a sample of the frame traced with the reference traversal
 * and the figures of model/data/estimate.ini (the formula and its
 * calibration are there and in docs/accel.md "Run-time estimate and progress").
 *
 * It is the functional level's throughput model (fidelity/functional.h)
 * cut down to its issue bound: cycles per ray = the busier of the TRVs
 * (node visits shared by trv.count of them) and the IST (one triangle test
 * a cycle), times a fitted overhead for everything the bound leaves out
 * (misses, latency, drain); no caches are simulated, so it costs a few
 * hundred traced pixels.
 *
 * Contract: fid_cost_load() reads the figures (a missing or broken file is
 * an error naming it); fid_cost_frame() traces the sample and fills the
 * estimate; both deterministic (fixed pixels, the frame's seed). */
#ifndef RTSIM_FIDELITY_COST_ESTIMATE_H
#define RTSIM_FIDELITY_COST_ESTIMATE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "frame/frame.h"
#include "tracer/trace/traverse.h"

/* The [estimate] figures of estimate.ini (all > 0). */
typedef struct fid_cost_params {
    double sample_pixels;      /* pixels traced for the estimate */
    double overhead;           /* simulated cycles over the issue bound */
    double primary_mcps;       /* M simulated cycles per host second, primary rays */
    double diffuse_mcps;       /* the same, diffuse paths */
    double exhaustive_factor;  /* speed with --exhaustive (no idle skipping), relative */
    double announce_s;         /* host seconds from which rtsim announces the estimate */
    double progress_s;         /* seconds between --progress lines off a terminal */
} fid_cost_params;

typedef struct fid_cost {
    double rays, cycles, host_s;
    double visits_per_ray, tests_per_ray;
} fid_cost;

/* Reads DATA_DIR/estimate.ini (every key of [estimate] is needed). */
bool fid_cost_load(fid_cost_params *p, char *err, size_t errlen);

/* Traces the sample (a fixed set of pixels spread over the image, each with
 * its bounce path when the frame is diffuse) and estimates the run. */
void fid_cost_frame(const fid_cost_params *p, const rtsim_frame *f, const rt_bvh_image *img,
                    const rt_trv_params *tp, uint32_t trv_count, bool exhaustive, fid_cost *out);

/* The issue bound of one ray, cycles: the busier of its TRV share of the
 * node visits and its IST triangle tests. */
double fid_cost_issue_cycles(double visits_per_ray, double tests_per_ray, uint32_t trv_count);

/* "1.2 h", "35 min", "12 s". */
void fid_cost_duration(double s, char *buf, size_t len);

#endif
