/* dram_ctrl.c — the controller of dram_ctrl.h: queues, FR-FCFS-Cap scheduler,
 * bank state machines, refresh, and the earliest-issue bookkeeping that turns
 * the spec's constraint rows into O(1) readiness checks. */
#include "model/dram_ctrl.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { REQ_READ, REQ_WRITE, REQ_REFRESH };
#define NEVER INT64_MIN

typedef struct dreq {
    uint64_t addr, tag;
    int64_t arrive, depart;
    uint32_t row;
    uint16_t rank, bank;
    uint16_t bidx;         /* rank * banks + bank */
    uint8_t type;
    uint8_t first;         /* no command issued yet (row hit/miss/conflict not yet counted) */
    uint8_t hit;           /* in a counted queue: targets its bank's open row (kept by q_push
                              and q_recount, so the scans need not look at the bank) */
} dreq;

/* A request queue. Read, write and act queues also keep, per bank, how many
 * entries target it and how many of those hit its open row (by type), so the
 * scheduler decides "can anything issue now" per bank instead of per entry. */
typedef struct dqcount {
    uint16_t n;            /* entries targeting the bank */
    uint16_t hit[2];       /* of which hit its open row, by type (REQ_READ, REQ_WRITE) */
} dqcount;

/* Bank indices per channel at most (ranks <= 8, banks <= 64: dram_timing.c). */
#define MAX_BANK_INDEX 512
#define BANK_WORDS (MAX_BANK_INDEX / 64)

typedef struct dqueue {
    dreq *v;
    int n, cap;
    dqcount *bc;           /* per bank index (rank * banks + bank); NULL: not counted (otherq) */
    uint64_t used[BANK_WORDS]; /* bit i: bc[i].n > 0 (the scan visits only these banks) */
    /* banks 0..63 by request class (channels of at most 64 banks, one rank: the
     * fast scan): entries that are no row hit, read row hits, write row hits */
    uint64_t cls_other, cls_rd, cls_wr;
} dqueue;

typedef struct dbank {
    int64_t next[DRAM_NCMD];   /* earliest cycle each command may issue (bank constraints); the
                                  command may issue at the max of this and the channel's and
                                  rank's next[] (combined where needed, not kept per bank: a
                                  command changes the channel's next[] of every bank at once) */
    int32_t open_row;          /* -1 = closed */
    int32_t hits;              /* RD/WR to the open row since its ACT (Ramulator RowTable) */
} dbank;

typedef struct drank {
    int64_t next[DRAM_NCMD];
    int64_t hist[DRAM_NCMD][DRAM_MAX_WINDOW]; /* latest issue cycles, newest first */
    int nopen;                 /* open banks */
    int64_t open_since;        /* cycle the first bank opened (energy background) */
} drank;

typedef struct dchan {
    int64_t next[DRAM_NCMD];
    int64_t hist[DRAM_NCMD][DRAM_MAX_WINDOW];
    dqueue readq, writeq, actq, otherq;
    dreq *pend;                /* ring of reads waiting for their data, FIFO */
    int pend_head, pend_n, pend_cap; /* pend_cap: 0 or a power of two (index by mask) */
    drank *ranks;
    dbank *banks;              /* rank-major */
    int write_mode;
    uint64_t open_mask;        /* banks 0..63 with an open row */
    uint64_t capped_mask;      /* banks 0..63 whose row hits exceed the cap */
    int64_t sched_wake;        /* no command can issue before this cycle unless the queues or
                                  bank states change (0 = unknown: run the scheduler) */
    int64_t refreshed;         /* cycle of the last refresh injection */
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
     * in one loop (each row only raises a next[], so the order does not matter) */
    issue_row irows[DRAM_NCMD][DRAM_MAX_CONSTRAINTS];
    int n_irows[DRAM_NCMD];
};

static void *xcalloc(size_t n, size_t sz)
{
    void *p = calloc(n ? n : 1, sz);
    if (!p) {
        fprintf(stderr, "dram_ctrl: out of memory\n");
        exit(1);
    }
    return p;
}

static void q_init(dqueue *q, int cap, int nbanks)
{
    q->cap = cap;
    q->n = 0;
    q->v = xcalloc((size_t)cap, sizeof *q->v);
    if (nbanks)
        q->bc = xcalloc((size_t)nbanks, sizeof *q->bc);
}

static void q_free(dqueue *q)
{
    free(q->v);
    free(q->bc);
}

/* The class bits of bank bidx in q from its counters. */
static inline void q_class_bits(dqueue *q, int bidx)
{
    if (bidx >= 64)
        return;
    const dqcount k = q->bc[bidx];
    const uint64_t bit = 1ull << bidx;
    q->cls_other = k.n > k.hit[0] + k.hit[1] ? q->cls_other | bit : q->cls_other & ~bit;
    q->cls_rd = k.hit[REQ_READ] ? q->cls_rd | bit : q->cls_rd & ~bit;
    q->cls_wr = k.hit[REQ_WRITE] ? q->cls_wr | bit : q->cls_wr & ~bit;
}

/* Per-bank counters of a counted queue: +1 or -1 for entry r given the banks' state. */
static inline void q_count(dqueue *q, const dbank *banks, const dreq *r, int d)
{
    if (!q->bc)
        return;
    dqcount *k = &q->bc[r->bidx];
    k->n = (uint16_t)(k->n + d);
    const uint64_t bit = 1ull << (r->bidx & 63);
    if (k->n)
        q->used[r->bidx >> 6] |= bit;
    else
        q->used[r->bidx >> 6] &= ~bit;
    /* counted queues hold reads and writes only (refreshes go to the uncounted
     * otherq); indexing by the comparison lets gcc -O3 see that hit[] is not
     * overrun where it inlines the refresh push (-Warray-bounds) */
    if (banks[r->bidx].open_row >= 0 && (uint32_t)banks[r->bidx].open_row == r->row)
        k->hit[r->type == REQ_WRITE] = (uint16_t)(k->hit[r->type == REQ_WRITE] + d);
    q_class_bits(q, r->bidx);
}

