/* functional.h — the functional level: every ray of a frame (or of a pixel
 * subset) traced by the reference traversal (tracer/trace/traverse.h), its node and
 * triangle fetches sent through the model's cache core (model/mem/cache_core.h: node
 * L1 per TRV, shared node L2, primitive cache) in a plausible order, and
 * cycles from a throughput model (docs/fidelity.md "functional").
 *
 * Order: trv.count x trv.slots ray slots, TRVs round-robin like the
 * scheduler; each round every busy slot makes its next memory access; a slot
 * whose ray is done takes its bounce (diffuse) or the next primary. Misses
 * are filled at once (no timing), so the counts are real and deterministic.
 * DRAM row locality: the LPDDR3 address mapping of memory.dram_config, one
 * open row per bank.
 *
 * Throughput model (per TRV and for the IST the issue cycles: a pass per
 * visit, per return from the IST and per loop while a miss is outstanding;
 * a test per triangle and per loop): cycles = the busiest of TRV issue, IST
 * issue, DRAM transfer at memory.fixed_bandwidth_gbs, and the latency bound
 * with all slots in flight (Little's law). The memory latency in the loops
 * and the latency bound is the unloaded one plus an M/D/1 queueing term at
 * the DRAM utilisation, solved by fixed-point iteration; plus the drain:
 * the last paths finish one path latency after the bound. */
#ifndef RTSIM_FIDELITY_FUNCTIONAL_H
#define RTSIM_FIDELITY_FUNCTIONAL_H

#include <stdint.h>

#include "fidelity/fidelity.h"
#include "model/mem/cache_core.h"

#define FID_MAX_TRV 64

typedef struct fid_func {
    uint32_t ntrv;
    uint64_t rays, primaries, bounces, failed;
    uint64_t visits, box_tests, leaves, tri_tests, pushes, pops, culls;
    uint64_t trv_visits[FID_MAX_TRV], trv_leaves[FID_MAX_TRV], trv_l1_miss_lines[FID_MAX_TRV];
    cache_stats l1, l2, prim;     /* l1: summed over the TRVs */
    uint64_t dram_bytes, dram_lines, row_hits;
    /* throughput model */
    double mem_latency;           /* cycles, request to data at the solved utilisation */
    double dram_util;
    double cyc_trv, cyc_ist, cyc_dram, cyc_lat, cyc_tail, cycles;
    double cyc_bound;             /* the largest bound (cycles without the drain) */
    const char *bound;            /* "trv", "ist", "dram", "latency" */
    double runner_up;             /* second largest bound / largest (1 = tie) */
    double mrps, clock_mhz;
    double miss_scale;            /* multiplies every miss's wait (1 = the model as fitted) */
    /* the busiest issue unit's work (a TRV's visits + leaves, the IST's
     * tests) summed phase by phase (func_phases runs of the primaries, in
     * admission order), over the busiest unit's work over the run, - 1:
     * how much slower than the issue bound the run is when each phase is
     * bound by its own busiest unit (the load moves between the TRVs and
     * the IST across a frame); loops on misses left out */
    double phase_excess;
} fid_func;

/* pixels: the primary rays' pixel indices in admission order (NULL: every
 * pixel in scanline order, npix ignored). Returns 0, or -1 with a message. */
int fid_functional_run(const fid_job *job, const uint32_t *pixels, uint32_t npix, fid_func *out, char *err,
                       size_t errlen);

/* What the run charged to each pixel's path: its rays' node visits and
 * triangle tests, its bounce rays' traversal work (visits + tests), the
 * DRAM lines its rays' misses brought in (a miss is the ray's that made it)
 * and its rays. */
enum { FID_ATTR_VISITS, FID_ATTR_TRI_TESTS, FID_ATTR_BOUNCE_WORK, FID_ATTR_DRAM_LINES, FID_ATTR_RAYS, FID_ATTR_COUNT };
typedef float fid_func_attr[FID_ATTR_COUNT];

/* fid_functional_run with attr[i] (npix of them, zeroed here) filled for
 * pixels[i] (pixels not NULL). */
int fid_functional_run_attributed(const fid_job *job, const uint32_t *pixels, uint32_t npix, fid_func *out,
                                  fid_func_attr *attr, char *err, size_t errlen);

/* A copy of the run's caches' contents (tags and LRU order) taken when
 * the run was about to admit the primary at list position `at`: the
 * windowed level's functional warming (windowed.c). */
typedef struct fid_func_snap {
    uint32_t at;                  /* set by the caller */
    uint32_t ntrv;
    cache_core *l1[FID_MAX_TRV], *l2, *prim;   /* NULL until taken */
} fid_func_snap;

/* fid_functional_run_attributed that also fills snaps[0..nsnap) (their
 * `at` ascending); fid_functional_snap_free() frees them. */
int fid_functional_run_snap(const fid_job *job, const uint32_t *pixels, uint32_t npix, fid_func *out,
                            fid_func_attr *attr, fid_func_snap *snaps, uint32_t nsnap, char *err, size_t errlen);
void fid_functional_snap_free(fid_func_snap *s);

/* Recomputes the throughput model of f's counts with every miss's wait
 * multiplied by miss_scale (sampled: fitted so that the functional cycles
 * of a sample match the cycle model's). */
void fid_functional_retime(const fid_job *job, fid_func *f, double miss_scale);
/* Adds f's counts (rays, work, cache accesses, hits, misses, fills, DRAM
 * lines and row hits) to sum, as if one pass had made both; the throughput
 * figures are left for fid_functional_retime, and phase_excess at 0. */
void fid_functional_add(fid_func *sum, const fid_func *f);

#endif
