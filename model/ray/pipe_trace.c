/* pipe_trace.c — the ray in each pipeline stage, for the VCD (see
 * pipe_trace.h). */
#include "model/ray/pipe_trace.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

bool pipe_trace_init(pipe_trace *t, ks_vcd *vcd, const char *unit, const pipe_stage_part *parts, unsigned nparts)
{
    memset(t, 0, sizeof *t);
    t->last_issue = UINT64_MAX;
    uint32_t stages = 0;
    for (unsigned i = 0; i < nparts; i++)
        stages += parts[i].n;
    if (!vcd || stages < 2)
        return true;
    stages--; /* the issue stage is the unit's own issue_ray */
    t->v = calloc(stages, sizeof *t->v);
    t->ray = calloc(stages + 1, sizeof *t->ray);
    t->at = malloc((stages + 1) * sizeof *t->at);
    if (!t->v || !t->ray || !t->at) {
        pipe_trace_free(t);
        return false;
    }
    for (uint32_t i = 0; i <= stages; i++)
        t->at[i] = UINT64_MAX;
    t->stages = stages;
    uint32_t k = 0; /* stage index from issue */
    for (unsigned i = 0; i < nparts; i++)
        for (uint32_t j = 1; j <= parts[i].n; j++, k++) {
            if (k == 0)
                continue;
            char nm[192];
            snprintf(nm, sizeof nm, "%s.stage.%02u_%s%u", unit, k, parts[i].fn, j);
            t->v[k - 1] = ks_vcd_var_int(vcd, nm, 32, PIPE_TRACE_NONE);
        }
    return true;
}

void pipe_trace_free(pipe_trace *t)
{
    free(t->v);
    free(t->ray);
    free(t->at);
    memset(t, 0, sizeof *t);
    t->last_issue = UINT64_MAX;
}

void pipe_trace_issue(pipe_trace *t, uint64_t cycle, uint32_t ray)
{
    if (!t->v)
        return;
    uint32_t slot = (uint32_t)(cycle % (t->stages + 1));
    t->ray[slot] = ray;
    t->at[slot] = cycle;
    t->last_issue = cycle;
}

void pipe_trace_update(pipe_trace *t, uint64_t cycle)
{
    if (!t->v)
        return;
    for (uint32_t k = 1; k <= t->stages; k++) {
        uint32_t v = PIPE_TRACE_NONE;
        if (cycle >= k) {
            uint32_t slot = (uint32_t)((cycle - k) % (t->stages + 1));
            if (t->at[slot] == cycle - k)
                v = t->ray[slot];
        }
        ks_vcd_set(t->v[k - 1], v);
    }
}
