/* fidelity_params.h — the constants of the cheaper fidelity levels: the
 * functional level's throughput model, the pilots and samples, and the error
 * model of each level. Each value is a measurement of the full model (how it
 * was measured: docs/fidelity.md "Parameters"), not a property of the
 * machine, so it lives here and not in the machine configuration. */
#ifndef RTSIM_FIDELITY_PARAMS_H
#define RTSIM_FIDELITY_PARAMS_H

typedef struct fid_params {
    /* functional throughput model */
    double dram_latency;          /* unloaded LPDDR3 row-hit read, accelerator cycles, queueing excluded */
    double row_miss_cycles;       /* extra cycles of a row miss (precharge + activate) */
    double queue_cycles;          /* scale of the u / (1 - u) queueing term at DRAM utilisation u */
    double ist_loop_extra;        /* cycles of an IST loop round trip beyond the test pipeline */
    double mem_side_fifo_cycles;  /* L1 miss -> L2 -> fill FIFO hops */
    double max_util;              /* cap of the DRAM utilisation in the queueing term */
    double miss_waiters;          /* rays waiting per missing line (Little's law term) */
    int func_phases;              /* phases of the primaries for fid_func.phase_excess */
    double func_err_base;         /* functional: relative MRPS error when one bound dominates */
    double func_err_tie;          /* functional: added error as the runner-up bound reaches a tie */
    double func_err_mem;          /* functional: added error per unit of DRAM utilisation x row-miss rate */
    double func_tie_flag;         /* functional: runner-up/bound ratio from which it is flagged */
    double func_err_dram;         /* functional: relative DRAM MB error (order of accesses) */
    double func_err_energy;       /* functional: relative mJ/frame error */
    /* fixed-mem */
    double pilot_fraction;        /* of the pixels, in interleaved row bands */
    double pilot_min_pixels;      /* at least this many (or the whole frame) */
    double fixed_max_util;        /* DRAM utilisation of the pilot beyond which calibration does not hold */
    double fixed_max_latency_ratio; /* pilot mean latency / unloaded latency beyond which it is saturated */
    double fixed_err_base;        /* fixed-mem: relative MRPS error at low utilisation */
    double fixed_err_util;        /* fixed-mem: added error per unit of utilisation squared */
    /* sampled */
    double sample_rate;           /* default fraction of the pixels */
    int sample_groups;            /* independent groups (confidence interval) */
    double sample_t95;            /* Student t, 95%, sample_groups - 1 degrees of freedom */
    double sample_max_err;        /* estimated error beyond which a sampled result is flagged */
    double sample_err_dram;       /* sampled: bias bound of the DRAM ratio estimator */
    double sample_give_up;        /* --accuracy: the groups' prediction taken at 1/this of itself decides sampled's frame pass */
    double sample_retry_margin;   /* --accuracy: sampled's second rate, x this margin */
    double sample_retry_max_rate; /* --accuracy: no second try of sampled beyond this rate */
    double sample_err_floor;      /* sampled: floor added to every estimate (bias of the ratio estimator) */
    int band_rows;                /* rows per band of a sample */
    /* windowed */
    double win_rate;              /* default fraction of the pixels through the model, warm-ups included */
    int win_count;                /* windows */
    int win_min_count;            /* fewer windows than this: shorter ones instead */
    double win_warm_pixels;       /* pixels of the warm-up before each window */
    double win_min_pixels;        /* shortest window */
    double win_tail_pixels;       /* pixels queued after a window so the pipeline stays full to its end */
    int win_lattice;              /* 1 pixel in this many through the functional level for the frame's
                                     auxiliary figures */
    double win_err_floor;         /* added to every estimate: boundary effects of the windows */
    double win_max_cold;          /* share of cold fills in the windows beyond which the warm-ups are too short */
    double win_max_rate;          /* --accuracy: most of the frame the windows may take before full is cheaper */
    int win_snapshot;             /* 1: functional warming: each window's caches start from the lattice's */
    double win_snap_warm_pixels;  /* with win_snapshot: the detailed warm-up after the caches are loaded */
    int win_snap_count;           /* with win_snapshot: windows of the default plan */
    double win_snap_max_bytes;    /* with win_snapshot: memory the windows' cache contents may take */
    double win_probe_pixels;      /* --accuracy's cold probe: pixels measured after its warm-up */
    double win_probe_max_cold;    /* --accuracy: the probe's cold-fill share beyond which windowed is not tried */
    double win_probe_min_turnover; /* --accuracy: the frame's fills over the caches' lines (from the probe) below
                                      which windowed is not tried */
    int win_pilot_windows;        /* --accuracy: windows run before predicting whether the plan can meet the target */
} fid_params;

const fid_params *fid_params_get(void);

#endif