/* Bank bidx changed its open row: recount its row hits in a counted queue. */
static void q_recount(dqueue *q, const dbank *banks, int bidx)
{
    dqcount *k = &q->bc[bidx];
    if (!k->n)
        return; /* no entries: no hits, class bits clear */
    const int had_hits = k->hit[0] + k->hit[1];
    k->hit[0] = k->hit[1] = 0;
    if (banks[bidx].open_row >= 0) {
        const uint32_t row = (uint32_t)banks[bidx].open_row;
        for (int i = 0; i < q->n; i++) {
            dreq *r = &q->v[i];
            if (r->bidx == bidx) {
                r->hit = r->row == row;
                k->hit[r->type] = (uint16_t)(k->hit[r->type] + r->hit);
            }
        }
    } else if (had_hits) { /* closed: only former hits have a flag to clear */
        for (int i = 0; i < q->n; i++)
            if (q->v[i].bidx == bidx)
                q->v[i].hit = 0;
    }
    q_class_bits(q, bidx);
}

static void q_push_raw(dqueue *q, const dreq *r)
{
    if (q->n == q->cap) {
        q->cap *= 2;
        q->v = realloc(q->v, (size_t)q->cap * sizeof *q->v);
        if (!q->v) {
            fprintf(stderr, "dram_ctrl: out of memory\n");
            exit(1);
        }
    }
    q->v[q->n++] = *r;
}

static void q_push(dqueue *q, const dbank *banks, const dreq *r)
{
    q_count(q, banks, r, +1);
    q_push_raw(q, r);
    q->v[q->n - 1].hit = banks[r->bidx].open_row >= 0 && (uint32_t)banks[r->bidx].open_row == r->row;
}


static void q_erase(dqueue *q, const dbank *banks, int i)
{
    q_count(q, banks, &q->v[i], -1);
    memmove(&q->v[i], &q->v[i + 1], (size_t)(q->n - i - 1) * sizeof *q->v);
    q->n--;
}

static void pend_push(dchan *ch, const dreq *r)
{
    if (ch->pend_n == ch->pend_cap) {
        int ncap = ch->pend_cap ? 2 * ch->pend_cap : 16;
        dreq *nv = xcalloc((size_t)ncap, sizeof *nv);
        for (int i = 0; i < ch->pend_n; i++)
            nv[i] = ch->pend[(ch->pend_head + i) % ch->pend_cap];
        free(ch->pend);
        ch->pend = nv;
        ch->pend_cap = ncap;
        ch->pend_head = 0;
    }
    ch->pend[(ch->pend_head + ch->pend_n++) & (ch->pend_cap - 1)] = *r;
}

dram_ctrl *dram_ctrl_create(const dram_spec *spec, dram_done_fn done, void *user, char *err, size_t errlen)
{
    dram_ctrl *c = xcalloc(1, sizeof *c);
    c->spec = spec;
    if (dram_addrmap_init(&c->map, spec, err, errlen)) {
        free(c);
        return NULL;
    }
    c->done = done;
    c->done_user = user;
    c->nch = spec->channels;
    c->nrank = spec->ranks;
    c->nbank = spec->banks;
    c->write_high_pct = spec->write_high_pct;
    c->fast_scan = c->nrank == 1 && c->nbank <= 64;
    c->wq_hi = spec->write_queue * c->write_high_pct / 100;
    c->wq_lo = spec->write_queue * spec->write_low_pct / 100;
    /* group constraint rows by (scope, FROM), keeping file order */
    int n = 0;
    for (int s = 0; s < DRAM_NSCOPE; s++)
        for (int f = 0; f < DRAM_NCMD; f++) {
            c->row_start[s][f] = n;
            c->max_window[s][f] = 1;
            for (int i = 0; i < spec->nconstraints; i++) {
                const dram_constraint *k = &spec->constraint[i];
                if (k->scope != s || k->from != f)
                    continue;
                c->rows[n++] = (cons_row){k->to, k->window, k->cycles};
                if (k->window > c->max_window[s][f])
                    c->max_window[s][f] = k->window;
            }
            c->row_count[s][f] = n - c->row_start[s][f];
        }
    for (int f = 0; f < DRAM_NCMD; f++) {
        const int nscope = dram_cmd_is_bank_scoped(f) ? 3 : 2;
        for (int sc = 0; sc < nscope; sc++)
            for (int i = 0; i < c->row_count[sc][f]; i++) {
                const cons_row *r = &c->rows[c->row_start[sc][f] + i];
                c->irows[f][c->n_irows[f]++] = (issue_row){(uint8_t)sc, r->to, r->window, r->cycles};
            }
    }
    c->ch = xcalloc((size_t)c->nch, sizeof *c->ch);
    for (int i = 0; i < c->nch; i++) {
        dchan *ch = &c->ch[i];
        q_init(&ch->readq, spec->read_queue, c->nrank * c->nbank);
        q_init(&ch->writeq, spec->write_queue, c->nrank * c->nbank);
        q_init(&ch->actq, spec->read_queue + spec->write_queue, c->nrank * c->nbank);
        q_init(&ch->otherq, 4 * c->nrank, 0);
        ch->ranks = xcalloc((size_t)c->nrank, sizeof *ch->ranks);
        ch->banks = xcalloc((size_t)(c->nrank * c->nbank), sizeof *ch->banks);
        for (int k = 0; k < DRAM_NCMD; k++)
            for (int w = 0; w < DRAM_MAX_WINDOW; w++)
                ch->hist[k][w] = NEVER;
        for (int r = 0; r < c->nrank; r++)
            for (int k = 0; k < DRAM_NCMD; k++)
                for (int w = 0; w < DRAM_MAX_WINDOW; w++)
                    ch->ranks[r].hist[k][w] = NEVER;
        for (int b = 0; b < c->nrank * c->nbank; b++)
            ch->banks[b].open_row = -1;
    }
    return c;
}

