/* fidelity_params.c — values of fidelity_params.h. Each comes from runs of
 * the full model; docs/fidelity.md "Parameters" gives the runs. */
#include "fidelity/fidelity_params.h"

static const fid_params defaults = {
    /* mean memory.latency_sum / memory.requests of the LPDDR3 model at low
     * utilisation (interior primary 160x90: 38.7 cycles at 29%, 66% row
     * hits): 25 cycles for a row hit plus 15 for precharge + activate
     * (tRP + tRCD = 2 x 15 ns at 500 MHz, model/data/lpddr3_1600.ini) */
    .dram_latency = 20.0,
    .row_miss_cycles = 30.0,
    /* fitted on interior and hairball, primary and diffuse, 160x90 MBVH4:
     * mean memory latency 38.7, 76.5, 54.1, 97.3 cycles at utilisation 29%,
     * 61%, 47%, 58% and row hits 66%, 48%, 46%, 39% */
    .queue_cycles = 25.0,
    /* IST loops per primitive-cache miss line in the full model are 1 +
     * latency / 23..29 (the four runs above), against prim.hit_latency +
     * ist.latency = 18: the loop FIFO and re-issue add about 6 */
    .ist_loop_extra = 6.0,
    .mem_side_fifo_cycles = 4.0,   /* L1 -> arbiter -> L2 and back: fifo.mem_latency hops */
    .max_util = 0.95,
    .miss_waiters = 1.0,
    /* 1/32 of a 1280x720 frame is 22 rows: far longer than the 128 rays in
     * flight and the FIFOs can smooth, the scale of a scene's regions */
    .func_phases = 32,
    .func_err_base = 0.15,         /* worst |functional - full| MRPS over the matrix with one clear bound */
    .func_err_tie = 0.15,
    .func_tie_flag = 0.85,
    .func_err_mem = 0.30,          /* covers hairball BVH2 diffuse 320x180: 32% off at util x row miss 0.53 */
    .func_err_dram = 0.10,
    .func_err_energy = 0.10,
    .pilot_fraction = 1.0 / 16.0,
    .pilot_min_pixels = 1024,
    .fixed_max_util = 0.60,        /* above it fixed-mem errs by > 5% on diffuse rays (docs/fidelity.md) */
    /* unloaded = dram_latency + row misses x row_miss_cycles; the 320x180
     * matrix's pilots are 1.3-3.3x it (3.3: hairball BVH2 diffuse, then
     * flagged), the furball stand-in's 5.6x */
    .fixed_max_latency_ratio = 3.0,
    .fixed_err_base = 0.02,
    .fixed_err_util = 0.10,
    .sample_rate = 1.0 / 16.0,
    .sample_groups = 4,
    .sample_t95 = 3.182,           /* Student t, 3 degrees of freedom, two-sided 95% */
    .sample_max_err = 0.10,
    .sample_err_floor = 0.01,
    /* --accuracy's sampled: a second try at the rate the first interval
     * says the target needs (1/sqrt(sample)) x 1.3, when at most 35% of the
     * pixels (beyond, a full run costs little more). The frame's functional
     * pass (about a quarter of a full run) only when it may pay: the
     * groups' own functional passes predict the estimate without it,
     * 0.60-1.26x the real one on the 1280x720 diffuse matrix (it misses the
     * frame's phase excess), so a prediction over 1.25x the point where
     * sampled would stop gives up before it
     * (docs/validation/fidelity-accuracy.md) */
    .sample_give_up = 1.25,
    .sample_retry_margin = 1.3,
    .sample_retry_max_rate = 0.35,
    /* hairball primary 640x360: functional DRAM MB 2.3% off on the frame,
     * 0.2% on the sample, so the ratio estimator is 2.3-2.6% off */
    .sample_err_dram = 0.025,      /* the worst excess over CI + bias term in the 320x180 matrix: 1.1% */
    .band_rows = 1,                /* 8x8 tiles and 4- or 8-row bands were 5-12% low on primary MRPS (docs/fidelity.md) */
    .win_rate = 0.125,
    .win_count = 16,
    .win_min_count = 8,
    .win_warm_pixels = 4096,
    .win_min_pixels = 256,
    .win_tail_pixels = 512,
    /* 1280x720 diffuse, 10 configurations: windowed 4.6-5.9x faster than
     * full with 1 in 4, 5.4-6.8x with 1 in 8, true errors within 1.4%
     * either way (docs/fidelity.md "windowed") */
    .win_lattice = 8,
    .win_err_floor = 0.005,
    .win_max_cold = 0.02,
    .win_max_rate = 0.4,
    /* functional warming from the lattice's caches: on the 1280x720
     * diffuse matrix (Morton order) cold fills 0.0-2.5% (bunny 8.6%)
     * against 0.1-41% after 4096-pixel warm-ups from empty caches; 1024
     * detailed pixels after it (512: interior MBVH4 cold fills 0.5%
     * against 0.2%, estimates wider), which leaves room for 48 windows in
     * 1/8 of the frame (docs/validation/fidelity-accuracy.md) */
    .win_snapshot = 1,
    .win_snap_warm_pixels = 1024,
    .win_snap_count = 48,
    /* a snapshot takes 16 bytes per cache line: about 60 KB at the default
     * caches, 48 windows 3 MB; a sweep to 64 MB caches would take 1.6 GB
     * for 48 windows and is refused with a message instead */
    .win_snap_max_bytes = 1e9,
    /* --accuracy's cold probe: over 5% windowed is not tried. With 10%,
     * city primary MBVH4 and hairball primary BVH2 passed it, and their
     * pilots (28.7% cold fills; a predicted 4.6%) cost 33% and 16% over
     * the full run; the diffuse matrix's windows were 0.0-3.4% cold after
     * 4096 pixels from empty caches except city (5.7%, 22%) and bunny
     * (34%, 41%), whose estimates were 4-77% */
    .win_probe_pixels = 512,
    .win_probe_max_cold = 0.05,
    /* the frame's projected L2 + primitive-cache fills over their lines:
     * interior primary moves 0.77 MB (6K lines) through 3K lines of cache
     * (about 2), interior diffuse 262 MB (about 700); with the cold share
     * alone city, bunny and hairball BVH2 primary passed the probe and
     * their pilots cost 12-45% over the full run */
    .win_probe_min_turnover = 20,
    /* --accuracy's pilot: 8 windows (4 pairs) with the lattice, about 6% of
     * a full run on interior diffuse; fewer pairs make the predicted
     * interval too uncertain to decide on */
    .win_pilot_windows = 8,
};

const fid_params *fid_params_get(void) { return &defaults; }
