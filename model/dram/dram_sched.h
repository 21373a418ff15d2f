/* dram_sched.h — the DRAM controller's command scheduler (internal to
 * model/dram): which queued request's next command issues this cycle, FR-FCFS
 * with a row-hit cap (dram_ctrl.h gives the policy), and lower bounds on the
 * cycle of the next issue that let the controller skip idle cycles.
 *
 * Contract:
 *  - The scheduler reads the channel state (dram_ctrl_state.h) and writes only
 *    ch->sched_wake: 0 = unknown (scan at the next tick), else no command can
 *    issue before that cycle unless the queues or bank states change.
 *  - A request's next command follows from its bank (Ramulator decode/prereq:
 *    ACT if closed, PRE if another row is open, RD/WR on a row hit; a refresh
 *    needs PREA while a bank of its rank is open, then REF); it may issue at
 *    the max of its channel's, rank's and (bank commands) bank's next[].
 *  - Exhaustive mode (c->exhaustive) scans every entry every cycle; the default
 *    scans per bank and request class with the same result. */
#ifndef RTSIM_DRAM_SCHED_H
#define RTSIM_DRAM_SCHED_H

#include "model/dram/dram_ctrl_state.h"

/* At clock c->clk: actq first, then refresh (otherq), then the queue of the
 * current mode. Returns the pool slot of the request whose command issues now,
 * with that command in *cmd and its queue in *from; -1 when nothing can issue
 * (sched_wake then holds the bound the scan found). */
int dram_sched_choose(const dram_ctrl *c, dchan *ch, dqueue **from, int *cmd);
/* After a command issued: sets sched_wake when the next tick's scan would find
 * nothing (so that tick need not scan). */
void dram_sched_after_issue(const dram_ctrl *c, dchan *ch);
/* Request r was just added to q: folds its earliest cycle into sched_wake. */
void dram_sched_added(const dram_ctrl *c, dchan *ch, const dqueue *q, const dreq *r);
/* min(lo, earliest cycle of the next command of any entry of q). */
int64_t dram_sched_queue_bound(const dram_ctrl *c, dchan *ch, const dqueue *q, int64_t lo);
/* The earliest cycle of the next command of any read or write not yet issued
 * (actq, readq, writeq); INT64_MAX when there is none. */
int64_t dram_sched_requests_bound(const dram_ctrl *c, dchan *ch);

#endif
