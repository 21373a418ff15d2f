/* dram_queue.c — the request queues of a DRAM channel (dram_queue.h): a slot
 * pool, queues linked in push order and per bank, per-bank class counters. */
#include "model/dram/dram_queue.h"

#include <stdio.h>
#include <stdlib.h>

void *dram_xcalloc(size_t n, size_t sz)
{
    void *p = calloc(n ? n : 1, sz);
    if (!p) {
        fprintf(stderr, "dram_ctrl: out of memory\n");
        exit(1);
    }
    return p;
}

void dram_queue_init(dqueue *q, int nbanks)
{
    q->n = 0;
    q->head = q->tail = -1;
    if (nbanks) {
        q->bc = dram_xcalloc((size_t)nbanks, sizeof *q->bc);
        q->bhead = dram_xcalloc((size_t)nbanks, sizeof *q->bhead);
        q->btail = dram_xcalloc((size_t)nbanks, sizeof *q->btail);
        for (int i = 0; i < nbanks; i++)
            q->bhead[i] = q->btail[i] = -1;
    }
}

void dram_queue_free(dqueue *q)
{
    free(q->bc);
    free(q->bhead);
    free(q->btail);
}

/* The class bits of bank bidx in q from its counters. */
static inline void class_bits(dqueue *q, int bidx)
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
static inline void bank_count(dqueue *q, const dreq *r, int d)
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

void dram_queue_recount(dreq_pool *p, dqueue *q, int bidx, int32_t open_row)
{
    dqcount *k = &q->bc[bidx];
    if (!k->n)
        return; /* no entries: no hits, class bits clear */
    const int had_hits = k->n != k->cnt[CLS_OTHER];
    dreq *const pool = p->slot;
    if (open_row >= 0) {
        const uint32_t row = (uint32_t)open_row;
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
    class_bits(q, bidx);
}

/* A free pool slot (the pool grows by doubling; slots are indices, so links survive). */
static int slot_alloc(dreq_pool *p)
{
    if (p->free < 0) {
        const int ncap = p->cap ? 2 * p->cap : 64;
        dreq *nv = realloc(p->slot, (size_t)ncap * sizeof *nv);
        if (!nv) {
            fprintf(stderr, "dram_ctrl: out of memory\n");
            exit(1);
        }
        p->slot = nv;
        for (int i = ncap - 1; i >= p->cap; i--) {
            nv[i].next = p->free;
            p->free = i;
        }
        p->cap = ncap;
    }
    const int s = p->free;
    p->free = p->slot[s].next;
    return s;
}

void dram_queue_link(dreq_pool *p, dqueue *q, int s, int32_t open_row)
{
    dreq *const pool = p->slot;
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
    /* counted queues hold reads and writes only; the class picked by a comparison
     * (not CLS_RD + type) lets gcc -O3 see cnt[] is not overrun where it inlines
     * the refresh push (-Warray-bounds) */
    r->cls = open_row >= 0 && (uint32_t)open_row == r->row ? (uint8_t)(r->type == REQ_WRITE ? CLS_WR : CLS_RD)
                                                                 : (uint8_t)CLS_OTHER;
    bank_count(q, r, +1);
    const int bt = q->btail[r->bidx];
    r->bprev = bt;
    r->bnext = -1;
    if (bt >= 0)
        pool[bt].bnext = s;
    else
        q->bhead[r->bidx] = s;
    q->btail[r->bidx] = s;
}

void dram_queue_unlink(dreq_pool *p, dqueue *q, int s)
{
    dreq *const pool = p->slot;
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
    bank_count(q, r, -1);
    if (r->bprev >= 0)
        pool[r->bprev].bnext = r->bnext;
    else
        q->bhead[r->bidx] = r->bnext;
    if (r->bnext >= 0)
        pool[r->bnext].bprev = r->bprev;
    else
        q->btail[r->bidx] = r->bprev;
}

int dram_queue_push(dreq_pool *p, dqueue *q, const dreq *r, int32_t open_row)
{
    const int s = slot_alloc(p);
    p->slot[s] = *r;
    dram_queue_link(p, q, s, open_row);
    return s;
}

void dram_queue_erase(dreq_pool *p, dqueue *q, int s)
{
    dram_queue_unlink(p, q, s);
    p->slot[s].next = p->free;
    p->free = s;
}

void dram_pool_free(dreq_pool *p)
{
    free(p->slot);
    p->slot = NULL;
    p->cap = 0;
    p->free = -1;
}

void dram_pend_push(dpend_ring *ring, uint64_t addr, uint64_t tag, int64_t arrive, int64_t depart)
{
    if (ring->n == ring->cap) {
        int ncap = ring->cap ? 2 * ring->cap : 16;
        dpend *nv = dram_xcalloc((size_t)ncap, sizeof *nv);
        for (int i = 0; i < ring->n; i++)
            nv[i] = ring->buf[(ring->head + i) % ring->cap];
        free(ring->buf);
        ring->buf = nv;
        ring->cap = ncap;
        ring->head = 0;
    }
    ring->buf[(ring->head + ring->n++) & (ring->cap - 1)] = (dpend){addr, tag, arrive, depart};
}
