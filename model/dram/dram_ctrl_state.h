/* dram_ctrl_state.h — the state of the DRAM controller (dram_ctrl.h), shared
 * by its files and by nothing else: dram_ctrl.c (public API, bank state
 * machines, refresh, tick) changes it; dram_sched.c (FR-FCFS-Cap: which
 * request's command issues next) reads it and sets only a channel's
 * sched_wake; dram_queue.c keeps the queues.
 *
 * Per channel, rank and bank, next[cmd] is the earliest cycle each command may
 * issue, raised by issue() from the spec's constraint rows (Ramulator's "next"
 * scheme); a command may issue at the max of its channel's, rank's and (bank
 * commands) bank's next[]. */
#ifndef RTSIM_DRAM_CTRL_STATE_H
#define RTSIM_DRAM_CTRL_STATE_H

#include "model/dram/dram_ctrl.h"
#include "model/dram/dram_queue.h"

typedef struct dbank {
    int64_t next[DRAM_NCMD];   /* earliest cycle each command may issue (bank constraints); the
                                  command may issue at the max of this and the channel's and
                                  rank's next[] (combined where needed, not kept per bank: a
                                  command changes the channel's next[] of every bank at once) */
    int32_t open_row;          /* -1 = closed */
    int32_t hits;              /* RD/WR to the open row since its ACT (Ramulator RowTable) */
    int64_t pad;               /* to 64 bytes: the class scans index banks by a shift */
} dbank;

typedef struct drank {
    int64_t next[DRAM_NCMD];
    int64_t hist[DRAM_NCMD][DRAM_MAX_WINDOW]; /* latest issue cycles, newest first */
    int nopen;                 /* open banks */
    int64_t open_since;        /* cycle the first bank opened (energy background) */
} drank;

typedef struct dchan {
    int64_t next[DRAM_NCMD];
    int64_t bound[DRAM_NCMD];  /* fast scan (one rank): max of next[] and rank 0's next[], the
                                  channel/rank bound of the class scans, kept by issue() */
    int64_t hist[DRAM_NCMD][DRAM_MAX_WINDOW];
    dqueue readq, writeq, actq, otherq;
    dreq_pool pool;            /* entry slots of the four queues */
    dpend_ring pend;           /* reads waiting for their data, FIFO */
    drank *ranks;
    dbank *banks;              /* rank-major */
    int write_mode;
    uint64_t open_mask;        /* banks 0..63 with an open row */
    uint64_t capped_mask;      /* banks 0..63 whose row hits exceed the cap */
    int64_t sched_wake;        /* no command can issue before this cycle unless the queues or
                                  bank states change (0 = unknown: run the scheduler) */
    int64_t refreshed;         /* cycle of the last refresh injection */
    int64_t refresh_due;       /* refreshed + refresh interval (the next injection) */
    int rd_live, wr_live;      /* reads / writes in readq, writeq or actq (not yet issued) */
    int64_t occ_upto;          /* queue_occupancy_sum covers the ticks up to this cycle: the
                                  count is constant between changes, so it is added per change
                                  (occ_flush) rather than per tick */
    dram_chan_stats st;
} dchan;

/* One row of a command's flattened list (scope 0 channel, 1 rank, 2 bank). */
typedef struct issue_row {
    uint8_t scope, to, window;
    int32_t cycles;
} issue_row;

/* Constraint rows grouped by (scope, FROM). */
typedef struct cons_row {
    uint8_t to, window;
    int32_t cycles;
} cons_row;

struct dram_ctrl {
    const dram_spec *spec;
    dram_addrmap map;
    dram_done_fn done;
    void *done_user;
    dram_cmd_fn cmd_sink;
    void *cmd_user;
    int64_t clk;
    int nch, nrank, nbank;
    int write_high_pct;
    int wq_hi, wq_lo;          /* write-mode watermarks in entries (from the percentages) */
    int pending;               /* requests not yet done, all channels (dram_pending) */
    int fast_scan;             /* one rank, <= 64 banks: pick_counted1 */
    int exhaustive;            /* run the scheduler every cycle, never skip (reference mode) */
    dchan *ch;
    cons_row rows[DRAM_MAX_CONSTRAINTS];
    int row_start[DRAM_NSCOPE][DRAM_NCMD], row_count[DRAM_NSCOPE][DRAM_NCMD];
    int max_window[DRAM_NSCOPE][DRAM_NCMD];
    /* per FROM command, its channel, rank and (bank commands) bank rows in one list,
     * the scope as the target index (0 channel, 1 rank, 2 bank): issue() applies them
     * in one loop (each row only raises a next[], so the order does not matter); the
     * first n_irows1 have a window of 1 (measured from now: no history look-up) */
    issue_row irows[DRAM_NCMD][DRAM_MAX_CONSTRAINTS];
    int n_irows[DRAM_NCMD], n_irows1[DRAM_NCMD];
    unsigned bound_mask[DRAM_NCMD]; /* per FROM command, the TO commands of its channel and
                                       rank rows (the bound[] entries it can raise) */
};

static inline int64_t max64(int64_t a, int64_t b) { return a > b ? a : b; }

#endif