void dram_ctrl_destroy(dram_ctrl *c)
{
    if (!c)
        return;
    for (int i = 0; i < c->nch; i++) {
        dchan *ch = &c->ch[i];
        q_free(&ch->readq);
        q_free(&ch->writeq);
        q_free(&ch->actq);
        q_free(&ch->otherq);
        free(ch->pend);
        free(ch->ranks);
        free(ch->banks);
    }
    free(c->ch);
    free(c);
}

void dram_set_cmd_sink(dram_ctrl *c, dram_cmd_fn fn, void *user)
{
    c->cmd_sink = fn;
    c->cmd_user = user;
}

const dram_spec *dram_ctrl_spec(const dram_ctrl *c) { return c->spec; }
const dram_addrmap *dram_ctrl_addrmap(const dram_ctrl *c) { return &c->map; }
int64_t dram_clock(const dram_ctrl *c) { return c->clk; }
void dram_set_write_high_pct(dram_ctrl *c, int pct)
{
    c->write_high_pct = pct;
    c->wq_hi = c->spec->write_queue * pct / 100;
}

/* ---- readiness ---- */

static inline dbank *bank_of(const dram_ctrl *c, dchan *ch, const dreq *r)
{
    (void)c;
    return &ch->banks[r->bidx];
}

/* The command a request needs next (Ramulator decode/prereq). */
static inline int first_cmd(const dram_ctrl *c, dchan *ch, const dreq *r)
{
    if (r->type == REQ_REFRESH)
        return ch->ranks[r->rank].nopen ? DRAM_PREA : DRAM_REF;
    const dbank *b = bank_of(c, ch, r);
    if (b->open_row < 0)
        return DRAM_ACT;
    if ((uint32_t)b->open_row == r->row)
        return r->type == REQ_WRITE ? DRAM_WR : DRAM_RD;
    return DRAM_PRE;
}

static inline int64_t max64(int64_t a, int64_t b) { return a > b ? a : b; }

/* Earliest cycle `cmd` for request r may issue given everything issued so far. */
static inline int64_t earliest(const dram_ctrl *c, dchan *ch, const dreq *r, int cmd)
{
    const int64_t t = max64(ch->next[cmd], ch->ranks[r->rank].next[cmd]);
    if (dram_cmd_is_bank_scoped(cmd))
        return max64(t, bank_of(c, ch, r)->next[cmd]);
    return t;
}

/* FR-FCFS-Cap head: the oldest request that is ready with <= cap row hits, else the
 * oldest (ties: first in queue). `sorted` queues are in arrival order. -1 if empty. */
static int pick(const dram_ctrl *c, dchan *ch, dqueue *q, int sorted, int64_t *min_earliest)
{
    int best = -1, best_ready = 0;
    const int cap = c->spec->row_hit_cap;
    int64_t lo = *min_earliest;
    for (int i = 0; i < q->n; i++) {
        const dreq *r = &q->v[i];
        int cmd = first_cmd(c, ch, r);
        int64_t e = earliest(c, ch, r, cmd);
        if (e < lo)
            lo = e;
        int ready = e <= c->clk;
        if (ready && (cmd == DRAM_RD || cmd == DRAM_WR) && bank_of(c, ch, r)->hits > cap)
            ready = 0;
        if (best < 0) {
            best = i;
            best_ready = ready;
            if (sorted && ready)
                break;
        } else if (ready && !best_ready) {
            best = i;
            best_ready = 1;
            if (sorted)
                break;
        } else if (ready == best_ready && r->arrive < q->v[best].arrive) {
            best = i;
        }
    }
    *min_earliest = lo;
    return best;
}

/* Readiness classes of a bank for one queue (bits of a per-bank mask). */
enum { READY_OTHER = 1, READY_HIT_RD = 2, READY_HIT_WR = 4 };

/* Whether r is ready (as pick() defines it) given its bank's class mask. */
static inline int counted_ready(const dbank *b, const dreq *r, const uint8_t *mask)
{
    if (b->open_row >= 0 && (uint32_t)b->open_row == r->row)
        return mask[r->bidx] & (r->type == REQ_WRITE ? READY_HIT_WR : READY_HIT_RD);
    return mask[r->bidx] & READY_OTHER;
}

/* Readiness of the classes of banks 0..63 (one bit per bank each). */
typedef struct class_ready {
    uint64_t other, rd, wr;
} class_ready;

static inline int class_ready_has(const dreq *r, const class_ready *cr)
{
    const uint64_t set = r->hit ? (r->type == REQ_WRITE ? cr->wr : cr->rd) : cr->other;
    return (int)((set >> r->bidx) & 1);
}

/* One command class of pick_counted1: banks `bits` need `cmd`; their earliest cycle
 * is max(channel/rank bound, bank next[cmd]). Returns the banks ready at now (none
 * while the channel/rank bound is later, without looking at the banks). */
static inline uint64_t class_scan(const dchan *ch, uint64_t bits, int cmd, int64_t now)
{
    if (!bits || max64(ch->next[cmd], ch->ranks[0].next[cmd]) > now)
        return 0;
    uint64_t rdy = 0;
    for (; bits; bits &= bits - 1) {
        const int i = __builtin_ctzll(bits);
        rdy |= (uint64_t)(ch->banks[i].next[cmd] <= now) << i;
    }
    return rdy;
}

/* The bound of a class: min(lo, earliest cycle of the banks `bits` needing cmd)
 * (min over banks of the max = the max with the banks' minimum). */
static inline int64_t class_min(const dchan *ch, uint64_t bits, int cmd, int64_t lo)
{
    if (!bits)
        return lo;
    int64_t mn = INT64_MAX;
    for (; bits; bits &= bits - 1) {
        const int64_t x = ch->banks[__builtin_ctzll(bits)].next[cmd];
        mn = x < mn ? x : mn;
    }
    const int64_t e = max64(max64(ch->next[cmd], ch->ranks[0].next[cmd]), mn);
    return e < lo ? e : lo;
}

