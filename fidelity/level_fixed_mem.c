/* level_fixed_mem.c — fixed-mem (docs/fidelity.md): the whole frame on a
 * fixed-latency memory calibrated from a full-fidelity pilot on row bands
 * (job->cfg's memory keys are changed for the runs, then restored); its
 * error estimate, and its flags where the DRAM saturates. */
#include "fidelity/levels.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "fidelity/fidelity_params.h"
#include "model/mem/memsys_config.h"

/* Saves and restores the memory keys fixed-mem changes. */
typedef struct mem_keys {
    char model[32], latency[32], bw[64], pj[64];
} mem_keys;

static void save_keys(const rtcfg *cfg, mem_keys *k)
{
    snprintf(k->model, sizeof k->model, "memory.model=%s", rtcfg_str(cfg, "memory.model"));
    snprintf(k->latency, sizeof k->latency, "memory.fixed_latency=%lld", (long long)rtcfg_int(cfg, "memory.fixed_latency"));
    snprintf(k->bw, sizeof k->bw, "memory.fixed_bandwidth_gbs=%.17g", rtcfg_real(cfg, "memory.fixed_bandwidth_gbs"));
    snprintf(k->pj, sizeof k->pj, "energy.fixed_mem_pj_per_byte=%.17g", rtcfg_real(cfg, "energy.fixed_mem_pj_per_byte"));
}

static int restore_keys(rtcfg *cfg, const mem_keys *k, char *err, size_t errlen)
{
    return rtcfg_set(cfg, k->model, err, errlen) || rtcfg_set(cfg, k->latency, err, errlen) ||
                   rtcfg_set(cfg, k->bw, err, errlen) || rtcfg_set(cfg, k->pj, err, errlen)
               ? 2
               : 0;
}

static int set_fixed(rtcfg *cfg, double latency, double pj, char *err, size_t errlen)
{
    char a[64], b[64];
    snprintf(a, sizeof a, "memory.fixed_latency=%lld", (long long)llround(latency < 1 ? 1 : latency));
    snprintf(b, sizeof b, "energy.fixed_mem_pj_per_byte=%.6g", pj);
    return rtcfg_set(cfg, "memory.model=fixed", err, errlen) || rtcfg_set(cfg, a, err, errlen) ||
                   rtcfg_set(cfg, b, err, errlen)
               ? 2
               : 0;
}

/* fixed-mem: a full pilot on interleaved row bands measures the memory (mean
 * latency, achieved bandwidth, DRAM energy per byte); the fixed model's
 * latency is fitted so that the pilot's cycles match (two fixed pilots and
 * a secant step); then the whole frame runs on the fitted fixed memory. */
