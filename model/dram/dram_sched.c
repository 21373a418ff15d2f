/* dram_sched.c — FR-FCFS-Cap command scheduling (dram_sched.h): readiness of
 * a request's next command from the earliest-issue bookkeeping, the scan of a
 * queue (per entry in the reference mode, per bank and request class
 * otherwise), and the bounds that let the controller skip idle cycles. */
#include "model/dram/dram_sched.h"

static inline int64_t min64(int64_t a, int64_t b) { return a < b ? a : b; }

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
    const dreq *const pool = ch->pool.slot;
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
    const dreq *const pool = ch->pool.slot;
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

/* The banks with entries in a counted queue, in index order, each with its
 * class times (the rank bounds computed once per rank): the walk shared by
 * pick_counted and dram_sched_queue_bound. */
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
    uint8_t mask[DRAM_MAX_BANK_INDEX];
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
    const dreq *const pool = ch->pool.slot;
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
int64_t dram_sched_queue_bound(const dram_ctrl *c, dchan *ch, const dqueue *q, int64_t lo)
{
    if (q->n == 0)
        return lo;
    if (!q->bc) {
        for (int i = q->head; i >= 0; i = ch->pool.slot[i].next) {
            const int64_t e = earliest(c, ch, &ch->pool.slot[i], first_cmd(c, ch, &ch->pool.slot[i]));
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

/* After a command: the scan of the next tick finds nothing to issue when every
 * candidate's earliest cycle is later than that tick; then it would only set
 * sched_wake to that bound, which is set here instead (the queues it scans are
 * those of the current mode; a mode change or refresh at that tick resets it,
 * and adds fold themselves in as after a fruitless scan). */
void dram_sched_after_issue(const dram_ctrl *c, dchan *ch)
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
            lo = dram_sched_queue_bound(c, ch, q, lo);
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
        lo = dram_sched_queue_bound(c, ch, q, dram_sched_queue_bound(c, ch, &ch->actq, lo));
    }
    if (lo > c->clk + 1)
        ch->sched_wake = lo;
}

int dram_sched_choose(const dram_ctrl *c, dchan *ch, dqueue **from, int *cmd_out)
{
    const int64_t now = c->clk;
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
        cmd = first_cmd(c, ch, &ch->pool.slot[i]);
        if (earliest(c, ch, &ch->pool.slot[i], cmd) > now)
            i = -1;
    }
    if (i < 0) {
        q = mq;
        if (shared)
            i = may_find1(ch, q, &cr) ? find_ready1(ch, q, 1, &cr) : -1;
        else
            i = c->exhaustive || q == &ch->otherq ? pick(c, ch, q, 1, &lo) : pick_counted(c, ch, q, 1, &lo);
        if (i >= 0) {
            cmd = first_cmd(c, ch, &ch->pool.slot[i]);
            if (earliest(c, ch, &ch->pool.slot[i], cmd) > now)
                i = -1;
        }
        if (i < 0) { /* full scans of both queues: lo bounds the next issue */
            if (shared) /* computed only now: unused when a command issues */
                lo = class_bound(ch, ch->actq.cls_other | mq->cls_other, ch->actq.cls_rd | mq->cls_rd,
                                 ch->actq.cls_wr | mq->cls_wr, lo);
            ch->sched_wake = lo;
            return -1;
        }
    }
    ch->sched_wake = 0;
    *from = q;
    *cmd_out = cmd;
    return i;
}

void dram_sched_added(const dram_ctrl *c, dchan *ch, const dqueue *q, const dreq *r)
{
    /* The last scan (or the bound set after the last command) found nothing issuable
     * before sched_wake and nothing changed since but this entry: the bound stays valid with the entry's own earliest
     * cycle folded in (as the next scan would compute it) when the next scan looks
     * at its queue; a queue it does not look at leaves it unchanged (a mode change
     * resets it). */
    if (ch->sched_wake && !ch->otherq.n && q == (ch->write_mode ? &ch->writeq : &ch->readq)) {
        const int64_t e = earliest(c, ch, r, first_cmd(c, ch, r));
        if (e < ch->sched_wake)
            ch->sched_wake = e > 0 ? e : 0;
    }
}

int64_t dram_sched_requests_bound(const dram_ctrl *c, dchan *ch)
{
    int64_t lo = INT64_MAX;
    const dqueue *a = &ch->actq, *r = &ch->readq, *w = &ch->writeq;
    if (c->fast_scan) {
        const uint64_t other = a->cls_other | r->cls_other | w->cls_other;
        lo = class_bound(ch, other, a->cls_rd | r->cls_rd | w->cls_rd, a->cls_wr | r->cls_wr | w->cls_wr, lo);
    } else {
        lo = dram_sched_queue_bound(c, ch, w, dram_sched_queue_bound(c, ch, r, dram_sched_queue_bound(c, ch, a, lo)));
    }
    return lo;
}
