/* series.h — interval statistics of a run (rtsim --series FILE,
 * docs/results.md "Interval statistics"): one CSV row every `interval`
 * cycles with the rays admitted and completed, rays in flight, each unit's
 * utilization, the hit rate of each cache level, DRAM bandwidth, row-hit
 * rate and queue occupancy, and the dynamic power of each Table 1 unit.
 *
 * Contract:
 *  - The caller creates a series on an open FILE and hands it to
 *    accel_top_create (accel_top_opts.series); the top samples it where its
 *    run already stops (kernel/sim.h: ks_sim_run to a time): at every
 *    multiple of the interval, wherever accel_top_run_until stops, and once
 *    at the end of the run (to the frame's last cycle). Without a series the
 *    run does no extra work at all.
 *  - A row covers the cycles [cycle_begin, cycle_end) of its run and holds
 *    the differences of cumulative counts between its two ends, so the rows
 *    of a run add up to the run's totals (counts), and their means weighted
 *    by cycles (or by accesses, for hit rates) to the run's means.
 *  - accel_series_label() names the rows that follow (piece, phase), so the
 *    rows of several runs of one result (a sampled level's groups, a
 *    windowed level's warm-ups and windows) can share one file.
 *  - Sampling reads state only: a run's results are the same, bit for bit,
 *    with and without a series.
 *  - Numbers are printed deterministically (%.10g). */
#ifndef RTSIM_MODEL_SERIES_H
#define RTSIM_MODEL_SERIES_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "model/energy/energy.h"

typedef struct accel_series accel_series;

/* Cumulative counts of a run at one cycle (filled by the top level). */
typedef struct accel_series_point {
    uint64_t cycle;
    uint64_t admitted, completed, in_flight, in_flight_area;   /* rays; ray-cycles */
    const uint64_t *trv_busy;      /* per TRV, busy cycles (ntrv entries) */
    uint64_t ist_busy;
    uint64_t cache_acc[3], cache_hit[3];                        /* node L1 (all TRVs), node L2, prim */
    uint64_t dram_bytes;
    bool dram;                     /* the LPDDR3 model: the next four are valid */
    uint64_t row_hits, row_accesses, queue_sum, dram_cycles;
} accel_series_point;

/* interval: cycles per row (>= 1). header: write the CSV header when the
 * run starts (accel_series_start); else the caller writes it
 * (accel_series_write_header). NULL when out of memory. */
accel_series *accel_series_create(FILE *out, uint64_t interval, bool header);
void accel_series_destroy(accel_series *s);
/* The piece and phase of the rows that follow (default 0, "frame"). */
void accel_series_label(accel_series *s, uint32_t piece, const char *phase);
/* The CSV header for a machine of ntrv TRVs. */
void accel_series_write_header(FILE *out, uint32_t ntrv);

/* ---- for the top level (model/accel_top.c) ---- */
/* The run starts: ntrv TRVs at clock_mhz; em: the energy model (NULL: none). */
void accel_series_start(accel_series *s, uint32_t ntrv, double clock_mhz, energy_model *em);
/* The next cycle at which a row ends. */
uint64_t accel_series_next(const accel_series *s);
/* Ends a row at p (act: the energy activity at p, NULL without an energy
 * model). Overwrites em->r (energy_compute). A row of no cycles is not
 * written. */
void accel_series_sample(accel_series *s, const accel_series_point *p, const energy_activity *act);

#endif
