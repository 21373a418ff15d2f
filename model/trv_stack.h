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
#include <stdint.h>

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
uint32_t trv_stack_cycles(const trv_stack *s, uint32_t first, uint32_t k);

static inline uint32_t trv_stack_size(const trv_stack *s, uint32_t slot) { return s->sp[slot]; }
static inline bool trv_stack_empty(const trv_stack *s, uint32_t slot) { return s->sp[slot] == 0; }
static inline void trv_stack_clear(trv_stack *s, uint32_t slot) { s->sp[slot] = 0; }

/* Pushes k entries in the order given (e[k-1] ends on top) as one operation.
 * Returns the cycles taken (>= 1; 0 when k == 0), or -1 on overflow (nothing
 * pushed). */
int trv_stack_push(trv_stack *s, uint32_t slot, const trv_stack_entry *e, uint32_t k);

/* Reads the entry `below` positions under the top (0 = top) without popping;
 * false when the stack holds fewer entries. */
bool trv_stack_peek(const trv_stack *s, uint32_t slot, uint32_t below, trv_stack_entry *out);

/* Pops k entries (k <= size) as one operation (distance-stack culls pop
 * several); returns the cycles taken (0 when k == 0). */
int trv_stack_pop(trv_stack *s, uint32_t slot, uint32_t k);

#endif
