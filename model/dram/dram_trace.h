/* dram_trace.h — drives a dram_ctrl from a request trace with the injection policy
 * of Ramulator v1's dram-trace mode (../shared/ref/dram/README.txt, "Injection policy"):
 * each DRAM cycle, if not stalled, read the next trace line; try to add it to its
 * channel's queue; if the queue is full the same line is retried next cycle
 * (strict order, head-of-line blocking across channels); then tick all channels.
 * After the last line the write high watermark becomes 0 (drain writes); the run
 * ends when every queue and in-flight read is empty. Idle stretches are skipped
 * with dram_skip() (bit-identical to ticking through them).
 *
 * Trace format (gen_traces.py): one request per line, "0x<hex address> R|W";
 * blank lines and lines starting with '#' are ignored. Any other line is an error
 * naming file:line, and so are a NUL byte in a line, an address at or beyond the
 * device's capacity (it would alias silently), a trace without requests and a
 * read error (a folder given as the trace). */
#ifndef RTSIM_DRAM_TRACE_H
#define RTSIM_DRAM_TRACE_H

#include <stdint.h>
#include <stdio.h>

#include "model/dram/dram_ctrl.h"

typedef struct dram_trace_result {
    uint64_t requests;      /* trace lines injected */
    uint64_t reads, writes;
} dram_trace_result;

/* Runs the whole trace read from `f` (name used in messages). Returns 0, 2 on
 * malformed input with "name:line: ..." in err, or 3 when the stop check
 * (below) said stop (the controller holds the statistics so far). */
int dram_trace_run(dram_ctrl *c, FILE *f, const char *name, dram_trace_result *res, char *err, size_t errlen);

/* A check made once per request: nonzero stops the run (rtdram passes
 * kernel/interrupt.h's ks_interrupted for Ctrl-C/SIGTERM; the DRAM library
 * itself does not use the kernel). NULL, the default: never stop. */
void dram_trace_set_stop_check(int (*stop)(void));

/* Bytes the device holds: channels x ranks x banks x rows x columns x dq_bits/8. */
uint64_t dram_spec_capacity_bytes(const dram_spec *spec);

/* The longest trace line read (characters before the newline): a request is
 * at most 0x + 16 hex digits, blanks and R/W; a longer line is refused, so an
 * input that never sends a newline (/dev/zero) is not read without end. */
#define DRAM_TRACE_MAX_LINE 4096

/* The trace reader both run loops share. Set f, name and capacity (0: no
 * check), the rest zero; free(buf) when done. */
typedef struct dram_trace_reader {
    FILE *f;
    const char *name;
    uint64_t capacity;
    char *buf;
    size_t cap;
    long line;
    uint64_t requests;
} dram_trace_reader;
/* 1 request, 0 end of the trace, -1 error ("name:line: ..." in err). */
int dram_trace_next(dram_trace_reader *r, uint64_t *addr, int *is_write, char *err, size_t errlen);

/* Parses one trace line; returns 1 request, 0 blank/comment, -1 malformed. */
int dram_trace_parse_line(const char *line, uint64_t *addr, int *is_write);

#endif
