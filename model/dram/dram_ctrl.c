/* dram_ctrl.c — the controller of dram_ctrl.h: the public API, the bank
 * state machines, refresh, the earliest-issue bookkeeping that turns the
 * spec's constraint rows into O(1) readiness checks, and the tick. The
 * queues are in dram_queue.c, the choice of the next command in dram_sched.c. */
#include "model/dram/dram_ctrl.h"

#include "model/dram/dram_ctrl_state.h"
#include "model/dram/dram_sched.h"

#include <stdlib.h>
#include <string.h>

/* A history entry of a command never issued. */
#define NEVER INT64_MIN

dram_ctrl *dram_ctrl_create(const dram_spec *spec, dram_done_fn done, void *user, char *err, size_t errlen)
{
    dram_ctrl *c = dram_xcalloc(1, sizeof *c);
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
    c->ch = dram_xcalloc((size_t)c->nch, sizeof *c->ch);
    for (int i = 0; i < c->nch; i++) {
        dchan *ch = &c->ch[i];
        dram_queue_init(&ch->readq, c->nrank * c->nbank);
        dram_queue_init(&ch->writeq, c->nrank * c->nbank);
        dram_queue_init(&ch->actq, c->nrank * c->nbank);
        dram_queue_init(&ch->otherq, 0);
        ch->pool.free = -1;
        ch->refresh_due = spec->refresh_interval;
        ch->ranks = dram_xcalloc((size_t)c->nrank, sizeof *ch->ranks);
        ch->banks = dram_xcalloc((size_t)(c->nrank * c->nbank), sizeof *ch->banks);
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
        dram_queue_free(&ch->readq);
        dram_queue_free(&ch->writeq);
        dram_queue_free(&ch->actq);
        dram_queue_free(&ch->otherq);
        dram_pool_free(&ch->pool);
        free(ch->pend.buf);
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
    const int32_t row = ch->banks[bidx].open_row;
    if (ch->readq.bc[bidx].n)
        dram_queue_recount(&ch->pool, &ch->readq, bidx, row);
    if (ch->writeq.bc[bidx].n)
        dram_queue_recount(&ch->pool, &ch->writeq, bidx, row);
    if (ch->actq.bc[bidx].n)
        dram_queue_recount(&ch->pool, &ch->actq, bidx, row);
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
    ch->st.queue_occupancy_sum += (uint64_t)(upto - ch->occ_upto) * (uint64_t)(ch->readq.n + ch->writeq.n + ch->pend.n);
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
        for (int i = ch->writeq.head; i >= 0; i = ch->pool.slot[i].next)
            if (ch->pool.slot[i].addr == addr) { /* forwarded from the write queue */
                ch->st.reads_forwarded++;
                dram_pend_push(&ch->pend, addr, tag, c->clk, c->clk + 1);
                return true;
            }
    dqueue *q = queue_for(ch, is_write);
    dram_queue_push(&ch->pool, q, &r, ch->banks[r.bidx].open_row);
    if (is_write)
        ch->wr_live++;
    else
        ch->rd_live++;
    dram_sched_added(c, ch, q, &r);
    return true;
}

static int write_mode_next(const dram_ctrl *c, const dchan *ch)
{
    const int hi = c->wq_hi, lo = c->wq_lo;
    if (!ch->write_mode)
        return ch->writeq.n > hi || ch->readq.n == 0;
    return !(ch->writeq.n < lo && ch->readq.n != 0);
}

static void chan_tick(dram_ctrl *c, int chi)
{
    dchan *ch = &c->ch[chi];
    const int64_t now = c->clk;
    occ_flush(ch, now);
    /* 1. one completed read */
    if (ch->pend.n && dram_pend_head(&ch->pend)->depart <= now) {
        const dpend r = *dram_pend_head(&ch->pend);
        dram_pend_pop(&ch->pend);
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
            dram_queue_push(&ch->pool, &ch->otherq, &r, -1);
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
    dqueue *q;
    int cmd;
    const int i = dram_sched_choose(c, ch, &q, &cmd);
    if (i < 0)
        return;
    dreq *r = &ch->pool.slot[i];
    if (r->first && r->type != REQ_REFRESH) {
        r->first = 0;
        const dbank *b = &ch->banks[r->bidx];
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
            dram_queue_unlink(&ch->pool, q, i);
            dram_queue_link(&ch->pool, &ch->actq, i, ch->banks[r->bidx].open_row);
        }
        dram_sched_after_issue(c, ch);
        return;
    }
    /* the fields the completion needs, before the slot is freed (a done callback may add) */
    const int type = r->type;
    const uint64_t addr = r->addr, tag = r->tag;
    const int64_t arrive = r->arrive;
    dram_queue_erase(&ch->pool, q, i);
    if (type == REQ_READ) {
        ch->rd_live--;
        dram_pend_push(&ch->pend, addr, tag, arrive, now + c->spec->read_latency);
    } else if (type == REQ_REFRESH) {
        c->pending--;
    } else if (type == REQ_WRITE) {
        ch->wr_live--;
        c->pending--;
        ch->st.writes_done++;
        if (c->done)
            c->done(c->done_user, addr, tag, true, now - arrive);
    }
    dram_sched_after_issue(c, ch);
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
    if (ch->pend.n && dram_pend_head(&ch->pend)->depart < t)
        t = dram_pend_head(&ch->pend)->depart;
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
    if (ch->pend.n && dram_pend_head(&ch->pend)->depart < t)
        t = dram_pend_head(&ch->pend)->depart;
    if (ch->otherq.n)
        t = dram_sched_queue_bound(c, ch, &ch->otherq, t);
    if (ch->wr_live || (ch->rd_live && !ch->pend.n)) {
        int64_t lo = dram_sched_requests_bound(c, ch);
        lo = lo < soon ? soon : lo;
        if (ch->wr_live && lo < t)
            t = lo;
        if (ch->rd_live && !ch->pend.n && lo + c->spec->read_latency < t)
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
    out->queue_occupancy_sum += (uint64_t)(c->clk - ch->occ_upto) * (uint64_t)(ch->readq.n + ch->writeq.n + ch->pend.n);
    for (int r = 0; r < c->nrank; r++)
        if (ch->ranks[r].nopen)
            out->open_cycles += (uint64_t)(c->clk - ch->ranks[r].open_since);
}
