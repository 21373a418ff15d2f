/* trv_stack.c — banked per-ray stacks of a TRV (see trv_stack.h). */
#include "model/ray/trv_stack.h"

#include <stdio.h>
#include <stdlib.h>

bool trv_stack_init(trv_stack *s, uint32_t slots, uint32_t depth, uint32_t banks, char *err, unsigned errlen)
{
    *s = (trv_stack){0};
    if (slots < 1 || slots > 65536 || depth < 1 || depth > 4096 || banks < 1 || banks > TRV_STACK_MAX_BANKS) {
        snprintf(err, errlen,
                 "trv stack: slots %u (allowed 1..65536), depth %u (allowed 1..4096), banks %u (allowed 1..64)", slots,
                 depth, banks);
        return false;
    }
    s->mem = calloc((size_t)slots * depth, sizeof *s->mem);
    s->sp = calloc(slots, sizeof *s->sp);
    if (!s->mem || !s->sp) {
        trv_stack_free(s);
        snprintf(err, errlen, "trv stack: out of memory for %u x %u entries", slots, depth);
        return false;
    }
    s->slots = slots;
    s->depth = depth;
    s->banks = banks;
    return true;
}

void trv_stack_free(trv_stack *s)
{
    free(s->mem);
    free(s->sp);
    *s = (trv_stack){0};
}

