/* trv_stack.h — the traversal stacks of one TRV unit: one full stack per ray
 * slot (default 32 slots x 64 entries, paper sec. 3), held in a multi-bank
 * memory so that the up to N-1 pushes of one MBVH-N visit go in one cycle
 * (paper sec. 3.1: "consecutive entries are guaranteed to be on separate
 * banks"). Entry e of a stack lives in bank e mod banks.
 *
 * Contract: an operation touching k consecutive entries costs
 * trv_stack_cycles() = the largest number of those entries in one bank
 * (1 when k <= banks); the extra cycles are bank-conflict stalls, counted.
 * Each entry holds the child reference, its meta word and — with the
 * distance stack (MBVH, sec. 3.1) — its tnear; tnear is kept in the model in
 * both cases (for event logs) but only counted as storage with the distance
 * stack. Overflow is reported, never silent: push returns false. */
#ifndef RTSIM_MODEL_TRV_STACK_H
#define RTSIM_MODEL_TRV_STACK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define TRV_STACK_MAX_BANKS 64

typedef struct trv_stack_entry {
    uint32_t ref, meta;
    float tnear;
} trv_stack_entry;

typedef struct trv_stack_stats {
    uint64_t pushes, pops;           /* entries written / read */
    uint64_t ops;                    /* push or pop operations (one per TRV pass that touches the stack) */
    uint64_t conflict_cycles;        /* extra cycles from bank conflicts */
    uint64_t overflows;
    uint32_t max_depth;              /* deepest stack seen in any slot */
    uint64_t max_depth_stat;         /* max_depth as a counter, for the statistics registry */
    /* entries written / read per bank (energy: each bank is one SRAM) */
    uint64_t bank_writes[TRV_STACK_MAX_BANKS], bank_reads[TRV_STACK_MAX_BANKS];
} trv_stack_stats;

typedef struct trv_stack {
    uint32_t slots, depth, banks;
    trv_stack_entry *mem;            /* slots * depth */
    uint32_t *sp;                    /* per slot: entries in use */
    trv_stack_stats st;
} trv_stack;

/* slots >= 1, depth >= 1, banks >= 1. False (with a message) on bad sizes or
 * allocation failure. */
bool trv_stack_init(trv_stack *s, uint32_t slots, uint32_t depth, uint32_t banks, char *err, unsigned errlen);
void trv_stack_free(trv_stack *s);

/* Cycles an access to entries [first, first + k) takes: max entries per bank. */
static inline uint32_t trv_stack_cycles(const trv_stack *s, uint32_t first, uint32_t k)
{
    if (k == 0)
        return 0;
    /* k consecutive entries go round-robin over the banks whatever bank
     * `first` is in, so the busiest bank holds ceil(k / banks) of them. */
    (void)first;
    return (k + s->banks - 1) / s->banks;
}

/* (inline: a TRV pass makes one or two stack operations) */
static inline void trv_stack_count_op_(trv_stack *s, uint32_t cycles)
{
    s->st.ops++;
    s->st.conflict_cycles += cycles - 1;
}

static inline uint32_t trv_stack_size(const trv_stack *s, uint32_t slot) { return s->sp[slot]; }
static inline bool trv_stack_empty(const trv_stack *s, uint32_t slot) { return s->sp[slot] == 0; }
static inline void trv_stack_clear(trv_stack *s, uint32_t slot) { s->sp[slot] = 0; }

/* Pushes k entries in the order given (e[k-1] ends on top) as one operation.
 * Returns the cycles taken (>= 1; 0 when k == 0), or -1 on overflow (nothing
 * pushed). */
static inline int trv_stack_push(trv_stack *s, uint32_t slot, const trv_stack_entry *e, uint32_t k)
{
    if (k == 0)
        return 0;
    uint32_t sp = s->sp[slot];
    if (sp + k > s->depth) {
        s->st.overflows++;
        return -1;
    }
    trv_stack_entry *base = s->mem + (size_t)slot * s->depth;
    for (uint32_t i = 0, b = sp % s->banks; i < k; i++, b = b + 1 == s->banks ? 0 : b + 1) {
        base[sp + i] = e[i];
        s->st.bank_writes[b]++;
    }
    uint32_t cycles = trv_stack_cycles(s, sp, k);
    s->sp[slot] = sp + k;
    if (sp + k > s->st.max_depth)
        s->st.max_depth_stat = s->st.max_depth = sp + k;
    s->st.pushes += k;
    trv_stack_count_op_(s, cycles);
    return (int)cycles;
}

/* Reads the entry `below` positions under the top (0 = top) without popping;
 * false when the stack holds fewer entries. */
static inline bool trv_stack_peek(const trv_stack *s, uint32_t slot, uint32_t below, trv_stack_entry *out)
{
    uint32_t sp = s->sp[slot];
    if (below >= sp)
        return false;
    *out = s->mem[(size_t)slot * s->depth + sp - 1 - below];
    return true;
}

/* Pops k entries (k <= size) as one operation (distance-stack culls pop
 * several); returns the cycles taken (0 when k == 0). */
static inline int trv_stack_pop(trv_stack *s, uint32_t slot, uint32_t k)
{
    if (k == 0)
        return 0;
    uint32_t sp = s->sp[slot];
    if (k > sp)
        k = sp;
    uint32_t cycles = trv_stack_cycles(s, sp - k, k);
    for (uint32_t i = 0, b = (sp - k) % s->banks; i < k; i++, b = b + 1 == s->banks ? 0 : b + 1)
        s->st.bank_reads[b]++;
    s->sp[slot] = sp - k;
    s->st.pops += k;
    trv_stack_count_op_(s, cycles);
    return (int)cycles;
}

#endif