/* The ready sets of a channel of one rank with at most 64 banks (LPDDR3: 8) for
 * the request classes `other`, `rd`, `wr` (bank masks; the
 * union of the queues about to be searched: a class's readiness depends only on
 * its bank and command, not on the queue): per class (ACT for closed banks with
 * non-hit entries, PRE for open ones, RD and WR row hits) the banks' minimum and
 * ready set, row hits over the cap excluded from the ready sets. */
static inline void class_state(const dchan *ch, uint64_t other, uint64_t rd, uint64_t wr, int64_t now,
                               class_ready *cr)
{
    cr->other = class_scan(ch, other & ~ch->open_mask, DRAM_ACT, now) | class_scan(ch, other & ch->open_mask, DRAM_PRE, now);
    cr->rd = class_scan(ch, rd, DRAM_RD, now) & ~ch->capped_mask;
    cr->wr = class_scan(ch, wr, DRAM_WR, now) & ~ch->capped_mask;
}

/* The earliest cycle any of the classes could issue (what a scan finding nothing
 * leaves as the bound), folded into lo. */
static inline int64_t class_bound(const dchan *ch, uint64_t other, uint64_t rd, uint64_t wr, int64_t lo)
{
    lo = class_min(ch, other & ~ch->open_mask, DRAM_ACT, lo);
    lo = class_min(ch, other & ch->open_mask, DRAM_PRE, lo);
    lo = class_min(ch, rd, DRAM_RD, lo);
    return class_min(ch, wr, DRAM_WR, lo);
}

/* pick_counted's choice in q given the ready sets of class_state (which covered
 * q's classes): the first (sorted) or oldest ready entry, else the oldest. */
static int find_ready1(const dqueue *q, int sorted, const class_ready *cr)
{
    const int any = ((cr->other & q->cls_other) | (cr->rd & q->cls_rd) | (cr->wr & q->cls_wr)) != 0;
    if (sorted) {
        if (any)
            for (int i = 0; i < q->n; i++)
                if (class_ready_has(&q->v[i], cr))
                    return i;
        return 0;
    }
    int best = 0, best_ready = any ? -1 : 0; /* without ready entries, the oldest of all */
    for (int i = 0; i < q->n; i++) {
        const dreq *r = &q->v[i];
        if (any && !class_ready_has(r, cr))
            continue;
        if (best_ready < 0 || r->arrive < q->v[best].arrive) {
            best = i;
            best_ready = 1;
        }
    }
    return best;
}

/* pick_counted for a channel of one rank with at most 64 banks: class_state over
 * q's own classes, then find_ready1. */
static int pick_counted1(const dram_ctrl *c, dchan *ch, dqueue *q, int sorted, int64_t *min_earliest)
{
    class_ready cr;
    class_state(ch, q->cls_other, q->cls_rd, q->cls_wr, c->clk, &cr);
    *min_earliest = class_bound(ch, q->cls_other, q->cls_rd, q->cls_wr, *min_earliest);
    return find_ready1(q, sorted, &cr);
}

/* The channel and rank bounds of the four bank commands for rank rk: a bank
 * command may issue at the max of these and the bank's own next[]. */
typedef struct rank_bounds {
    int64_t act, pre, rd, wr;
} rank_bounds;

static inline rank_bounds rank_bounds_of(const dchan *ch, int rk)
{
    const int64_t *cn = ch->next, *rn = ch->ranks[rk].next;
    rank_bounds t = {max64(cn[DRAM_ACT], rn[DRAM_ACT]), max64(cn[DRAM_PRE], rn[DRAM_PRE]),
                     max64(cn[DRAM_RD], rn[DRAM_RD]), max64(cn[DRAM_WR], rn[DRAM_WR])};
    return t;
}

/* Earliest cycles of bank b's three request classes in a queue with counters
 * k (the rest: ACT if closed, PRE if another row is open; read row hits; write
 * row hits); INT64_MAX for a class without entries. */
typedef struct class_times {
    int64_t other, rd, wr;
} class_times;

static inline class_times bank_class_times(const dbank *b, dqcount k, const rank_bounds *t)
{
    class_times e = {INT64_MAX, INT64_MAX, INT64_MAX};
    if (k.n > k.hit[REQ_READ] + k.hit[REQ_WRITE])
        e.other = b->open_row < 0 ? max64(t->act, b->next[DRAM_ACT]) : max64(t->pre, b->next[DRAM_PRE]);
    if (k.hit[REQ_READ])
        e.rd = max64(t->rd, b->next[DRAM_RD]);
    if (k.hit[REQ_WRITE])
        e.wr = max64(t->wr, b->next[DRAM_WR]);
    return e;
}

static inline int64_t min64(int64_t a, int64_t b) { return a < b ? a : b; }

/* The banks with entries in a counted queue, in index order, each with its
 * class times (the rank bounds computed once per rank): the walk shared by
 * pick_counted and queue_bound. */
typedef struct used_banks {
    const dram_ctrl *c;
    const dchan *ch;
    const dqueue *q;
    int w, words, cur_rank;
    uint64_t bits;
    rank_bounds t;
} used_banks;

static inline used_banks used_banks_begin(const dram_ctrl *c, const dchan *ch, const dqueue *q)
{
    used_banks it = {c, ch, q, 0, (c->nrank * c->nbank + 63) >> 6, -1, q->used[0], {0, 0, 0, 0}};
    return it;
}

/* Next bank: its index in *bidx and class times in *e; 0 when there is none. */
static inline int used_banks_next(used_banks *it, int *bidx, class_times *e)
{
    while (!it->bits) {
        if (++it->w >= it->words)
            return 0;
        it->bits = it->q->used[it->w];
    }
    const int i = (it->w << 6) + __builtin_ctzll(it->bits);
    it->bits &= it->bits - 1;
    const int rk = it->c->nrank == 1 ? 0 : i / it->c->nbank;
    if (rk != it->cur_rank) {
        it->t = rank_bounds_of(it->ch, rk);
        it->cur_rank = rk;
    }
    *bidx = i;
    *e = bank_class_times(&it->ch->banks[i], it->q->bc[i], &it->t);
    return 1;
}

