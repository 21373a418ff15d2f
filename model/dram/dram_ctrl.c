/* dram_ctrl.c — the controller of dram_ctrl.h: queues, FR-FCFS-Cap scheduler,
 * bank state machines, refresh, and the earliest-issue bookkeeping that turns
 * the spec's constraint rows into O(1) readiness checks. */
#include "model/dram/dram_ctrl.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { REQ_READ, REQ_WRITE, REQ_REFRESH };
#define NEVER INT64_MIN

typedef struct dreq {
    uint64_t addr, tag;
    int64_t arrive;
    uint32_t row;
    uint16_t rank, bank;
    uint16_t bidx;         /* rank * banks + bank */
    uint8_t type;
    uint8_t first;         /* no command issued yet (row hit/miss/conflict not yet counted) */
    uint8_t cls;           /* in a counted queue: its request class (CLS_*: a row hit of its
                              bank's open row by type, or not; kept by q_link and q_recount,
                              so the scans need not look at the bank) */
    uint64_t seq;          /* in a queue: its push number there (queue order = seq order) */
    int32_t prev, next;    /* in a queue: neighbours in queue order (pool slots, -1 none) */
    int32_t bprev, bnext;  /* in a counted queue: neighbours among the entries of its bank */
} dreq;

/* Request classes of a bank's entries: the entries of a class share their next
 * command (ACT if the bank is closed, PRE if another row is open; RD; WR). */
enum { CLS_OTHER, CLS_RD, CLS_WR };

/* A request queue. Read, write and act queues also keep, per bank, how many
 * entries target it and how many of them fall in each class, so the scheduler
 * decides "can anything issue now" per bank instead of per entry. */
typedef struct dqcount {
    uint16_t n;            /* entries targeting the bank */
    uint16_t cnt[3];       /* of which in each class (CLS_*) */
} dqcount;

/* Bank indices per channel at most (ranks <= 8, banks <= 64: dram_timing.c). */
#define MAX_BANK_INDEX 512
#define BANK_WORDS (MAX_BANK_INDEX / 64)

/* Entries live in slots of the channel's pool and never move while queued: a
 * queue links them in queue order (push order; FR-FCFS "first" = lowest seq) and,
 * counted queues, per bank as well, so removal is an unlink (no shifting of the
 * entries behind), a bank's row-hit recount visits only that bank's entries, and
 * the search for the first ready entry visits only the ready banks' entries. */
typedef struct dqueue {
    int n;
    int head, tail;        /* first / last entry in queue order, -1: empty */
    uint64_t seq;          /* pushes so far (the next entry's seq) */
    int32_t *bhead;        /* per bank index: its first entry in queue order (counted queues) */
    int32_t *btail;        /* per bank index: its last entry */
    dqcount *bc;           /* per bank index (rank * banks + bank); NULL: not counted (otherq) */
    uint64_t used[BANK_WORDS]; /* bit i: bc[i].n > 0 (the scan visits only these banks) */
    /* banks 0..63 by request class (channels of at most 64 banks, one rank: the
     * fast scan): entries that are no row hit, read row hits, write row hits */
    union {
        uint64_t cls[3];   /* by class (CLS_*) */
        struct {
            uint64_t cls_other, cls_rd, cls_wr;
        };
    };
} dqueue;

/* A read waiting for its data (or forwarded from the write queue). */
typedef struct dpend {
    uint64_t addr, tag;
    int64_t arrive, depart;
} dpend;

typedef struct dbank {
    int64_t next[DRAM_NCMD];   /* earliest cycle each command may issue (bank constraints); the
                                  command may issue at the max of this and the channel's and
                                  rank's next[] (combined where needed, not kept per bank: a
                                  command changes the channel's next[] of every bank at once) */
    int32_t open_row;          /* -1 = closed */
    int32_t hits;              /* RD/WR to the open row since its ACT (Ramulator RowTable) */
    int64_t pad;               /* to 64 bytes: the class scans index banks by a shift */
} dbank;

