/* sim.h — the simulation context: scheduler, run control, deadlock detector.
 *
 * Contract (SystemC semantics where they matter):
 *  - One ks_sim owns every event, process, clock, FIFO and signal created on
 *    it; ks_sim_destroy frees them all. Not thread-safe; one sim per thread.
 *  - A run repeats: evaluate (run every runnable method process, clock steps
 *    included, in a deterministic order) -> update (apply requested signal
 *    updates) -> delta notification (trigger delta-notified events) -> next
 *    delta while anything is runnable; then time advances to the earliest
 *    timed notification. Entries at the same time fire in the order they were
 *    notified (a global sequence number), so runs are bit-for-bit repeatable.
 *  - ks_sim_run(sim, until) processes everything at times <= until and
 *    returns why it stopped; it can be called again to continue.
 *  - Deadlock detector (progress based, armed when the sim has clocked
 *    processes): clocked processes report progress (their step's return
 *    value; methods may call ks_sim_progress). Work is pending when a FIFO
 *    holds items, a process's busy callback says so, or a clocked process is
 *    awake. When nothing at all is left to run while work is pending, or no
 *    progress was reported for ks_sim_set_deadlock_cycles() cycles of the
 *    first clock (default 100000; 0 disables) while work is pending, the run
 *    stops with KS_RUN_DEADLOCK and ks_sim_deadlock_report() tells which
 *    processes wait on which events/channels. A run never hangs silently. */
#ifndef KS_SIM_H
#define KS_SIM_H

#include <stdint.h>
#include <stdio.h>

#include "kernel/time.h"

typedef struct ks_sim ks_sim;

typedef enum ks_run_status {
    KS_RUN_FINISHED = 0,   /* nothing left to do (no pending activity) */
    KS_RUN_TIME_LIMIT = 1, /* reached `until` with activity still pending */
    KS_RUN_DEADLOCK = 2,   /* the deadlock detector fired; see the report */
    KS_RUN_STOPPED = 3,    /* ks_sim_stop() was called */
} ks_run_status;

ks_sim *ks_sim_create(void);
void ks_sim_destroy(ks_sim *sim);

/* Current simulated time in picoseconds. */
ks_time ks_sim_now(const ks_sim *sim);
/* Number of delta cycles executed so far (all times). */
uint64_t ks_sim_delta_count(const ks_sim *sim);
/* Number of process activations (method runs + clocked steps) so far. */
uint64_t ks_sim_activations(const ks_sim *sim);

/* Runs until nothing is pending, `until` is passed, stop or deadlock.
 * On KS_RUN_TIME_LIMIT, now == until afterwards. */
ks_run_status ks_sim_run(ks_sim *sim, ks_time until);
/* Requests the run to stop after the current delta cycle. */
void ks_sim_stop(ks_sim *sim);
const char *ks_run_status_name(ks_run_status st);

/* Deadlock detection window in cycles of the first clock created (or of a
 * 500 MHz clock when there is none); 0 disables the timed part. */
void ks_sim_set_deadlock_cycles(ks_sim *sim, uint64_t cycles);
/* Reports `n` units of progress made by a method process (clocked processes
 * report theirs as the return value of their step function). */
void ks_sim_progress(ks_sim *sim, uint64_t n);
/* Total progress reported so far. */
uint64_t ks_sim_total_progress(const ks_sim *sim);
/* The report of the last deadlock (multi-line text), "" if none. */
const char *ks_sim_deadlock_report(const ks_sim *sim);

/* Text of the last API misuse error (e.g. invalid FIFO parameters), "" if
 * none; functions that can fail return NULL / -1 and set it. */
const char *ks_sim_error(const ks_sim *sim);

#endif