/* pick() for a counted queue, with the same result: per bank, the requests fall in
 * three classes (row hits by reads, by writes, and the rest: ACT if the bank is
 * closed, PRE if another row is open) that share their next command and thus their
 * earliest cycle. The per-bank counters give min earliest and "any ready" in
 * O(banks); the entries are visited only to find the chosen one. */
static int pick_counted(const dram_ctrl *c, dchan *ch, dqueue *q, int sorted, int64_t *min_earliest)
{
    if (q->n == 0)
        return -1;
    if (c->fast_scan)
        return pick_counted1(c, ch, q, sorted, min_earliest);
    const int cap = c->spec->row_hit_cap;
    const int64_t now = c->clk;
    int64_t lo = *min_earliest;
    /* mask[] is written for every bank with entries: the only ones read below */
    uint8_t mask[MAX_BANK_INDEX];
    int any = 0;
    used_banks it = used_banks_begin(c, ch, q);
    int bi;
    class_times e;
    while (used_banks_next(&it, &bi, &e)) {
        const int hit_ok = ch->banks[bi].hits <= cap;
        lo = min64(lo, min64(e.other, min64(e.rd, e.wr)));
        int m = e.other <= now ? READY_OTHER : 0;
        m |= e.rd <= now && hit_ok ? READY_HIT_RD : 0;
        m |= e.wr <= now && hit_ok ? READY_HIT_WR : 0;
        mask[bi] = (uint8_t)m;
        any |= m;
    }
    *min_earliest = lo;
    int best = 0;
    if (sorted) {
        if (any)
            for (int i = 0; i < q->n; i++)
                if (counted_ready(&ch->banks[q->v[i].bidx], &q->v[i], mask))
                    return i;
        return 0;
    }
    int best_ready = any ? -1 : 0; /* without ready entries, the oldest of all */
    for (int i = 0; i < q->n; i++) {
        const dreq *r = &q->v[i];
        if (any && !counted_ready(&ch->banks[r->bidx], r, mask))
            continue;
        if (best_ready < 0 || r->arrive < q->v[best].arrive) {
            best = i;
            best_ready = 1;
        }
    }
    return best;
}

/* The lower bound a scan at the next tick would compute (lo of pick_counted/pick)
 * over q, without looking for a ready entry: the minimum over q's classes (or, for
 * an uncounted queue, entries) of the earliest cycle of their next command. */
static int64_t queue_bound(const dram_ctrl *c, dchan *ch, const dqueue *q, int64_t lo)
{
    if (q->n == 0)
        return lo;
    if (!q->bc) {
        for (int i = 0; i < q->n; i++) {
            const int64_t e = earliest(c, ch, &q->v[i], first_cmd(c, ch, &q->v[i]));
            lo = e < lo ? e : lo;
        }
        return lo;
    }
    used_banks it = used_banks_begin(c, ch, q);
    int bi;
    class_times e;
    while (used_banks_next(&it, &bi, &e))
        lo = min64(lo, min64(e.other, min64(e.rd, e.wr)));
    return lo;
}

/* ---- issuing ---- */

static void apply_rows(const dram_ctrl *c, int scope, int cmd, int64_t *next, const int64_t (*hist)[DRAM_MAX_WINDOW],
                       int64_t now)
{
    const cons_row *row = &c->rows[c->row_start[scope][cmd]];
    for (int i = 0; i < c->row_count[scope][cmd]; i++) {
        int64_t from = row[i].window == 1 ? now : hist[cmd][row[i].window - 1];
        if (from == NEVER)
            continue;
        int64_t t = from + row[i].cycles;
        if (t > next[row[i].to])
            next[row[i].to] = t;
    }
}

static void hist_push(int64_t (*hist)[DRAM_MAX_WINDOW], int cmd, int depth, int64_t now)
{
    for (int w = depth - 1; w > 0; w--)
        hist[cmd][w] = hist[cmd][w - 1];
    hist[cmd][0] = now;
}

/* The open row of bank bidx changed: keep the queues' per-bank hit counts exact. */
static void bank_row_changed(dchan *ch, int bidx)
{
    q_recount(&ch->readq, ch->banks, bidx);
    q_recount(&ch->writeq, ch->banks, bidx);
    q_recount(&ch->actq, ch->banks, bidx);
}

/* Mirrors bank bidx's open state and hit cap into the channel's masks. */
static inline void bank_bits(const dram_ctrl *c, dchan *ch, int bidx)
{
    if (bidx >= 64)
        return;
    const dbank *b = &ch->banks[bidx];
    const uint64_t bit = 1ull << bidx;
    ch->open_mask = b->open_row >= 0 ? ch->open_mask | bit : ch->open_mask & ~bit;
    ch->capped_mask = b->hits > c->spec->row_hit_cap ? ch->capped_mask | bit : ch->capped_mask & ~bit;
}

static void close_bank(const dram_ctrl *c, dchan *ch, drank *rk, dbank *b, int64_t now)
{
    if (b->open_row < 0)
        return;
    b->open_row = -1;
    b->hits = 0;
    bank_bits(c, ch, (int)(b - ch->banks));
    bank_row_changed(ch, (int)(b - ch->banks));
    ch->st.n_pre_banks++;
    if (--rk->nopen == 0)
        ch->st.open_cycles += (uint64_t)(now - rk->open_since);
}

