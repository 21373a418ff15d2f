/* clock.h — clocks and clocked processes with idle skipping.
 *
 * Contract:
 *  - A clock has rising edges at times k * period (cycle k = 0, 1, ...);
 *    period 0 means KS_DEFAULT_PERIOD_PS (500 MHz).
 *  - A clocked process has a step function called at the edge of cycle k
 *    while it is awake: `int step(void *user, uint64_t cycle)` returns the
 *    progress it made (0 = nothing to do, ChampSim style). Processes of one
 *    clock are stepped in creation order, inside one evaluate phase; clocks
 *    with an edge at the same time tick in creation order, before the
 *    methods of that time.
 *  - A step sees what earlier steps of the same edge did (a FIFO slot freed,
 *    an item written with latency 0). So that idle skipping never changes
 *    what a process sees, a delta/immediate wake-up (FIFO freed, latency-0
 *    written, ks_clocked_wake) made by a step wakes the process in the same
 *    edge when it steps later in that order (later on the same clock, or on
 *    a later-created clock with an edge at that time), else at its next edge.
 *  - Idle skipping: a step returning 0 puts the process to sleep until an
 *    event it was registered on with ks_clocked_wake_on() is notified, or
 *    an explicit wake (ks_clocked_wake / _wake_at_cycle), or the cycle given
 *    to ks_clocked_sleep_until_cycle() during that step. A step returning
 *    > 0 keeps it awake for the next cycle unless it called
 *    ks_clocked_sleep_until_cycle(). When no process of a clock is awake the
 *    clock does not tick at all: time jumps to the next wake-up.
 *  - Wake-ups may be spurious; a step with nothing to do must change nothing
 *    and return 0. Under that rule results are bit-identical to stepping
 *    every process every cycle (ks_clock_set_exhaustive, the reference mode
 *    the equivalence test compares against).
 *  - Every process starts awake at the first edge after its creation.
 *  - Progress counts feed the deadlock detector (sim.h); a busy/describe
 *    callback (process.h types) adds the unit's state to deadlock reports.
 *  - ks_clock_posedge(): an event notified at every edge while any method
 *    is statically sensitive to it (this forces per-cycle ticking). */
#ifndef KS_CLOCK_H
#define KS_CLOCK_H

#include <stdint.h>

#include "kernel/event.h"
#include "kernel/process.h"
#include "kernel/sim.h"
#include "kernel/time.h"

typedef struct ks_clock ks_clock;
typedef struct ks_clocked ks_clocked;
typedef int (*ks_step_fn)(void *user, uint64_t cycle);

ks_clock *ks_clock_create(ks_sim *sim, const char *name, ks_time period);
const char *ks_clock_name(const ks_clock *clk);
ks_time ks_clock_period(const ks_clock *clk);
/* The cycle whose edge was processed last (0 before the first edge). */
uint64_t ks_clock_cycle(const ks_clock *clk);
/* Number of edges at which the clock actually ticked (idle ones skipped). */
uint64_t ks_clock_ticks(const ks_clock *clk);
/* Edge time of cycle k, and the first cycle whose edge is at or after t. */
ks_time ks_clock_time_of(const ks_clock *clk, uint64_t cycle);
uint64_t ks_clock_cycle_at_or_after(const ks_clock *clk, ks_time t);
/* Reference mode: every process is stepped every cycle, sleeps ignored,
 * as long as anything is left to happen in the simulation (a process awake
 * or with a timer on any clock, a timed method or event entry); when
 * nothing is, the clock stops as with idle skipping and a wake-up restarts
 * it. Results must equal idle skipping's (tb_kernel_clock_* tests). */
void ks_clock_set_exhaustive(ks_clock *clk, int on);
ks_event *ks_clock_posedge(ks_clock *clk);

ks_clocked *ks_clocked_create(ks_clock *clk, const char *name, ks_step_fn step, void *user);
const char *ks_clocked_name(const ks_clocked *p);
ks_clock *ks_clocked_clock(const ks_clocked *p);
/* Static wake-up sensitivity (typically FIFO written/freed events). */
void ks_clocked_wake_on(ks_clocked *p, ks_event *ev);
/* From a step: sleep (even if the step returns > 0) until `cycle` (or an
 * earlier event wake-up). */
void ks_clocked_sleep_until_cycle(ks_clocked *p, uint64_t cycle);
/* Wake at the next edge after now / at the given cycle (>= next edge). */
void ks_clocked_wake(ks_clocked *p);
void ks_clocked_wake_at_cycle(ks_clocked *p, uint64_t cycle);
void ks_clocked_set_describe(ks_clocked *p, ks_busy_fn busy, ks_describe_fn describe);
/* Number of times the process was stepped. */
uint64_t ks_clocked_steps(const ks_clocked *p);
/* Sum of the progress its steps returned. */
uint64_t ks_clocked_progress(const ks_clocked *p);

#endif