int fid_lv_fixed_mem(const fid_job *job, fid_outcome *o, char *err, size_t errlen)
{
    const fid_params *fp = fid_params_get();
    rtcfg *cfg = job->cfg;
    fid_result *r = &o->res;
    r->level = FID_FIXED_MEM;
    if (rtcfg_enum(cfg, "memory.model") != MEMSYS_LPDDR3) {
        model_fig f;
        snprintf(r->detail, sizeof r->detail, "memory.model is already fixed: the full model of this machine");
        return fid_run_model_series(job, cfg, NULL, 0, &f, &o->top, "frame", 0, err, errlen);
    }
    mem_keys saved;
    save_keys(cfg, &saved);
    uint32_t period = fid_pilot_period(job, fp->pilot_fraction), n = 0;
    uint32_t *px = NULL;
    if (period > 1 && !(px = fid_band_subset(job, period, 0, 1, &n))) {
        snprintf(err, errlen, "out of memory");
        return 2;
    }
    model_fig full, f0, f1, fin;
    double L = 0, util = 0, resid = 0, dram_static_share = 0, pilot_latency = 0, pilot_row_hit = 1;
    int rc = fid_run_model(job, cfg, px, n, &full, NULL, err, errlen);
    if (rc == 0) {
        double gbs = rtcfg_real(cfg, "memory.fixed_bandwidth_gbs");
        double bpc = gbs * 1000.0 / rtcfg_real(cfg, "machine.clock_mhz");
        util = gbs > 0 ? full.dram_gbs / gbs : 0;
        double line = full.mem_requests > 0 ? full.dram_bytes / full.mem_requests : 64;
        /* the fixed model moves the line over its bus before the latency */
        double L0 = fmax(1.0, full.mem_latency - (bpc > 0 ? line / bpc : 0));
        double pj = full.dram_bytes > 0 ? full.dram_mj * 1e9 / full.dram_bytes : rtcfg_real(cfg, "energy.fixed_mem_pj_per_byte");
        L = L0;
        dram_static_share = full.energy_mj > 0 ? full.dram_static_mj / full.energy_mj : 0;
        pilot_latency = full.mem_latency, pilot_row_hit = full.row_hit;
        if (!(rc = set_fixed(cfg, L0, pj, err, errlen)))
            rc = fid_run_model(job, cfg, px, n, &f0, NULL, err, errlen);
        if (rc == 0 && full.cycles > 0 && fabs(f0.cycles - full.cycles) > 0.005 * full.cycles) {
            double L1 = fmax(1.0, L0 * (f0.cycles > full.cycles ? 0.7 : 1.3));
            if (!(rc = set_fixed(cfg, L1, pj, err, errlen)))
                rc = fid_run_model(job, cfg, px, n, &f1, NULL, err, errlen);
            if (rc == 0 && fabs(f1.cycles - f0.cycles) > 0.5)
                L = L0 + (full.cycles - f0.cycles) * (L1 - L0) / (f1.cycles - f0.cycles);
            else if (rc == 0)
                L = L1;
            L = fmin(fmax(L, 1.0), 20.0 * L0 + 100.0);
            resid = fmin(fabs(f0.cycles - full.cycles), fabs(f1.cycles - full.cycles)) / full.cycles;
            if (fabs(f1.cycles - full.cycles) < fabs(f0.cycles - full.cycles) && fabs(f1.cycles - f0.cycles) <= 0.5)
                L = L1;
        }
        if (rc == 0 && !(rc = set_fixed(cfg, L, pj, err, errlen)))
            rc = fid_run_model_series(job, cfg, NULL, 0, &fin, &o->top, "frame", 0, err, errlen);
        snprintf(r->detail, sizeof r->detail,
                 "full-fidelity pilot on %u of %u pixels (row bands): mean memory latency %.1f cycles, %.2f GB/s "
                 "(%.0f%% of peak), %.0f%% row hits; fixed memory calibrated to latency %.0f cycles, %.0f pJ/byte",
                 px ? n : job->width * job->height, job->width * job->height, full.mem_latency, full.dram_gbs,
                 100.0 * util, 100.0 * full.row_hit, L, pj);
    }
    if (restore_keys(cfg, &saved, err, errlen) && rc == 0)
        rc = 2;
    free(px);
    r->err_mrps = fp->fixed_err_base + fp->fixed_err_util * util * util + resid;
    r->err_dram_mb = fp->fixed_err_base;
    /* the DRAM's background energy follows time, not bytes: the pJ/byte of
     * the pilot carries it only at the pilot's bytes per second */
    r->err_energy_mj = r->err_mrps + dram_static_share;
    if (util > fp->fixed_max_util) {
        char why[200];
        snprintf(why, sizeof why,
                 "fixed-mem: the pilot's DRAM utilisation %.0f%% exceeds %.0f%%: queueing and row conflicts at "
                 "saturation are outside the range the calibration holds",
                 100.0 * util, 100.0 * fp->fixed_max_util);
        fid_set_unreliable(r, why);
    }
    /* saturation shows in the latency as well: with few row hits the
     * LPDDR3 saturates far below its peak bandwidth (the furball stand-in:
     * 59% of peak, 37% row hits, 203 cycles mean latency) */
    double unloaded = fp->dram_latency + (1.0 - pilot_row_hit) * fp->row_miss_cycles;
    if (pilot_latency > fp->fixed_max_latency_ratio * unloaded) {
        char why[240];
        snprintf(why, sizeof why,
                 "fixed-mem: the pilot's mean memory latency %.0f cycles is %.1f times the unloaded %.0f: the "
                 "DRAM is saturated, where one fixed latency stands for a queue that changes with the load",
                 pilot_latency, pilot_latency / unloaded, unloaded);
        fid_set_unreliable(r, why);
    }
    return rc;
}