static void issue(dram_ctrl *c, int chi, int cmd, int rank, int bank, uint32_t row)
{
    dchan *ch = &c->ch[chi];
    drank *rk = &ch->ranks[rank];
    const int64_t now = c->clk;
    if (c->max_window[DRAM_SCOPE_CHANNEL][cmd] > 1)
        hist_push(ch->hist, cmd, c->max_window[DRAM_SCOPE_CHANNEL][cmd], now);
    if (c->max_window[DRAM_SCOPE_RANK][cmd] > 1)
        hist_push(rk->hist, cmd, c->max_window[DRAM_SCOPE_RANK][cmd], now);
    dbank *banks = &ch->banks[rank * c->nbank];
    {
        int64_t *const tgt[3] = {ch->next, rk->next, banks[bank < 0 ? 0 : bank].next};
        const int64_t *const hst[2] = {ch->hist[cmd], rk->hist[cmd]};
        const issue_row *row = c->irows[cmd];
        for (int i = 0, n = c->n_irows[cmd]; i < n; i++) {
            const int64_t from = row[i].window == 1 ? now : hst[row[i].scope][row[i].window - 1];
            if (from == NEVER)
                continue;
            const int64_t t = from + row[i].cycles;
            int64_t *nx = &tgt[row[i].scope][row[i].to];
            if (t > *nx)
                *nx = t;
        }
    }
    if (dram_cmd_is_bank_scoped(cmd)) {
        if (c->row_count[DRAM_SCOPE_SIBLING][cmd])
            for (int b = 0; b < c->nbank; b++)
                if (b != bank)
                    apply_rows(c, DRAM_SCOPE_SIBLING, cmd, banks[b].next, NULL, now);
    }
    switch (cmd) {
    case DRAM_ACT:
        banks[bank].open_row = (int32_t)row;
        banks[bank].hits = 0;
        bank_bits(c, ch, rank * c->nbank + bank);
        bank_row_changed(ch, rank * c->nbank + bank);
        if (rk->nopen++ == 0)
            rk->open_since = now;
        break;
    case DRAM_PRE:
        close_bank(c, ch, rk, &banks[bank], now);
        break;
    case DRAM_PREA:
        for (int b = 0; b < c->nbank; b++)
            close_bank(c, ch, rk, &banks[b], now);
        break;
    case DRAM_RD:
    case DRAM_WR:
        banks[bank].hits++;
        bank_bits(c, ch, rank * c->nbank + bank);
        break;
    default:
        break;
    }
    ch->st.n_cmd[cmd]++;
    if (c->cmd_sink) {
        dram_cmd_rec rec = {now, chi, rank, dram_cmd_is_bank_scoped(cmd) ? bank : -1,
                            cmd == DRAM_ACT ? (int)row : -1, cmd};
        c->cmd_sink(c->cmd_user, &rec);
    }
}

/* Accounts ticks occ_upto+1 .. upto at the current readq + writeq + pend count (call
 * before the count changes: at a tick before its own changes, at an add after the
 * tick of its cycle). */
static inline void occ_flush(dchan *ch, int64_t upto)
{
    ch->st.queue_occupancy_sum += (uint64_t)(upto - ch->occ_upto) * (uint64_t)(ch->readq.n + ch->writeq.n + ch->pend_n);
    ch->occ_upto = upto;
}

/* ---- requests ---- */

static dqueue *queue_for(dchan *ch, bool is_write) { return is_write ? &ch->writeq : &ch->readq; }

bool dram_will_accept(const dram_ctrl *c, uint64_t addr, bool is_write)
{
    dram_addr a;
    dram_addrmap_decode(&c->map, addr, &a);
    dchan *ch = &c->ch[a.channel];
    dqueue *q = queue_for(ch, is_write);
    return q->n < (is_write ? c->spec->write_queue : c->spec->read_queue);
}

bool dram_add(dram_ctrl *c, uint64_t addr, bool is_write, uint64_t tag)
{
    dram_addr a;
    dram_addrmap_decode(&c->map, addr, &a);
    dchan *ch = &c->ch[a.channel];
    if (queue_for(ch, is_write)->n >= (is_write ? c->spec->write_queue : c->spec->read_queue))
        return false; /* = !dram_will_accept() */
    c->pending++;
    occ_flush(ch, c->clk);
    dreq r = {.addr = addr, .tag = tag, .arrive = c->clk, .depart = 0, .row = a.row,
              .rank = (uint16_t)a.rank, .bank = (uint16_t)a.bank,
              .bidx = (uint16_t)(a.rank * (uint32_t)c->nbank + a.bank), .type = is_write ? REQ_WRITE : REQ_READ, .first = 1};
    if (!is_write)
        for (int i = 0; i < ch->writeq.n; i++)
            if (ch->writeq.v[i].addr == addr) { /* forwarded from the write queue */
                r.depart = c->clk + 1;
                ch->st.reads_forwarded++;
                pend_push(ch, &r);
                return true;
            }
    dqueue *q = queue_for(ch, is_write);
    q_push(q, ch->banks, &r);
    if (is_write)
        ch->wr_live++;
    else
        ch->rd_live++;
    /* The last scan (or the bound set after the last command) found nothing issuable
     * before sched_wake and nothing changed since but this entry: the bound stays valid with the entry's own earliest
     * cycle folded in (as the next scan would compute it) when the next scan looks
     * at its queue; a queue it does not look at leaves it unchanged (a mode change
     * resets it). */
    if (ch->sched_wake && !ch->otherq.n && q == (ch->write_mode ? &ch->writeq : &ch->readq)) {
        const int64_t e = earliest(c, ch, &r, first_cmd(c, ch, &r));
        if (e < ch->sched_wake)
            ch->sched_wake = e > 0 ? e : 0;
    }
    return true;
}

static int write_mode_next(const dram_ctrl *c, const dchan *ch)
{
    const int hi = c->wq_hi, lo = c->wq_lo;
    if (!ch->write_mode)
        return ch->writeq.n > hi || ch->readq.n == 0;
    return !(ch->writeq.n < lo && ch->readq.n != 0);
}

/* After a command: the scan of the next tick finds nothing to issue when every
 * candidate's earliest cycle is later than that tick; then it would only set
 * sched_wake to that bound, which is set here instead (the queues it scans are
 * those of the current mode; a mode change or refresh at that tick resets it,
 * and adds fold themselves in as after a fruitless scan). */
