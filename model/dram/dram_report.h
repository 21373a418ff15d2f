/* dram_report.h — the summary of a DRAM run (what rtdram prints and the
 * reference comparison uses): time, bandwidth, latency, row-hit rate, command
 * counts and DRAMPower-method energy, summed over channels. Meanings follow
 * ../shared/ref/dram/README.txt ("Parse"): bw = (read+write burst bytes)/time,
 * row_hit_rate = hits/(hits+misses+conflicts), read latency = enqueue -> data
 * complete in DRAM cycles, averaged over reads served by DRAM (not forwarded). */
#ifndef RTSIM_DRAM_REPORT_H
#define RTSIM_DRAM_REPORT_H

#include <stdint.h>
#include <stdio.h>

#include "model/dram/dram_ctrl.h"
#include "model/dram/dram_energy.h"

typedef struct dram_summary {
    int64_t dram_cycles;
    double time_ns, bw_GBps, read_lat_avg_cycles, row_hit_rate;
    uint64_t n_act, n_pre, n_prea, n_ref, n_rd, n_wr, n_pre_banks;
    uint64_t row_hits, row_misses, row_conflicts, reads_forwarded, bytes;
    dram_energy energy;       /* summed over channels */
    double energy_uJ, energy_pJ_per_byte;
} dram_summary;

void dram_summary_compute(const dram_ctrl *c, const dram_power_spec *p, dram_summary *s);
/* One JSON object (keys of the reference CSV plus extras), newline-terminated. */
void dram_summary_json(const dram_summary *s, FILE *out);
void dram_summary_text(const dram_summary *s, FILE *out);

#endif
