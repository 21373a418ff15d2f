/* dram_report.c — run summary (dram_report.h). */
#include "model/dram/dram_report.h"

#include <string.h>

void dram_summary_compute(const dram_ctrl *c, const dram_power_spec *p, dram_summary *s)
{
    const dram_spec *spec = dram_ctrl_spec(c);
    memset(s, 0, sizeof *s);
    s->dram_cycles = dram_clock(c);
    s->time_ns = (double)s->dram_cycles * spec->tck_ps / 1000.0;
    uint64_t lat_sum = 0, lat_n = 0;
    for (int i = 0; i < spec->channels; i++) {
        dram_chan_stats st;
        dram_chan_stats_get(c, i, &st);
        s->n_act += st.n_cmd[DRAM_ACT];
        s->n_pre += st.n_cmd[DRAM_PRE];
        s->n_prea += st.n_cmd[DRAM_PREA];
        s->n_ref += st.n_cmd[DRAM_REF];
        s->n_rd += st.n_cmd[DRAM_RD];
        s->n_wr += st.n_cmd[DRAM_WR];
        s->n_pre_banks += st.n_pre_banks;
        s->row_hits += st.row_hits;
        s->row_misses += st.row_misses;
        s->row_conflicts += st.row_conflicts;
        s->reads_forwarded += st.reads_forwarded;
        lat_sum += st.read_latency_sum;
        lat_n += st.reads_done;
        dram_energy_in in = {st.n_cmd[DRAM_ACT], st.n_pre_banks, st.n_cmd[DRAM_RD], st.n_cmd[DRAM_WR],
                             st.n_cmd[DRAM_REF], st.open_cycles, (uint64_t)s->dram_cycles};
        dram_energy e;
        dram_energy_compute(p, &in, &e);
        s->energy.act_pJ += e.act_pJ;
        s->energy.pre_pJ += e.pre_pJ;
        s->energy.rd_pJ += e.rd_pJ;
        s->energy.wr_pJ += e.wr_pJ;
        s->energy.ref_pJ += e.ref_pJ;
        s->energy.act_stby_pJ += e.act_stby_pJ;
        s->energy.pre_stby_pJ += e.pre_stby_pJ;
        s->energy.total_pJ += e.total_pJ;
        s->energy.act_cycles += e.act_cycles;
        s->energy.pre_cycles += e.pre_cycles;
    }
    s->bytes = (s->n_rd + s->n_wr) * (uint64_t)spec->tx_bytes;
    s->bw_GBps = s->time_ns > 0 ? (double)s->bytes / s->time_ns : 0;
    s->read_lat_avg_cycles = lat_n ? (double)lat_sum / (double)lat_n : 0;
    uint64_t acc = s->row_hits + s->row_misses + s->row_conflicts;
    s->row_hit_rate = acc ? (double)s->row_hits / (double)acc : 0;
    s->energy_uJ = s->energy.total_pJ / 1e6;
    s->energy_pJ_per_byte = s->bytes ? s->energy.total_pJ / (double)s->bytes : 0;
}

void dram_summary_json(const dram_summary *s, FILE *o)
{
    fprintf(o,
            "{\"dram_cycles\": %lld, \"time_ns\": %.2f, \"bw_GBps\": %.6f, \"read_lat_avg_cycles\": %.4f, "
            "\"row_hit_rate\": %.6f, \"n_act\": %llu, \"n_pre\": %llu, \"n_prea\": %llu, \"n_ref\": %llu, "
            "\"n_rd\": %llu, \"n_wr\": %llu, \"energy_uJ\": %.6f, \"energy_pJ_per_byte\": %.4f, "
            "\"row_hits\": %llu, \"row_misses\": %llu, \"row_conflicts\": %llu, \"reads_forwarded\": %llu, "
            "\"bytes\": %llu, \"n_pre_banks\": %llu, \"energy_act_pJ\": %.1f, \"energy_pre_pJ\": %.1f, "
            "\"energy_rd_pJ\": %.1f, \"energy_wr_pJ\": %.1f, \"energy_ref_pJ\": %.1f, "
            "\"energy_act_stby_pJ\": %.1f, \"energy_pre_stby_pJ\": %.1f, \"act_cycles\": %llu, \"pre_cycles\": %llu}\n",
            (long long)s->dram_cycles, s->time_ns, s->bw_GBps, s->read_lat_avg_cycles, s->row_hit_rate,
            (unsigned long long)s->n_act, (unsigned long long)s->n_pre, (unsigned long long)s->n_prea,
            (unsigned long long)s->n_ref, (unsigned long long)s->n_rd, (unsigned long long)s->n_wr, s->energy_uJ,
            s->energy_pJ_per_byte, (unsigned long long)s->row_hits, (unsigned long long)s->row_misses,
            (unsigned long long)s->row_conflicts, (unsigned long long)s->reads_forwarded,
            (unsigned long long)s->bytes, (unsigned long long)s->n_pre_banks, s->energy.act_pJ, s->energy.pre_pJ,
            s->energy.rd_pJ, s->energy.wr_pJ, s->energy.ref_pJ, s->energy.act_stby_pJ, s->energy.pre_stby_pJ,
            (unsigned long long)s->energy.act_cycles, (unsigned long long)s->energy.pre_cycles);
}

void dram_summary_text(const dram_summary *s, FILE *o)
{
    fprintf(o, "DRAM cycles          %lld\n", (long long)s->dram_cycles);
    fprintf(o, "time                 %.1f ns\n", s->time_ns);
    fprintf(o, "bandwidth            %.4f GB/s (%llu bytes)\n", s->bw_GBps, (unsigned long long)s->bytes);
    fprintf(o, "mean read latency    %.2f cycles\n", s->read_lat_avg_cycles);
    fprintf(o, "row-hit rate         %.5f (hits %llu, misses %llu, conflicts %llu)\n", s->row_hit_rate,
            (unsigned long long)s->row_hits, (unsigned long long)s->row_misses, (unsigned long long)s->row_conflicts);
    fprintf(o, "reads forwarded      %llu\n", (unsigned long long)s->reads_forwarded);
    fprintf(o, "commands             ACT %llu  PRE %llu  PREA %llu  REF %llu  RD %llu  WR %llu\n",
            (unsigned long long)s->n_act, (unsigned long long)s->n_pre, (unsigned long long)s->n_prea,
            (unsigned long long)s->n_ref, (unsigned long long)s->n_rd, (unsigned long long)s->n_wr);
    fprintf(o, "energy               %.3f uJ (%.3f pJ/byte)\n", s->energy_uJ, s->energy_pJ_per_byte);
    fprintf(o, "  pJ: ACT %.0f  PRE %.0f  RD %.0f  WR %.0f  REF %.0f  act-stby %.0f  pre-stby %.0f\n",
            s->energy.act_pJ, s->energy.pre_pJ, s->energy.rd_pJ, s->energy.wr_pJ, s->energy.ref_pJ,
            s->energy.act_stby_pJ, s->energy.pre_stby_pJ);
}