typedef struct drank {
    int64_t next[DRAM_NCMD];
    int64_t hist[DRAM_NCMD][DRAM_MAX_WINDOW]; /* latest issue cycles, newest first */
    int nopen;                 /* open banks */
    int64_t open_since;        /* cycle the first bank opened (energy background) */
} drank;

typedef struct dchan {
    int64_t next[DRAM_NCMD];
    int64_t bound[DRAM_NCMD];  /* fast scan (one rank): max of next[] and rank 0's next[], the
                                  channel/rank bound of the class scans, kept by issue() */
    int64_t hist[DRAM_NCMD][DRAM_MAX_WINDOW];
    dqueue readq, writeq, actq, otherq;
    dreq *pool;                /* entry slots of the four queues */
    int pool_cap, pool_free;   /* free slots linked through next, -1: none */
    dpend *pend;               /* ring of reads waiting for their data, FIFO */
    int pend_head, pend_n, pend_cap; /* pend_cap: 0 or a power of two (index by mask) */
    drank *ranks;
    dbank *banks;              /* rank-major */
    int write_mode;
    uint64_t open_mask;        /* banks 0..63 with an open row */
    uint64_t capped_mask;      /* banks 0..63 whose row hits exceed the cap */
    int64_t sched_wake;        /* no command can issue before this cycle unless the queues or
                                  bank states change (0 = unknown: run the scheduler) */
    int64_t refreshed;         /* cycle of the last refresh injection */
    int64_t refresh_due;       /* refreshed + refresh interval (the next injection) */
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
     * in one loop (each row only raises a next[], so the order does not matter); the
     * first n_irows1 have a window of 1 (measured from now: no history look-up) */
    issue_row irows[DRAM_NCMD][DRAM_MAX_CONSTRAINTS];
    int n_irows[DRAM_NCMD], n_irows1[DRAM_NCMD];
    unsigned bound_mask[DRAM_NCMD]; /* per FROM command, the TO commands of its channel and
                                       rank rows (the bound[] entries it can raise) */
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

static void q_init(dqueue *q, int nbanks)
{
    q->n = 0;
    q->head = q->tail = -1;
    if (nbanks) {
        q->bc = xcalloc((size_t)nbanks, sizeof *q->bc);
        q->bhead = xcalloc((size_t)nbanks, sizeof *q->bhead);
        q->btail = xcalloc((size_t)nbanks, sizeof *q->btail);
        for (int i = 0; i < nbanks; i++)
            q->bhead[i] = q->btail[i] = -1;
    }
}

static void q_free(dqueue *q)
{
    free(q->bc);
    free(q->bhead);
    free(q->btail);
}

/* The class bits of bank bidx in q from its counters. */
static inline void q_class_bits(dqueue *q, int bidx)
{
    if (bidx >= 64)
        return;
    const dqcount k = q->bc[bidx];
    const uint64_t bit = 1ull << bidx;
    q->cls_other = k.cnt[CLS_OTHER] ? q->cls_other | bit : q->cls_other & ~bit;
    q->cls_rd = k.cnt[CLS_RD] ? q->cls_rd | bit : q->cls_rd & ~bit;
    q->cls_wr = k.cnt[CLS_WR] ? q->cls_wr | bit : q->cls_wr & ~bit;
}

/* Per-bank counters of a counted queue: entry r (its class current) joins (d = +1)
 * or leaves (d = -1). Only r's class can change its bit: set on joining, cleared
 * when the class's count drops to 0. */
static inline void q_count(dqueue *q, const dreq *r, int d)
{
    dqcount *k = &q->bc[r->bidx];
    k->n = (uint16_t)(k->n + d);
    k->cnt[r->cls] = (uint16_t)(k->cnt[r->cls] + d);
    const uint64_t bit = 1ull << (r->bidx & 63);
    if (d > 0) {
        q->used[r->bidx >> 6] |= bit;
        if (r->bidx < 64)
            q->cls[r->cls] |= bit;
    } else {
        if (!k->n)
            q->used[r->bidx >> 6] &= ~bit;
        if (r->bidx < 64 && !k->cnt[r->cls])
            q->cls[r->cls] &= ~bit;
    }
}

/* Bank bidx changed its open row: recount its row hits in a counted queue. */
static void q_recount(dchan *ch, dqueue *q, int bidx)
{
    dqcount *k = &q->bc[bidx];
    if (!k->n)
        return; /* no entries: no hits, class bits clear */
    const int had_hits = k->n != k->cnt[CLS_OTHER];
    dreq *const pool = ch->pool;
    if (ch->banks[bidx].open_row >= 0) {
        const uint32_t row = (uint32_t)ch->banks[bidx].open_row;
        k->cnt[CLS_OTHER] = k->cnt[CLS_RD] = k->cnt[CLS_WR] = 0;
        for (int s = q->bhead[bidx]; s >= 0; s = pool[s].bnext) {
            dreq *r = &pool[s];
            r->cls = r->row == row ? (uint8_t)(r->type == REQ_WRITE ? CLS_WR : CLS_RD) : (uint8_t)CLS_OTHER;
            k->cnt[r->cls]++;
        }
    } else if (had_hits) { /* closed: only former hits have a class to reset */
        k->cnt[CLS_OTHER] = k->n;
        k->cnt[CLS_RD] = k->cnt[CLS_WR] = 0;
        for (int s = q->bhead[bidx]; s >= 0; s = pool[s].bnext)
            pool[s].cls = CLS_OTHER;
    } else {
        return; /* all were and stay CLS_OTHER */
    }
    q_class_bits(q, bidx);
}

/* A free pool slot (the pool grows by doubling; slots are indices, so links survive). */
static int slot_alloc(dchan *ch)
{
    if (ch->pool_free < 0) {
        const int ncap = ch->pool_cap ? 2 * ch->pool_cap : 64;
        dreq *nv = realloc(ch->pool, (size_t)ncap * sizeof *nv);
        if (!nv) {
            fprintf(stderr, "dram_ctrl: out of memory\n");
            exit(1);
        }
        ch->pool = nv;
        for (int i = ncap - 1; i >= ch->pool_cap; i--) {
            nv[i].next = ch->pool_free;
            ch->pool_free = i;
        }
        ch->pool_cap = ncap;
    }
    const int s = ch->pool_free;
    ch->pool_free = ch->pool[s].next;
    return s;
}

/* Links slot s (its request fields set) at the back of q. */
static void q_link(dchan *ch, dqueue *q, int s)
{
    dreq *const pool = ch->pool;
    dreq *r = &pool[s];
    r->seq = q->seq++;
    r->prev = q->tail;
    r->next = -1;
    if (q->tail >= 0)
        pool[q->tail].next = s;
    else
        q->head = s;
    q->tail = s;
    q->n++;
    if (!q->bc)
        return;
    const dbank *b = &ch->banks[r->bidx];
    /* counted queues hold reads and writes only; the class picked by a comparison
     * (not CLS_RD + type) lets gcc -O3 see cnt[] is not overrun where it inlines
     * the refresh push (-Warray-bounds) */
    r->cls = b->open_row >= 0 && (uint32_t)b->open_row == r->row ? (uint8_t)(r->type == REQ_WRITE ? CLS_WR : CLS_RD)
                                                                 : (uint8_t)CLS_OTHER;
    q_count(q, r, +1);
    const int bt = q->btail[r->bidx];
    r->bprev = bt;
    r->bnext = -1;
    if (bt >= 0)
        pool[bt].bnext = s;
    else
        q->bhead[r->bidx] = s;
    q->btail[r->bidx] = s;
}

/* Unlinks slot s from q (the slot stays allocated). */
static void q_unlink(dchan *ch, dqueue *q, int s)
{
    dreq *const pool = ch->pool;
    const dreq *r = &pool[s];
    if (r->prev >= 0)
        pool[r->prev].next = r->next;
    else
        q->head = r->next;
    if (r->next >= 0)
        pool[r->next].prev = r->prev;
    else
        q->tail = r->prev;
    q->n--;
    if (!q->bc)
        return;
    q_count(q, r, -1);
    if (r->bprev >= 0)
        pool[r->bprev].bnext = r->bnext;
    else
        q->bhead[r->bidx] = r->bnext;
    if (r->bnext >= 0)
        pool[r->bnext].bprev = r->bprev;
    else
        q->btail[r->bidx] = r->bprev;
}

static void q_push(dchan *ch, dqueue *q, const dreq *r)
{
    const int s = slot_alloc(ch);
    ch->pool[s] = *r;
    q_link(ch, q, s);
}

static void q_erase(dchan *ch, dqueue *q, int s)
{
    q_unlink(ch, q, s);
    ch->pool[s].next = ch->pool_free;
    ch->pool_free = s;
}

static void pend_push(dchan *ch, uint64_t addr, uint64_t tag, int64_t arrive, int64_t depart)
{
    if (ch->pend_n == ch->pend_cap) {
        int ncap = ch->pend_cap ? 2 * ch->pend_cap : 16;
        dpend *nv = xcalloc((size_t)ncap, sizeof *nv);
        for (int i = 0; i < ch->pend_n; i++)
            nv[i] = ch->pend[(ch->pend_head + i) % ch->pend_cap];
        free(ch->pend);
        ch->pend = nv;
        ch->pend_cap = ncap;
        ch->pend_head = 0;
    }
    ch->pend[(ch->pend_head + ch->pend_n++) & (ch->pend_cap - 1)] = (dpend){addr, tag, arrive, depart};
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
        for (int pass = 0; pass < 2; pass++) /* window 1 first */
            for (int sc = 0; sc < nscope; sc++)
                for (int i = 0; i < c->row_count[sc][f]; i++) {
                    const cons_row *r = &c->rows[c->row_start[sc][f] + i];
                    if ((r->window == 1) != (pass == 0))
                        continue;
                    c->irows[f][c->n_irows[f]++] = (issue_row){(uint8_t)sc, r->to, r->window, r->cycles};
                    c->n_irows1[f] += pass == 0;
                    if (sc != DRAM_SCOPE_BANK)
                        c->bound_mask[f] |= 1u << r->to;
                }
    }
    c->ch = xcalloc((size_t)c->nch, sizeof *c->ch);
    for (int i = 0; i < c->nch; i++) {
        dchan *ch = &c->ch[i];
        q_init(&ch->readq, c->nrank * c->nbank);
        q_init(&ch->writeq, c->nrank * c->nbank);
        q_init(&ch->actq, c->nrank * c->nbank);
        q_init(&ch->otherq, 0);
        ch->pool_free = -1;
        ch->refresh_due = spec->refresh_interval;
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
        free(ch->pool);
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
 * oldest (ties: first in queue). `sorted` queues are in arrival order. Returns its
 * pool slot, -1 if empty. */
static int pick(const dram_ctrl *c, dchan *ch, dqueue *q, int sorted, int64_t *min_earliest)
{
    int best = -1, best_ready = 0;
    const int cap = c->spec->row_hit_cap;
    int64_t lo = *min_earliest;
    const dreq *const pool = ch->pool;
    for (int i = q->head; i >= 0; i = pool[i].next) {
        const dreq *r = &pool[i];
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
        } else if (ready == best_ready && r->arrive < pool[best].arrive) {
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

/* One command class of pick_counted1: banks `bits` need `cmd`; their earliest cycle
 * is max(channel/rank bound, bank next[cmd]). Returns the banks ready at now (none
 * while the channel/rank bound is later, without looking at the banks). */
static inline uint64_t class_scan(const dchan *ch, uint64_t bits, int cmd, int64_t now)
{
    if (!bits || ch->bound[cmd] > now)
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
    const int64_t e = max64(ch->bound[cmd], mn);
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

/* Whether find_ready1 could return an entry of q: some class of q is ready or has
 * capped row hits (see there); tested inline before the call. */
static inline int may_find1(const dchan *ch, const dqueue *q, const class_ready *cr)
{
    return q->n && ((cr->other & q->cls_other) | ((cr->rd | ch->capped_mask) & q->cls_rd) |
                    ((cr->wr | ch->capped_mask) & q->cls_wr)) != 0;
}

/* pick_counted's choice in q given the ready sets of class_state (which covered
 * q's classes): the first (sorted) or oldest ready entry, else the first or oldest
 * of all (ties: first in queue). A bank's entries are ready by class, so only the
 * ready banks' entries are visited, each bank's in queue order (the first ready one
 * of a bank is its candidate when sorted); "first" across banks is the lowest seq.
 * Returns a pool slot, or -1 when nothing in q can issue now. */
static int find_ready1(const dchan *ch, const dqueue *q, int sorted, const class_ready *cr)
{
    const dreq *const pool = ch->pool;
    const uint64_t set[3] = {cr->other & q->cls_other, cr->rd & q->cls_rd, cr->wr & q->cls_wr};
    int best = -1;
    for (uint64_t bits = set[CLS_OTHER] | set[CLS_RD] | set[CLS_WR]; bits; bits &= bits - 1) {
        const int b = __builtin_ctzll(bits);
        for (int s = q->bhead[b]; s >= 0; s = pool[s].bnext) {
            const dreq *r = &pool[s];
            if (!((set[r->cls] >> b) & 1))
                continue;
            if (sorted) {
                if (best < 0 || r->seq < pool[best].seq)
                    best = s;
                break;
            }
            if (best < 0 || r->arrive < pool[best].arrive ||
                (r->arrive == pool[best].arrive && r->seq < pool[best].seq))
                best = s;
        }
    }
    if (best >= 0)
        return best;
    /* Without ready entries the choice is the first or oldest of all, which can issue
     * only if its class was left out of the ready sets for the row-hit cap alone (a
     * class not ready has its earliest cycle ahead): else skip the search. */
    if (!((q->cls_rd | q->cls_wr) & ch->capped_mask))
        return -1;
    if (sorted)
        return q->head;
    best = q->head; /* the oldest of all */
    for (int s = pool[best].next; s >= 0; s = pool[s].next)
        if (pool[s].arrive < pool[best].arrive)
            best = s;
    return best;
}

/* pick_counted for a channel of one rank with at most 64 banks: class_state over
 * q's own classes, then find_ready1. */
static int pick_counted1(const dram_ctrl *c, dchan *ch, dqueue *q, int sorted, int64_t *min_earliest)
{
    class_ready cr;
    class_state(ch, q->cls_other, q->cls_rd, q->cls_wr, c->clk, &cr);
    *min_earliest = class_bound(ch, q->cls_other, q->cls_rd, q->cls_wr, *min_earliest);
    return find_ready1(ch, q, sorted, &cr);
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
    if (k.cnt[CLS_OTHER])
        e.other = b->open_row < 0 ? max64(t->act, b->next[DRAM_ACT]) : max64(t->pre, b->next[DRAM_PRE]);
    if (k.cnt[CLS_RD])
        e.rd = max64(t->rd, b->next[DRAM_RD]);
    if (k.cnt[CLS_WR])
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
    const dreq *const pool = ch->pool;
    int best = q->head;
    if (sorted) {
        if (any)
            for (int i = q->head; i >= 0; i = pool[i].next)
                if (counted_ready(&ch->banks[pool[i].bidx], &pool[i], mask))
                    return i;
        return q->head;
    }
    int best_ready = any ? -1 : 0; /* without ready entries, the oldest of all */
    for (int i = q->head; i >= 0; i = pool[i].next) {
        const dreq *r = &pool[i];
        if (any && !counted_ready(&ch->banks[r->bidx], r, mask))
            continue;
        if (best_ready < 0 || r->arrive < pool[best].arrive) {
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
        for (int i = q->head; i >= 0; i = ch->pool[i].next) {
            const int64_t e = earliest(c, ch, &ch->pool[i], first_cmd(c, ch, &ch->pool[i]));
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

/* Records an issue of cmd, newest first. All entries shift, a move of constant size
 * the compiler inlines (not a library call): those beyond the deepest window of cmd
 * are never read. */
static void hist_push(int64_t (*hist)[DRAM_MAX_WINDOW], int cmd, int64_t now)
{
    memmove(&hist[cmd][1], &hist[cmd][0], (DRAM_MAX_WINDOW - 1) * sizeof hist[cmd][0]);
    hist[cmd][0] = now;
}

/* The open row of bank bidx changed: keep the queues' per-bank hit counts exact. */
static void bank_row_changed(dchan *ch, int bidx)
{
    /* a queue without entries of the bank has nothing to recount (tested here: most
     * have none, a call would cost more than the test) */
    if (ch->readq.bc[bidx].n)
        q_recount(ch, &ch->readq, bidx);
    if (ch->writeq.bc[bidx].n)
        q_recount(ch, &ch->writeq, bidx);
    if (ch->actq.bc[bidx].n)
        q_recount(ch, &ch->actq, bidx);
}

/* Mirror bank bidx's open state and hit cap into the channel's masks (banks 0..63):
 * a bank opened (no hits yet: the cap is >= 0) or closed. RD/WR raise the hits and
 * set the capped bit themselves. */
static inline void bank_opened(dchan *ch, int bidx)
{
    if (bidx >= 64)
        return;
    ch->open_mask |= 1ull << bidx;
    ch->capped_mask &= ~(1ull << bidx);
}

static inline void bank_closed(dchan *ch, int bidx)
{
    if (bidx >= 64)
        return;
    ch->open_mask &= ~(1ull << bidx);
    ch->capped_mask &= ~(1ull << bidx);
}

static void close_bank(dchan *ch, drank *rk, dbank *b, int64_t now)
{
    if (b->open_row < 0)
        return;
    b->open_row = -1;
    b->hits = 0;
    bank_closed(ch, (int)(b - ch->banks));
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
        hist_push(ch->hist, cmd, now);
    if (c->max_window[DRAM_SCOPE_RANK][cmd] > 1)
        hist_push(rk->hist, cmd, now);
    dbank *banks = &ch->banks[rank * c->nbank];
    {
        int64_t *const tgt[3] = {ch->next, rk->next, banks[bank < 0 ? 0 : bank].next};
        const int64_t *const hst[2] = {ch->hist[cmd], rk->hist[cmd]};
        const issue_row *row = c->irows[cmd];
        int i = 0;
        for (const int n1 = c->n_irows1[cmd]; i < n1; i++) {
            const int64_t t = now + row[i].cycles;
            int64_t *nx = &tgt[row[i].scope][row[i].to];
            if (t > *nx)
                *nx = t;
        }
        for (const int n = c->n_irows[cmd]; i < n; i++) {
            const int64_t from = hst[row[i].scope][row[i].window - 1];
            if (from == NEVER)
                continue;
            const int64_t t = from + row[i].cycles;
            int64_t *nx = &tgt[row[i].scope][row[i].to];
            if (t > *nx)
                *nx = t;
        }
    }
    if (c->fast_scan) /* one rank: rk is rank 0 */
        for (unsigned m = c->bound_mask[cmd]; m; m &= m - 1) {
            const int k = __builtin_ctz(m);
            ch->bound[k] = max64(ch->next[k], rk->next[k]);
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
        bank_opened(ch, rank * c->nbank + bank);
        bank_row_changed(ch, rank * c->nbank + bank);
        if (rk->nopen++ == 0)
            rk->open_since = now;
        break;
    case DRAM_PRE:
        close_bank(ch, rk, &banks[bank], now);
        break;
    case DRAM_PREA:
        for (int b = 0; b < c->nbank; b++)
            close_bank(ch, rk, &banks[b], now);
        break;
    case DRAM_RD:
    case DRAM_WR:
        if (++banks[bank].hits > c->spec->row_hit_cap && rank * c->nbank + bank < 64)
            ch->capped_mask |= 1ull << (rank * c->nbank + bank);
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
    dreq r = {.addr = addr, .tag = tag, .arrive = c->clk, .row = a.row,
              .rank = (uint16_t)a.rank, .bank = (uint16_t)a.bank,
              .bidx = (uint16_t)(a.rank * (uint32_t)c->nbank + a.bank), .type = is_write ? REQ_WRITE : REQ_READ, .first = 1};
    if (!is_write)
        for (int i = ch->writeq.head; i >= 0; i = ch->pool[i].next)
            if (ch->pool[i].addr == addr) { /* forwarded from the write queue */
                ch->st.reads_forwarded++;
                pend_push(ch, addr, tag, c->clk, c->clk + 1);
                return true;
            }
    dqueue *q = queue_for(ch, is_write);
    q_push(ch, q, &r);
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
        const dpend r = ch->pend[ch->pend_head];
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
    if (now >= ch->refresh_due) {
        for (int rk = 0; rk < c->nrank; rk++) {
            dreq r = {.arrive = now, .rank = (uint16_t)rk, .bidx = (uint16_t)(rk * c->nbank), .type = REQ_REFRESH,
                      .first = 0};
            q_push(ch, &ch->otherq, &r);
            c->pending++;
        }
        ch->refreshed = now;
        ch->refresh_due = now + c->spec->refresh_interval;
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
        i = may_find1(ch, q, &cr) ? find_ready1(ch, q, 0, &cr) : -1;
    } else {
        i = c->exhaustive ? pick(c, ch, q, 0, &lo) : pick_counted(c, ch, q, 0, &lo);
    }
    if (i >= 0) {
        cmd = first_cmd(c, ch, &ch->pool[i]);
        if (earliest(c, ch, &ch->pool[i], cmd) > now)
            i = -1;
    }
    if (i < 0) {
        q = mq;
        if (shared)
            i = may_find1(ch, q, &cr) ? find_ready1(ch, q, 1, &cr) : -1;
        else
            i = c->exhaustive || q == &ch->otherq ? pick(c, ch, q, 1, &lo) : pick_counted(c, ch, q, 1, &lo);
        if (i >= 0) {
            cmd = first_cmd(c, ch, &ch->pool[i]);
            if (earliest(c, ch, &ch->pool[i], cmd) > now)
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
    dreq *r = &ch->pool[i];
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
            q_unlink(ch, q, i);
            q_link(ch, &ch->actq, i);
        }
        next_scan_bound(c, ch);
        return;
    }
    /* the fields the completion needs, before the slot is freed (a done callback may add) */
    const int type = r->type;
    const uint64_t addr = r->addr, tag = r->tag;
    const int64_t arrive = r->arrive;
    q_erase(ch, q, i);
    if (type == REQ_READ) {
        ch->rd_live--;
        pend_push(ch, addr, tag, arrive, now + c->spec->read_latency);
    } else if (type == REQ_REFRESH) {
        c->pending--;
    } else if (type == REQ_WRITE) {
        ch->wr_live--;
        c->pending--;
        ch->st.writes_done++;
        if (c->done)
            c->done(c->done_user, addr, tag, true, now - arrive);
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
    int64_t t = ch->refresh_due;
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
    int64_t t = ch->refresh_due;
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
