/* dram_energy.h — DRAM energy from command counts and background state, with
 * DRAMPower 4.1's method (MemoryPowerModel.cc as documented in
 * ../shared/ref/dram/drampower_lpddr3_1600_idd.txt:17-26), per channel:
 *   E_ACT = [V1(IDD0-IDD3N) + V2(IDD02-IDD3N2)] * tRAS          per ACT
 *   E_PRE = [V1(IDD0-IDD2N) + V2(IDD02-IDD2N2)] * (tRC-tRAS)    per closed bank
 *   E_RD  = [V1(IDD4R-IDD3N) + V2(IDD4R2-IDD3N2)] * BL/dataRate cycles
 *   E_WR  likewise with IDD4W; E_REF = [V1(IDD5-IDD3N)+V2(IDD52-IDD3N2)] * tRFC
 *   background: active standby (V1*IDD3N + V2*IDD3N2) over active cycles,
 *   precharged standby (V1*IDD2N + V2*IDD2N2) over the rest; DRAMPower counts
 *   each REF as tRFC - tRP active cycles (its refresh accounting).
 * Currents/voltages/timings come from a data file (model/data/lpddr3_1600_idd.ini).
 * Power-down and self-refresh are not modelled (the controller never enters them). */
#ifndef RTSIM_DRAM_ENERGY_H
#define RTSIM_DRAM_ENERGY_H

#include <stddef.h>
#include <stdint.h>

typedef struct dram_power_spec {
    double clk_mhz, vdd1, vdd2;
    double idd0, idd02, idd2n, idd2n2, idd3n, idd3n2, idd4r, idd4r2, idd4w, idd4w2, idd5, idd52;
    int burst_length, data_rate, nRAS, nRC, nRP, nRFC;
    int dies_per_channel;
} dram_power_spec;

/* What the energy depends on, per channel (from dram_chan_stats). */
typedef struct dram_energy_in {
    uint64_t n_act, n_pre_banks, n_rd, n_wr, n_ref;
    uint64_t open_cycles;   /* cycles with >= 1 bank open */
    uint64_t total_cycles;
} dram_energy_in;

typedef struct dram_energy {
    double act_pJ, pre_pJ, rd_pJ, wr_pJ, ref_pJ;
    double act_stby_pJ, pre_stby_pJ;
    double total_pJ;
    uint64_t act_cycles, pre_cycles;
} dram_energy;

/* Loads the [memspec] file; 0, or -1 with "file:line: key ... allowed range". */
int dram_power_spec_load(dram_power_spec *p, const char *path, char *err, size_t errlen);
/* Energy of one command in pJ (per channel, all dies): for docs and tests. */
double dram_energy_per_act(const dram_power_spec *p);
double dram_energy_per_pre(const dram_power_spec *p);
double dram_energy_per_rd(const dram_power_spec *p);
double dram_energy_per_wr(const dram_power_spec *p);
double dram_energy_per_ref(const dram_power_spec *p);
/* Channel energy. */
void dram_energy_compute(const dram_power_spec *p, const dram_energy_in *in, dram_energy *out);

#endif
