/* dram_checker.h — independent timing checker: replays a command stream and
 * reports every violated rule of a dram_spec. It shares only the spec (the
 * constraint rows) with the controller, not its bookkeeping: it keeps the issue
 * history per channel/rank/bank and measures each distance directly.
 * Rules checked for each command:
 *  - every constraint row "<scope> FROM -> TO [window N] = cycles" with TO = the
 *    command: distance from the N-th latest FROM in that scope >= cycles;
 *  - bank state: ACT needs a closed bank; RD/WR need an open bank; REF needs all
 *    banks of the rank closed;
 *  - command bus: one command per channel per cycle, cycles non-decreasing;
 *  - refresh: consecutive REFs of a rank (and the first) no more than
 *    (1 + max_postponed_refresh) * refresh_interval apart (checked up to the end). */
#ifndef RTSIM_DRAM_CHECKER_H
#define RTSIM_DRAM_CHECKER_H

#include <stdint.h>
#include <stdio.h>

#include "model/dram/dram_ctrl.h"
#include "model/dram/dram_timing.h"

typedef struct dram_checker dram_checker;

/* report: where to print each violation (one line each, at most max_report lines; NULL = silent). */
dram_checker *dram_checker_create(const dram_spec *spec, FILE *report, int max_report);
void dram_checker_destroy(dram_checker *k);
void dram_checker_feed(dram_checker *k, const dram_cmd_rec *rec);
/* Checks the refresh gaps up to end_cycle; returns the total number of violations. */
uint64_t dram_checker_finish(dram_checker *k, int64_t end_cycle);
uint64_t dram_checker_violations(const dram_checker *k);
uint64_t dram_checker_commands(const dram_checker *k);
/* Text of the first violation ("" if none). */
const char *dram_checker_first(const dram_checker *k);

/* Command stream file format (rtdram --cmd-trace): a "#" header line, then
 * "cycle,channel,rank,bank,CMD,row" per command (bank/row -1 when not applicable),
 * one line as formatted by dram_cmd_format. */
void dram_cmd_format(const dram_cmd_rec *rec, char *buf, size_t n);

#endif