static void next_scan_bound(const dram_ctrl *c, dchan *ch)
{
    if (c->exhaustive)
        return;
    const dqueue *q = ch->otherq.n ? &ch->otherq : ch->write_mode ? &ch->writeq : &ch->readq;
    int64_t lo = INT64_MAX;
    if (c->fast_scan) {
        /* the minimum over the union of both queues' classes per command */
        const dqueue *a = &ch->actq;
        uint64_t other = a->cls_other, rd = a->cls_rd, wr = a->cls_wr;
        if (q->bc) {
            other |= q->cls_other;
            rd |= q->cls_rd;
            wr |= q->cls_wr;
        } else {
            lo = queue_bound(c, ch, q, lo);
        }
        /* class by class, stopping once one can issue at the next cycle (then the
         * next tick scans anyway) */
        const int64_t soon = c->clk + 1;
        lo = class_min(ch, rd, DRAM_RD, lo);
        if (lo > soon)
            lo = class_min(ch, other & ~ch->open_mask, DRAM_ACT, lo);
        if (lo > soon)
            lo = class_min(ch, other & ch->open_mask, DRAM_PRE, lo);
        if (lo > soon)
            lo = class_min(ch, wr, DRAM_WR, lo);
    } else {
        lo = queue_bound(c, ch, q, queue_bound(c, ch, &ch->actq, lo));
    }
    if (lo > c->clk + 1)
        ch->sched_wake = lo;
}

static void chan_tick(dram_ctrl *c, int chi)
{
    dchan *ch = &c->ch[chi];
    const int64_t now = c->clk;
    occ_flush(ch, now);
    /* 1. one completed read */
    if (ch->pend_n && ch->pend[ch->pend_head].depart <= now) {
        dreq r = ch->pend[ch->pend_head];
        ch->pend_head = (ch->pend_head + 1) & (ch->pend_cap - 1);
        ch->pend_n--;
        c->pending--;
        int64_t lat = r.depart - r.arrive;
        if (lat > 1) {
            ch->st.reads_done++;
            ch->st.read_latency_sum += (uint64_t)lat;
        }
        if (c->done)
            c->done(c->done_user, r.addr, r.tag, false, lat);
    }
    /* 2. refresh */
    if (now - ch->refreshed >= c->spec->refresh_interval) {
        for (int rk = 0; rk < c->nrank; rk++) {
            dreq r = {.arrive = now, .rank = (uint16_t)rk, .bidx = (uint16_t)(rk * c->nbank), .type = REQ_REFRESH,
                      .first = 0};
            q_push(&ch->otherq, ch->banks, &r);
            c->pending++;
        }
        ch->refreshed = now;
        ch->sched_wake = 0;
    }
    /* 3. read or write mode */
    int mode = write_mode_next(c, ch);
    if (mode != ch->write_mode) {
        ch->write_mode = mode;
        ch->sched_wake = 0;
    }
    /* 4. one command: actq first, then refresh, then the mode's queue. While nothing
     * changed since the last scan found nothing issuable, skip the scan. */
    if (now < ch->sched_wake && !c->exhaustive)
        return;
    int64_t lo = INT64_MAX;
    dqueue *q = &ch->actq;
    dqueue *mq = ch->otherq.n ? &ch->otherq : ch->write_mode ? &ch->writeq : &ch->readq;
    int i, cmd = -1;
    class_ready cr;
    const int shared = c->fast_scan && !c->exhaustive && mq != &ch->otherq;
    if (shared) { /* one class state for actq and the mode's queue */
        class_state(ch, q->cls_other | mq->cls_other, q->cls_rd | mq->cls_rd, q->cls_wr | mq->cls_wr, now, &cr);
        i = q->n ? find_ready1(q, 0, &cr) : -1;
    } else {
        i = c->exhaustive ? pick(c, ch, q, 0, &lo) : pick_counted(c, ch, q, 0, &lo);
    }
    if (i >= 0) {
        cmd = first_cmd(c, ch, &q->v[i]);
        if (earliest(c, ch, &q->v[i], cmd) > now)
            i = -1;
    }
    if (i < 0) {
        q = mq;
        if (shared)
            i = q->n ? find_ready1(q, 1, &cr) : -1;
        else
            i = c->exhaustive || q == &ch->otherq ? pick(c, ch, q, 1, &lo) : pick_counted(c, ch, q, 1, &lo);
        if (i >= 0) {
            cmd = first_cmd(c, ch, &q->v[i]);
            if (earliest(c, ch, &q->v[i], cmd) > now)
                i = -1;
        }
        if (i < 0) { /* full scans of both queues: lo bounds the next issue */
            if (shared) /* computed only now: unused when a command issues */
                lo = class_bound(ch, ch->actq.cls_other | mq->cls_other, ch->actq.cls_rd | mq->cls_rd,
                                 ch->actq.cls_wr | mq->cls_wr, lo);
            ch->sched_wake = lo;
            return;
        }
    }
    ch->sched_wake = 0;
    dreq *r = &q->v[i];
    if (r->first && r->type != REQ_REFRESH) {
        r->first = 0;
        const dbank *b = bank_of(c, ch, r);
        if (b->open_row >= 0 && (uint32_t)b->open_row == r->row)
            ch->st.row_hits++;
        else if (b->open_row >= 0)
            ch->st.row_conflicts++;
        else
            ch->st.row_misses++;
    }
    issue(c, chi, cmd, r->rank, r->bank, r->row);
    const int final_cmd = r->type == REQ_READ ? DRAM_RD : r->type == REQ_WRITE ? DRAM_WR : DRAM_REF;
    if (cmd != final_cmd) {
        if (cmd == DRAM_ACT) { /* promote to actq (to its back, also from actq itself) */
            dreq moved = *r;
            q_erase(q, ch->banks, i);
            q_push(&ch->actq, ch->banks, &moved);
        }
        next_scan_bound(c, ch);
        return;
    }
    dreq done = *r;
    q_erase(q, ch->banks, i);
    if (done.type == REQ_READ) {
        ch->rd_live--;
        done.depart = now + c->spec->read_latency;
        pend_push(ch, &done);
    } else if (done.type == REQ_REFRESH) {
        c->pending--;
    } else if (done.type == REQ_WRITE) {
        ch->wr_live--;
        c->pending--;
        ch->st.writes_done++;
        if (c->done)
            c->done(c->done_user, done.addr, done.tag, true, now - done.arrive);
    }
    next_scan_bound(c, ch);
}

