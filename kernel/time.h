/* time.h — simulated time of the rtsim kernel.
 *
 * Contract: time is a signed 64-bit count of picoseconds (ks_time), so every
 * clock period of interest (500 MHz = 2000 ps, LPDDR3-1600 = 1250 ps) is exact
 * and runs of up to ~106 days of simulated time fit. KS_TIME_MAX means
 * "forever" (e.g. ks_sim_run(sim, KS_TIME_MAX) runs until nothing is left). */
#ifndef KS_TIME_H
#define KS_TIME_H

#include <stdint.h>

typedef int64_t ks_time;

#define KS_TIME_MAX INT64_MAX
#define KS_PS(x) ((ks_time)(x))
#define KS_NS(x) ((ks_time)(x) * 1000)
#define KS_US(x) ((ks_time)(x) * 1000000)
#define KS_MS(x) ((ks_time)(x) * 1000000000)

/* 500 MHz, the accelerator's clock (docs/design.md "Hardware defaults"). */
#define KS_DEFAULT_PERIOD_PS ((ks_time)2000)

#endif
