/* trv_stack.c — banked per-ray stacks of a TRV (see trv_stack.h). */
#include "model/trv_stack.h"

#include <stdio.h>
#include <stdlib.h>

bool trv_stack_init(trv_stack *s, uint32_t slots, uint32_t depth, uint32_t banks, char *err, unsigned errlen)
{
    *s = (trv_stack){0};
    if (slots < 1 || slots > 65536 || depth < 1 || depth > 4096 || banks < 1 || banks > 64) {
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

uint32_t trv_stack_cycles(const trv_stack *s, uint32_t first, uint32_t k)
{
    if (k == 0)
        return 0;
    /* k consecutive entries go round-robin over the banks whatever bank
     * `first` is in, so the busiest bank holds ceil(k / banks) of them. */
    (void)first;
    return (k + s->banks - 1) / s->banks;
}

static void count_op(trv_stack *s, uint32_t cycles)
{
    s->st.ops++;
    s->st.conflict_cycles += cycles - 1;
}

int trv_stack_push(trv_stack *s, uint32_t slot, const trv_stack_entry *e, uint32_t k)
{
    if (k == 0)
        return 0;
    uint32_t sp = s->sp[slot];
    if (sp + k > s->depth) {
        s->st.overflows++;
        return -1;
    }
    trv_stack_entry *base = s->mem + (size_t)slot * s->depth;
    for (uint32_t i = 0; i < k; i++)
        base[sp + i] = e[i];
    uint32_t cycles = trv_stack_cycles(s, sp, k);
    s->sp[slot] = sp + k;
    if (sp + k > s->st.max_depth)
        s->st.max_depth = sp + k;
    s->st.pushes += k;
    count_op(s, cycles);
    return (int)cycles;
}

bool trv_stack_peek(const trv_stack *s, uint32_t slot, uint32_t below, trv_stack_entry *out)
{
    uint32_t sp = s->sp[slot];
    if (below >= sp)
        return false;
    *out = s->mem[(size_t)slot * s->depth + sp - 1 - below];
    return true;
}

int trv_stack_pop(trv_stack *s, uint32_t slot, uint32_t k)
{
    if (k == 0)
        return 0;
    uint32_t sp = s->sp[slot];
    if (k > sp)
        k = sp;
    uint32_t cycles = trv_stack_cycles(s, sp - k, k);
    s->sp[slot] = sp - k;
    s->st.pops += k;
    count_op(s, cycles);
    return (int)cycles;
}
