/* pipe_trace.h — the ray in each stage of a unit's pipeline, for the VCD.
 *
 * Contract: a unit that issues at most one ray per cycle into a pipeline of
 * `stages` stages after its issue stage (stage 0, traced by the unit as
 * issue_ray) records each issue with pipe_trace_issue(); pipe_trace_update()
 * at cycle c sets stage k's variable ("<unit>.stage.<kk>_<name>") to the ray
 * issued at c - k, or 0xFFFFFFFF (an empty stage). The unit's process must
 * be stepped in every cycle in which pipe_trace_occupied() says a stage
 * still holds a ray (it keeps itself awake for that only while a VCD is
 * open, so VCD off costs nothing). Observation only: it changes no result. */
#ifndef RTSIM_MODEL_PIPE_TRACE_H
#define RTSIM_MODEL_PIPE_TRACE_H

#include <stdbool.h>
#include <stdint.h>

#include "kernel/vcd.h"

enum { PIPE_TRACE_NONE = 0xFFFFFFFFu };

typedef struct pipe_trace {
    uint32_t stages;        /* traced stages after issue: 1..stages */
    ks_vcd_var **v;         /* v[k - 1]: the ray in stage k */
    uint32_t *ray;          /* ring of the last stages + 1 issues, by cycle */
    uint64_t *at;           /* their issue cycles (UINT64_MAX: none) */
    uint64_t last_issue;    /* cycle of the last issue (UINT64_MAX: none) */
} pipe_trace;

/* The pipeline by function, issue stage first: {"fetch", 1}, {"box", 3}, ...
 * names the stages fetch1, box1, box2, box3, ... */
typedef struct pipe_stage_part {
    const char *fn;
    uint32_t n;
} pipe_stage_part;

/* Declares the variables of the stages after issue (all parts' stages but
 * the first) in vcd. false on allocation failure (t left empty: no trace). */
bool pipe_trace_init(pipe_trace *t, ks_vcd *vcd, const char *unit, const pipe_stage_part *parts, unsigned nparts);
void pipe_trace_free(pipe_trace *t);
static inline bool pipe_trace_on(const pipe_trace *t) { return t->v != 0; }
void pipe_trace_issue(pipe_trace *t, uint64_t cycle, uint32_t ray);
void pipe_trace_update(pipe_trace *t, uint64_t cycle);
/* Does a stage hold a ray in cycle + 1? */
static inline bool pipe_trace_occupied(const pipe_trace *t, uint64_t cycle)
{
    return t->v && t->last_issue != UINT64_MAX && cycle + 1 - t->last_issue <= t->stages;
}

#endif
