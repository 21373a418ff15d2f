/* dram_queue.h — the request queues of one DRAM channel (internal to
 * model/dram: dram_ctrl.c and dram_sched.c).
 *
 * Contract:
 *  - Requests (dreq) live in slots of a per-channel pool (dreq_pool) and never
 *    move while queued; a slot index stays valid while the pool grows.
 *  - A queue (dqueue) links its entries in push order. A counted queue
 *    (created with nbanks > 0: read, write and act queues) also links them per
 *    bank and keeps, per bank, how many entries fall in each request class
 *    (CLS_*: row hit by a read, by a write, or neither), which the scheduler
 *    reads to decide per bank, not per entry. The caller passes the open row
 *    of the entry's bank (-1 closed) where the class depends on it, and calls
 *    dram_queue_recount when a bank's open row changes.
 *  - Reads waiting for their data sit in a FIFO ring (dpend_ring).
 *  - Out of memory: message on stderr, exit(1). No randomness. */
#ifndef RTSIM_DRAM_QUEUE_H
#define RTSIM_DRAM_QUEUE_H

#include <stddef.h>
#include <stdint.h>

/* What a request asks for. */
enum { REQ_READ, REQ_WRITE, REQ_REFRESH };

typedef struct dreq {
    uint64_t addr, tag;
    int64_t arrive;
    uint32_t row;
    uint16_t rank, bank;
    uint16_t bidx;         /* rank * banks + bank */
    uint8_t type;
    uint8_t first;         /* no command issued yet (row hit/miss/conflict not yet counted) */
    uint8_t cls;           /* in a counted queue: its request class (CLS_*: a row hit of its
                              bank's open row by type, or not; kept by dram_queue_link and dram_queue_recount,
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
#define DRAM_MAX_BANK_INDEX 512
#define DRAM_BANK_WORDS (DRAM_MAX_BANK_INDEX / 64)

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
    uint64_t used[DRAM_BANK_WORDS]; /* bit i: bc[i].n > 0 (the scan visits only these banks) */
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

/* The slots of a channel's queues. */
typedef struct dreq_pool {
    dreq *slot;
    int cap, free;         /* free slots linked through next, -1: none */
} dreq_pool;

/* The reads waiting for their data, oldest first. */
typedef struct dpend_ring {
    dpend *buf;
    int head, n, cap;      /* cap: 0 or a power of two (index by mask) */
} dpend_ring;

/* calloc that exits with a message when memory runs out (the controller's files). */
void *dram_xcalloc(size_t n, size_t size);

/* nbanks > 0: a counted queue over that many bank indices (rank * banks + bank);
 * 0: a plain queue (refresh requests). */
void dram_queue_init(dqueue *q, int nbanks);
void dram_queue_free(dqueue *q);
/* Copies r into a new slot at the back of q; returns the slot. open_row: of r's
 * bank (counted queues; ignored otherwise). */
int dram_queue_push(dreq_pool *p, dqueue *q, const dreq *r, int32_t open_row);
/* Links slot s (its request fields set) at the back of q. */
void dram_queue_link(dreq_pool *p, dqueue *q, int s, int32_t open_row);
/* Unlinks slot s from q (the slot stays allocated: link it elsewhere). */
void dram_queue_unlink(dreq_pool *p, dqueue *q, int s);
/* Unlinks slot s from q and frees it. */
void dram_queue_erase(dreq_pool *p, dqueue *q, int s);
/* Bank bidx now has open_row (-1 closed): recount its entries' classes in q. */
void dram_queue_recount(dreq_pool *p, dqueue *q, int bidx, int32_t open_row);
void dram_pool_free(dreq_pool *p);

void dram_pend_push(dpend_ring *ring, uint64_t addr, uint64_t tag, int64_t arrive, int64_t depart);
/* The oldest waiting read (ring->n > 0). */
static inline const dpend *dram_pend_head(const dpend_ring *ring) { return &ring->buf[ring->head]; }
static inline void dram_pend_pop(dpend_ring *ring)
{
    ring->head = (ring->head + 1) & (ring->cap - 1);
    ring->n--;
}

#endif