void dram_tick(dram_ctrl *c)
{
    c->clk++;
    for (int i = 0; i < c->nch; i++)
        chan_tick(c, i);
}

int dram_pending(const dram_ctrl *c)
{
    /* = the sum over channels of readq + writeq + actq + otherq + pend, kept as a count */
    return c->pending;
}

static int64_t chan_next_event(const dram_ctrl *c, dchan *ch)
{
    const int64_t soon = c->clk + 1;
    if (ch->sched_wake == 0 || write_mode_next(c, ch) != ch->write_mode)
        return soon;
    int64_t t = ch->refreshed + c->spec->refresh_interval;
    if (ch->pend_n && ch->pend[ch->pend_head].depart < t)
        t = ch->pend[ch->pend_head].depart;
    if (ch->sched_wake < t)
        t = ch->sched_wake;
    return t < soon ? soon : t;
}

int64_t dram_next_event(const dram_ctrl *c)
{
    int64_t t = INT64_MAX;
    for (int i = 0; i < c->nch; i++) {
        int64_t e = chan_next_event(c, &c->ch[i]);
        if (e < t)
            t = e;
        if (t == c->clk + 1)
            break;
    }
    return t;
}

/* A channel's bound for dram_next_completion. Until the next command, the state
 * is frozen, so that command is some queued request's next command at or after its
 * earliest cycle: every command issues at or after the minimum of those (lo), every
 * read completes read_latency after its RD, a write at its WR. A refresh changes
 * the banks without a request's command, so its injection and its commands bound
 * too; a read issued already completes at the head of pend first (FIFO), before
 * any read issued from now on (pend's head departs by now + read_latency). */
static int64_t chan_next_completion(const dram_ctrl *c, dchan *ch)
{
    const int64_t soon = c->clk + 1;
    int64_t t = ch->refreshed + c->spec->refresh_interval;
    if (ch->pend_n && ch->pend[ch->pend_head].depart < t)
        t = ch->pend[ch->pend_head].depart;
    if (ch->otherq.n)
        t = queue_bound(c, ch, &ch->otherq, t);
    if (ch->wr_live || (ch->rd_live && !ch->pend_n)) {
        int64_t lo = INT64_MAX;
        const dqueue *a = &ch->actq, *r = &ch->readq, *w = &ch->writeq;
        if (c->fast_scan) {
            const uint64_t other = a->cls_other | r->cls_other | w->cls_other;
            lo = class_bound(ch, other, a->cls_rd | r->cls_rd | w->cls_rd, a->cls_wr | r->cls_wr | w->cls_wr, lo);
        } else {
            lo = queue_bound(c, ch, w, queue_bound(c, ch, r, queue_bound(c, ch, a, lo)));
        }
        lo = lo < soon ? soon : lo;
        if (ch->wr_live && lo < t)
            t = lo;
        if (ch->rd_live && !ch->pend_n && lo + c->spec->read_latency < t)
            t = lo + c->spec->read_latency;
    }
    return t < soon ? soon : t;
}

int64_t dram_next_completion(const dram_ctrl *c)
{
    if (c->exhaustive)
        return c->clk + 1;
    int64_t t = INT64_MAX;
    for (int i = 0; i < c->nch; i++) {
        const int64_t e = chan_next_completion(c, &c->ch[i]);
        t = e < t ? e : t;
    }
    return t;
}

void dram_set_exhaustive(dram_ctrl *c, bool on) { c->exhaustive = on; }

/* Jumps k idle cycles, accounting what ticking through them would have. */
static void skip_by(dram_ctrl *c, int64_t k)
{
    c->clk += k; /* queue occupancy: accounted lazily (occ_flush) */
}

int64_t dram_skip(dram_ctrl *c)
{
    if (c->exhaustive)
        return 0;
    int64_t t = dram_next_event(c);
    int64_t k = t - 1 - c->clk;
    if (k <= 0)
        return 0;
    skip_by(c, k);
    return k;
}

void dram_advance_to(dram_ctrl *c, int64_t cycle)
{
    if (c->exhaustive) {
        while (c->clk < cycle)
            dram_tick(c);
        return;
    }
    /* Tick only at events and, there, only the channels with one: a channel's tick
     * before its next event changes nothing (its queue occupancy is accounted
     * lazily), and channels tick in order, so callbacks keep their order. */
    int64_t ev[16];
    const int nch = c->nch;
    while (c->clk < cycle) {
        int64_t t = INT64_MAX;
        for (int i = 0; i < nch; i++) {
            ev[i] = chan_next_event(c, &c->ch[i]);
            t = ev[i] < t ? ev[i] : t;
        }
        if (t > cycle) {
            c->clk = cycle;
            break;
        }
        c->clk = t;
        for (int i = 0; i < nch; i++)
            if (ev[i] == t)
                chan_tick(c, i);
    }
}

void dram_chan_stats_get(const dram_ctrl *c, int channel, dram_chan_stats *out)
{
    const dchan *ch = &c->ch[channel];
    *out = ch->st;
    out->queue_occupancy_sum += (uint64_t)(c->clk - ch->occ_upto) * (uint64_t)(ch->readq.n + ch->writeq.n + ch->pend_n);
    for (int r = 0; r < c->nrank; r++)
        if (ch->ranks[r].nopen)
            out->open_cycles += (uint64_t)(c->clk - ch->ranks[r].open_since);
}
