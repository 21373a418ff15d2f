/* dram_ctrl.h — command-level DRAM memory controller (all channels of a memory),
 * independent of the simulation kernel, with a DRAMsim3-like API.
 *
 * Per channel: read, write, activated ("actq") and other (refresh) queues; per
 * bank a state machine (closed / open row) and per channel, rank and bank the
 * earliest cycle each command may issue, maintained from the constraint rows of
 * the spec (dram_timing.h) when a command issues (Ramulator's "next" scheme).
 * Policy (reproduces Ramulator v1, lpddr3_1600_timing.txt:57-66):
 *  - open page: rows close only on a conflict or by PREA before refresh;
 *  - FR-FCFS with a row-hit cap: the oldest request whose next command can
 *    issue this cycle and whose row has had <= cap hits, else the oldest;
 *    requests whose ACT issued move to actq, served first;
 *  - write mode when writeq > high% or readq empty; back to reads when
 *    writeq < low% and reads wait; a read that matches a queued write's
 *    address completes one cycle later without a DRAM access;
 *  - every refresh_interval cycles an all-bank REF per rank joins otherq, which
 *    has priority over reads/writes; it needs PREA first if a bank is open;
 *  - at most one command per channel per cycle; one read completion per cycle.
 *
 * Contract:
 *  - dram_add() enqueues at the current cycle; it returns false (nothing
 *    changes) when the target queue is full, which dram_will_accept() predicts.
 *  - dram_tick() advances one DRAM clock: completes at most one read per
 *    channel (callback), injects refresh, issues at most one command per channel.
 *  - Completion callback: reads when their data is complete (latency = done -
 *    enqueue cycle); writes when their WR command issues (latency likewise).
 *  - dram_next_event() is a lower bound on the next cycle at which a tick could
 *    change anything while no request is added; dram_skip() jumps the clock to
 *    just before it, dram_advance_to() to a given cycle (results are
 *    bit-identical to ticking through).
 * Deterministic: no randomness, no dependence on host state. */
#ifndef RTSIM_DRAM_CTRL_H
#define RTSIM_DRAM_CTRL_H

#include <stdbool.h>
#include <stdint.h>

#include "model/dram/dram_addrmap.h"
#include "model/dram/dram_timing.h"

typedef struct dram_ctrl dram_ctrl;

/* Request done. latency in DRAM cycles; forwarded reads report 1. */
typedef void (*dram_done_fn)(void *user, uint64_t addr, uint64_t tag, bool is_write, int64_t latency);

/* One issued command (for --cmd-trace, the timing checker and tests). bank is
 * -1 for rank commands (PREA, REF); row is -1 except for ACT. */
typedef struct dram_cmd_rec {
    int64_t cycle;
    int channel, rank, bank, row;
    int cmd;               /* enum dram_cmd */
} dram_cmd_rec;
typedef void (*dram_cmd_fn)(void *user, const dram_cmd_rec *rec);

/* Per-channel statistics (all counters since creation). */
typedef struct dram_chan_stats {
    uint64_t n_cmd[DRAM_NCMD];
    uint64_t n_pre_banks;      /* banks closed: PRE of an open bank + open banks at PREA (DRAMPower's count) */
    uint64_t row_hits, row_misses, row_conflicts;
    uint64_t reads_done;       /* reads completed through DRAM */
    uint64_t reads_forwarded;  /* reads answered from the write queue */
    uint64_t writes_done;
    uint64_t read_latency_sum; /* over reads_done */
    uint64_t open_cycles;      /* cycles with >= 1 bank open, summed over ranks (energy) */
    uint64_t queue_occupancy_sum; /* readq + writeq + pending, summed per tick */
} dram_chan_stats;

/* The spec must outlive the controller. Returns NULL with a message on a bad mapping. */
dram_ctrl *dram_ctrl_create(const dram_spec *spec, dram_done_fn done, void *user, char *err, size_t errlen);
void dram_ctrl_destroy(dram_ctrl *c);

/* Optional command sink, called for every issued command in issue order. */
void dram_set_cmd_sink(dram_ctrl *c, dram_cmd_fn fn, void *user);

bool dram_will_accept(const dram_ctrl *c, uint64_t addr, bool is_write);
bool dram_add(dram_ctrl *c, uint64_t addr, bool is_write, uint64_t tag);
void dram_tick(dram_ctrl *c);

/* Cycles ticked so far (the cycle of the last tick). */
int64_t dram_clock(const dram_ctrl *c);
/* Requests not yet done, including refresh requests waiting in otherq. */
int dram_pending(const dram_ctrl *c);
/* Lower bound (> dram_clock) on the next cycle at which dram_tick could act. */
int64_t dram_next_event(const dram_ctrl *c);
/* Lower bound (> dram_clock) on the next cycle at which dram_tick could complete a
 * request (done callback) while no request is added: a caller that only needs
 * completions (kernel port) may sleep until then and catch up with
 * dram_advance_to. */
int64_t dram_next_completion(const dram_ctrl *c);
/* Advances the clock over idle cycles to dram_next_event()-1; returns cycles skipped. */
int64_t dram_skip(dram_ctrl *c);
/* Advances the clock to `cycle` (no-op if already there or past): ticks where
 * something can happen, skips the idle stretches in between; bit-identical to
 * calling dram_tick() until dram_clock() == cycle. Lets a caller that sleeps
 * (kernel port) catch up lazily, refreshes included. */
void dram_advance_to(dram_ctrl *c, int64_t cycle);

/* Reference mode for tests: scan the queues every cycle and never skip; results
 * must be identical to the default (fast) mode. */
void dram_set_exhaustive(dram_ctrl *c, bool on);

/* Write high watermark in percent (the final drain of a trace sets 0). */
void dram_set_write_high_pct(dram_ctrl *c, int pct);

const dram_spec *dram_ctrl_spec(const dram_ctrl *c);
const dram_addrmap *dram_ctrl_addrmap(const dram_ctrl *c);
/* Statistics of one channel; open_cycles includes still-open intervals up to now. */
void dram_chan_stats_get(const dram_ctrl *c, int channel, dram_chan_stats *out);

#endif
