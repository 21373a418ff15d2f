/* cache_core.c — the generic cache core (tags, true LRU, MSHRs with merging, banks,
 * ports); see cache.h for the protocol.
 *
 * Organisation: line number L = addr / line; bank = L mod banks (line-
 * interleaved, Alvarez et al. 2007 as cited in paper sec. 3); set within the
 * bank = (L / banks) mod sets_per_bank. True LRU by per-way use stamps from a
 * per-cache counter (the least recently used way has the smallest stamp);
 * invalid ways are filled first, lowest index first. Ports: at most `ports`
 * accesses per cycle, and each bank reads at most `ports` lines per cycle (an
 * access with more lines in one bank takes that bank for ceil(k/ports)
 * cycles). Fills use a separate write port (no access port or bank cycle).
 *
 * Index-addressed (cache_params.index_addressed; paper sec. 3.1, the node
 * hierarchy "addressed with array indices rather than byte addresses, and
 * use a node-sized data word"): L = addr / line (a division: the line is a
 * node, 96 B for MBVH3), set within the bank = (L / banks) mod
 * sets_per_bank, sets_per_bank any whole number >= 1. Byte-addressed caches
 * keep the shifts and masks (the hot path of every default machine). */
#include "model/mem/cache_core.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_LINES_PER_ACCESS CACHE_MAX_LINES_PER_ACCESS
#define NO_LINE UINT64_MAX       /* never a line number (addresses are shifted right by >= 4) */

typedef struct mshr {
    bool busy;
    uint64_t line;        /* line number */
    int64_t since;        /* allocation cycle */
    int nwait;            /* waiters in the list (request mode) */
    int *wait;            /* waiter pool indices, capacity mshr_merge */
} mshr;

typedef struct waiter {
    mem_req req;
    int remaining;        /* lines still missing */
    int next_free;
} waiter;

struct cache_core {
    cache_params p;
    uint32_t line_shift, bank_shift, sets_per_bank;
    bool index;           /* index-addressed: divide and modulo instead of shift and mask */
    uint32_t nsets;
    uint64_t *tag;        /* line number per way, nsets * ways; NO_LINE while invalid */
    uint64_t *stamp;      /* 0 = invalid */
    uint64_t clock;       /* LRU stamp counter */
    mshr *m;
    uint64_t *mline;      /* line of each MSHR, NO_LINE when free (the search key) */
    int mshr_busy;
    /* The busy MSHRs chained per set (a line's MSHR is on the chain of the
     * line's set): a probe that misses in the tags looks only at the few
     * MSHRs of its own set instead of every busy one. Most probes of a
     * memory-bound run are rays retrying a line still in flight (looping
     * for next chance), which walked all busy MSHRs (32 at the L2 and the
     * primitive cache) to find it. */
    int *set_mshr;        /* per set: first busy MSHR of the set's chain, -1 none */
    int *mnext;           /* per MSHR: next on its set's chain, -1 last */
    int *missq;           /* ring of MSHR indices not yet sent downstream */
    int missq_head, missq_n;
    waiter *w;
    int nwaiters, free_waiter;
    int *readyq;          /* ring of waiter indices */
    int ready_head, ready_n;
    int64_t cycle;        /* cycle of the port/bank bookkeeping */
    uint32_t ports_used;
    int64_t *bank_busy_until;   /* last cycle the bank is taken */
    int64_t *bank_cycle;        /* per bank: the cycle its bank_used counts (else 0 reads) */
    uint32_t *bank_used;        /* line reads of the bank in its bank_cycle */
    uint32_t last_cycles;
    cache_stats st;
    cache_core_miss_hook hook;
    void *hook_user;
};

static uint32_t log2u(uint64_t v)
{
    uint32_t r = 0;
    while (v > 1) {
        v >>= 1;
        r++;
    }
    return r;
}
static bool pow2(uint64_t v) { return v && !(v & (v - 1)); }

uint64_t cache_core_capacity_bytes(const cache_params *p)
{
    if (!p->index_addressed)
        return p->size_bytes;
    const uint64_t per_set = (uint64_t)p->line_bytes * p->ways * p->banks;
    return per_set ? p->size_bytes / per_set * per_set : 0;
}

/* The one statement of which cache geometries work (the configuration's
 * check and cache_core_create both use it). */
int cache_core_check_params(const cache_params *p, const char *s, char *err, size_t errlen)
{
    uint64_t per_set = (uint64_t)p->line_bytes * p->ways * p->banks;
    if (p->index_addressed) {
        /* the word is a node (N x 32 B): any whole number of sets */
        if (!pow2(p->size_bytes) || p->line_bytes < 16 || p->line_bytes % 16) {
            snprintf(err, errlen,
                     "%s.size = %u must be a power of two (index-addressed, %u-byte words; a word is a multiple of 16)",
                     s, p->size_bytes, p->line_bytes);
            return -1;
        }
        if (p->ways == 0 || p->banks == 0 || !pow2(p->banks) || p->size_bytes < per_set) {
            snprintf(err, errlen,
                     "[%s]: %s.addressing = index: size/(node*ways*banks) = %u/(%u*%u*%u) must be >= 1 set (banks a "
                     "power of two); raise %s.size or lower %s.ways",
                     s, s, p->size_bytes, p->line_bytes, p->ways, p->banks, s, s);
            return -1;
        }
    } else if (!pow2(p->size_bytes) || !pow2(p->line_bytes) || p->line_bytes < 16) {
        snprintf(err, errlen, "%s.size = %u and %s.line = %u: both must be powers of two (line >= 16)", s,
                 p->size_bytes, s, p->line_bytes);
        return -1;
    }
    if (p->ways == 0 || p->banks == 0 || !pow2(p->banks) || p->ports == 0 || p->mshrs == 0 || p->mshr_merge == 0 ||
        p->hit_latency == 0) {
        snprintf(err, errlen,
                 "[%s]: ways, ports, mshrs, mshr_merge, hit_latency must be >= 1 and banks a power of two "
                 "(got ways=%u banks=%u ports=%u mshrs=%u mshr_merge=%u hit_latency=%u)",
                 s, p->ways, p->banks, p->ports, p->mshrs, p->mshr_merge, p->hit_latency);
        return -1;
    }
    if (!p->index_addressed && (p->size_bytes % per_set || !pow2(p->size_bytes / per_set))) {
        snprintf(err, errlen,
                 "[%s]: size/(line*ways*banks) = %u/(%u*%u*%u) must be a whole power of two >= 1 (sets per bank); "
                 "change %s.ways or %s.size",
                 s, p->size_bytes, p->line_bytes, p->ways, p->banks, s, s);
        return -1;
    }
    return 0;
}

/* Sets in each bank (floor for index-addressed caches; 0 for a geometry
 * cache_core_check_params refuses). */
static uint32_t sets_per_bank(const cache_params *p)
{
    uint64_t per_set = (uint64_t)p->line_bytes * p->ways * p->banks;
    return per_set ? (uint32_t)(p->size_bytes / per_set) : 0;
}

size_t cache_core_bytes(const cache_params *p)
{
    size_t nsets = (size_t)sets_per_bank(p) * p->banks, nways = nsets * p->ways;
    size_t nwaiters = (size_t)p->mshrs * p->mshr_merge;
    /* what cache_core_create allocates, array by array */
    return sizeof(cache_core) + nways * (sizeof(uint64_t) + sizeof(uint64_t)) + nsets * sizeof(int) +
           p->mshrs * (sizeof(mshr) + sizeof(uint64_t) + 2 * sizeof(int) + p->mshr_merge * sizeof(int)) +
           nwaiters * (sizeof(waiter) + sizeof(int)) + p->banks * (2 * sizeof(int64_t) + sizeof(uint32_t));
}

cache_core *cache_core_create(const cache_params *p, char *err, size_t errlen)
{
    if (cache_core_check_params(p, "cache", err, errlen))
        return NULL;
    cache_core *c = calloc(1, sizeof *c);
    if (!c) {
        snprintf(err, errlen, "cache: out of memory");
        return NULL;
    }
    c->p = *p;
    c->index = p->index_addressed != 0;
    c->line_shift = log2u(p->line_bytes);
    c->bank_shift = log2u(p->banks);
    c->sets_per_bank = sets_per_bank(p);
    c->nsets = c->sets_per_bank * p->banks;
    size_t nways = (size_t)c->nsets * p->ways;
    c->nwaiters = (int)(p->mshrs * p->mshr_merge);
    c->tag = malloc(nways * sizeof *c->tag);
    c->stamp = calloc(nways, sizeof *c->stamp);
    c->m = calloc(p->mshrs, sizeof *c->m);
    c->mline = malloc(p->mshrs * sizeof *c->mline);
    c->set_mshr = malloc(c->nsets * sizeof *c->set_mshr);
    c->mnext = malloc(p->mshrs * sizeof *c->mnext);
    c->missq = calloc(p->mshrs, sizeof *c->missq);
    c->w = calloc((size_t)c->nwaiters, sizeof *c->w);
    c->readyq = calloc((size_t)c->nwaiters, sizeof *c->readyq);
    c->bank_busy_until = calloc(p->banks, sizeof *c->bank_busy_until);
    c->bank_used = calloc(p->banks, sizeof *c->bank_used);
    c->bank_cycle = calloc(p->banks, sizeof *c->bank_cycle);
    bool ok = c->tag && c->stamp && c->m && c->mline && c->set_mshr && c->mnext && c->missq && c->w && c->readyq && c->bank_busy_until &&
              c->bank_used && c->bank_cycle;
    for (uint32_t i = 0; ok && i < p->mshrs; i++)
        ok = (c->m[i].wait = calloc(p->mshr_merge, sizeof(int))) != NULL;
    if (!ok) {
        cache_core_destroy(c);
        snprintf(err, errlen, "cache: out of memory");
        return NULL;
    }
    for (int i = 0; i < c->nwaiters; i++)
        c->w[i].next_free = i + 1 < c->nwaiters ? i + 1 : -1;
    c->free_waiter = 0;
    for (size_t i = 0; i < nways; i++)
        c->tag[i] = NO_LINE;
    for (uint32_t i = 0; i < p->mshrs; i++)
        c->mline[i] = NO_LINE;
    for (uint32_t i = 0; i < c->nsets; i++)
        c->set_mshr[i] = -1;
    for (uint32_t b = 0; b < p->banks; b++) {
        c->bank_busy_until[b] = -1;
        c->bank_cycle[b] = INT64_MIN;
    }
    c->cycle = INT64_MIN;
    c->last_cycles = 1;
    return c;
}

void cache_core_destroy(cache_core *c)
{
    if (!c)
        return;
    if (c->m)
        for (uint32_t i = 0; i < c->p.mshrs; i++)
            free(c->m[i].wait);
    free(c->tag);
    free(c->stamp);
    free(c->m);
    free(c->mline);
    free(c->set_mshr);
    free(c->mnext);
    free(c->missq);
    free(c->w);
    free(c->readyq);
    free(c->bank_busy_until);
    free(c->bank_used);
    free(c->bank_cycle);
    free(c);
}

const cache_params *cache_core_get_params(const cache_core *c) { return &c->p; }

/* Line (word) number of a byte address, and the first byte of a line. */
static inline uint64_t line_of(const cache_core *c, uint64_t addr)
{
    return c->index ? addr / c->p.line_bytes : addr >> c->line_shift;
}
static inline uint64_t addr_of(const cache_core *c, uint64_t line)
{
    return c->index ? line * c->p.line_bytes : line << c->line_shift;
}
static inline uint32_t bank_of(const cache_core *c, uint64_t line) { return (uint32_t)(line & (c->p.banks - 1)); }
static inline uint32_t set_of(const cache_core *c, uint64_t line)
{
    const uint64_t in_bank = line >> c->bank_shift;
    return bank_of(c, line) * c->sets_per_bank +
           (uint32_t)(c->index ? in_bank % c->sets_per_bank : in_bank & (c->sets_per_bank - 1));
}

/* Way index of a present line, or -1 (invalid ways hold NO_LINE). */
static inline int lookup(const cache_core *c, uint64_t line)
{
    const size_t base = (size_t)set_of(c, line) * c->p.ways;
    const uint64_t *t = c->tag + base;
    if (c->p.ways == 4) {   /* the default of every cache: the same search, unrolled */
#pragma GCC unroll 4
        for (uint32_t w = 0; w < 4; w++)
            if (t[w] == line)
                return (int)(base + w);
        return -1;
    }
    for (uint32_t w = 0; w < c->p.ways; w++)
        if (t[w] == line)
            return (int)(base + w);
    return -1;
}

/* The busy MSHR waiting for line, or -1: a walk of the line's set chain. A
 * line has at most one MSHR (one is allocated only when this finds none), so
 * the order of a chain does not matter. */
static inline int find_mshr(const cache_core *c, uint64_t line)
{
    int k = c->set_mshr[set_of(c, line)];
    while (k >= 0 && c->mline[k] != line)
        k = c->mnext[k];
    return k;
}

static int free_mshr(const cache_core *c)
{
    for (uint32_t i = 0; i < c->p.mshrs; i++)
        if (!c->m[i].busy)
            return (int)i;
    return -1;
}

/* Line reads bank b has served in cycle now. */
static inline uint32_t bank_reads(const cache_core *c, uint32_t b, int64_t now)
{
    return c->bank_cycle[b] == now ? c->bank_used[b] : 0;
}

static inline void bank_set_reads(cache_core *c, uint32_t b, int64_t now, uint32_t v)
{
    c->bank_cycle[b] = now;
    c->bank_used[b] = v;
}

/* Takes a free MSHR for line (queued downstream; the miss hook runs). */
static int alloc_mshr(cache_core *c, uint64_t line, int64_t now)
{
    int k = free_mshr(c);
    mshr *m = &c->m[k];
    m->busy = true;
    m->line = line;
    m->since = now;
    m->nwait = 0;
    c->mline[k] = line;
    c->mshr_busy++;
    {   /* onto the front of its set's chain */
        int *head = &c->set_mshr[set_of(c, line)];
        c->mnext[k] = *head;
        *head = k;
    }
    c->missq[(c->missq_head + c->missq_n++) % (int)c->p.mshrs] = k;
    c->st.miss_lines++;
    if (c->hook)
        c->hook(c->hook_user);
    return k;
}

static cache_result access_multi(cache_core *c, uint64_t first, uint64_t last, uint32_t bytes, int64_t now,
                                 const mem_req *req);

/* access_multi for two lines in two different banks (an unaligned triangle over
 * two lines of the two-bank primitive cache): the same checks in the same order
 * and the same effects, without the general bookkeeping. */
/* How many of an access's need_new missing lines get a new MSHR now: all of
 * them, or -1 (BLOCKED, counted) when they do not all fit: all or nothing.
 * Except that a probe needing more new lines than the cache has MSHRs at all
 * (a 48-byte triangle over two missing lines with one MSHR) could never be
 * accepted and would loop forever: it takes the free MSHRs for its first
 * missing lines and retries for the rest. */
static inline int mshrs_to_take(cache_core *c, int need_new, const mem_req *req)
{
    int free_mshrs = (int)c->p.mshrs - c->mshr_busy;
    if (need_new <= free_mshrs)
        return need_new;
    if (req || need_new <= (int)c->p.mshrs || free_mshrs == 0) {
        c->st.blocked_mshr++;
        return -1;
    }
    return free_mshrs;
}

/* Classifies lines first..first+n-1 of a multi-line access: present (way),
 * pending (ms: its MSHR), or new misses. Returns how many new lines get an
 * MSHR (mshrs_to_take), or -1 when the access is BLOCKED (counted): an MSHR
 * it would merge into has mshr_merge waiters, the MSHRs do not suffice, or
 * a request finds no free waiter slot. */
static inline __attribute__((always_inline)) int classify_lines(cache_core *c, uint64_t first, int n, int *way, int *ms,
                                                                 int *missing, const mem_req *req)
{
    int need_new = 0;
    *missing = 0;
    for (int i = 0; i < n; i++) {
        uint64_t line = first + (uint64_t)i;
        way[i] = lookup(c, line);
        ms[i] = -1;
        if (way[i] >= 0)
            continue;
        ++*missing;
        ms[i] = find_mshr(c, line);
        if (ms[i] < 0)
            need_new++;
        else if (req && c->m[ms[i]].nwait >= (int)c->p.mshr_merge) {
            c->st.blocked_merge++;
            return -1;
        }
    }
    int alloc_new = mshrs_to_take(c, need_new, req);
    if (alloc_new < 0)
        return -1;
    if (req && *missing && c->free_waiter < 0) {
        c->st.blocked_merge++;
        return -1;
    }
    return alloc_new;
}

/* The common end of an accepted multi-line access (lines first..first+n-1,
 * port and banks already taken): LRU stamps of the present lines, hit or
 * miss counts, the request's waiter, MSHRs for up to alloc_new new lines
 * and merges into pending ones. */
static inline __attribute__((always_inline)) cache_result accept_lines(cache_core *c, uint64_t first, int n, const int *way,
                                                                    const int *ms, int missing, int alloc_new,
                                                                    const mem_req *req, int64_t now)
{
    c->st.accesses++;
    for (int i = 0; i < n; i++)
        if (way[i] >= 0)
            c->stamp[way[i]] = ++c->clock;
    if (!missing) {
        c->st.hits++;
        return CACHE_HIT;
    }
    c->st.misses++;
    int wi = -1;
    if (req) {
        wi = c->free_waiter;
        c->free_waiter = c->w[wi].next_free;
        c->w[wi].req = *req;
        c->w[wi].remaining = missing;
    }
    for (int i = 0; i < n; i++) {
        if (way[i] >= 0)
            continue;
        int k = ms[i];
        if (k >= 0)
            c->st.merged++;
        else if (alloc_new-- > 0)
            k = alloc_mshr(c, first + (uint64_t)i, now);
        else
            continue; /* a partial probe (mshrs_to_take): the rest next time */
        if (req)
            c->m[k].wait[c->m[k].nwait++] = wi;
    }
    return CACHE_MISS;
}

static cache_result access_two(cache_core *c, uint64_t first, int64_t now, const mem_req *req)
{
    const uint64_t line[2] = {first, first + 1};
    const uint32_t b[2] = {bank_of(c, line[0]), bank_of(c, line[1])};
    uint32_t used[2];
    for (int k = 0; k < 2; k++) {
        used[k] = bank_reads(c, b[k], now);
        if (!(c->bank_busy_until[b[k]] < now && (used[k] + 1 <= c->p.ports || used[k] == 0))) {
            c->st.blocked_bank++;
            return CACHE_BLOCKED;
        }
    }
    int way[2], ms[2], missing;
    int alloc_new = classify_lines(c, first, 2, way, ms, &missing, req);
    if (alloc_new < 0)
        return CACHE_BLOCKED;
    c->ports_used++;
    bank_set_reads(c, b[0], now, used[0] + 1);
    bank_set_reads(c, b[1], now, used[1] + 1);
    c->last_cycles = 1;
    return accept_lines(c, first, 2, way, ms, missing, alloc_new, req, now);
}

/* Shared body of cache_core_access / cache_core_request (inlined into both). */
static inline __attribute__((always_inline)) cache_result access_lines(cache_core *c, uint64_t addr, uint32_t bytes,
                                                                    int64_t now, const mem_req *req)
{
    if (now != c->cycle) {
        c->cycle = now;
        c->ports_used = 0;
    }
    if (c->ports_used >= c->p.ports) {
        c->st.blocked_port++;
        return CACHE_BLOCKED;
    }
    uint64_t first = line_of(c, addr);
    uint64_t last = line_of(c, addr + (bytes ? bytes : 1) - 1);
    if (first == last) {
        /* one line (every node-cache probe): the general path below specialised
         * to n = 1, with the same checks in the same order and the same effects
         * (one line needs one read of its bank for one cycle) */
        const uint32_t b = bank_of(c, first);
        const uint32_t used = bank_reads(c, b, now);
        if (!(c->bank_busy_until[b] < now && (used + 1 <= c->p.ports || used == 0))) {
            c->st.blocked_bank++;
            return CACHE_BLOCKED;
        }
        const int w = lookup(c, first);
        if (w >= 0) {
            c->ports_used++;
            bank_set_reads(c, b, now, used + 1);
            c->last_cycles = 1;
            c->st.accesses++;
            c->stamp[w] = ++c->clock;
            c->st.hits++;
            return CACHE_HIT;
        }
        int k = find_mshr(c, first);
        if (k >= 0) {
            if (req && c->m[k].nwait >= (int)c->p.mshr_merge) {
                c->st.blocked_merge++;
                return CACHE_BLOCKED;
            }
        } else if (c->mshr_busy >= (int)c->p.mshrs) {
            c->st.blocked_mshr++;
            return CACHE_BLOCKED;
        }
        if (req && c->free_waiter < 0) {
            c->st.blocked_merge++;
            return CACHE_BLOCKED;
        }
        c->ports_used++;
        bank_set_reads(c, b, now, used + 1);
        c->last_cycles = 1;
        c->st.accesses++;
        c->st.misses++;
        int wi = -1;
        if (req) {
            wi = c->free_waiter;
            c->free_waiter = c->w[wi].next_free;
            c->w[wi].req = *req;
            c->w[wi].remaining = 1;
        }
        if (k >= 0)
            c->st.merged++;
        else
            k = alloc_mshr(c, first, now);
        if (req)
            c->m[k].wait[c->m[k].nwait++] = wi;
        return CACHE_MISS;
    }
    if (last == first + 1 && bank_of(c, first) != bank_of(c, last))
        return access_two(c, first, now, req);
    return access_multi(c, first, last, bytes, now, req);
}

/* The general path of access_lines: lines first..last (port already checked). Out of
 * line so that the one-line path above stays small. */
static __attribute__((noinline)) cache_result access_multi(cache_core *c, uint64_t first, uint64_t last, uint32_t bytes,
                                                           int64_t now, const mem_req *req)
{
    int n = (int)(last - first + 1);
    if (n > MAX_LINES_PER_ACCESS) {
        fprintf(stderr, "cache: access of %u bytes spans %d lines (at most %d)\n", bytes, n, MAX_LINES_PER_ACCESS);
        abort();
    }
    /* banks: lines per bank in this access; every needed bank must be free now */
    uint32_t per_bank[MAX_LINES_PER_ACCESS] = {0}, banks_used[MAX_LINES_PER_ACCESS];
    int nb = 0;
    uint32_t cycles;
    for (int i = 0; i < n; i++) {
        uint32_t b = bank_of(c, first + (uint64_t)i);
        int k = 0;
        while (k < nb && banks_used[k] != b)
            k++;
        if (k == nb)
            banks_used[nb++] = b;
        per_bank[k]++;
    }
    /* every bank has `ports` read ports: k lines of one bank fit this cycle
     * when its ports are free enough; more than `ports` lines need a bank of
     * its own for ceil(k / ports) cycles */
    cycles = 1;
    for (int k = 0; k < nb; k++) {
        uint32_t b = banks_used[k];
        const uint32_t used = bank_reads(c, b, now);
        bool ok = c->bank_busy_until[b] < now && (used + per_bank[k] <= c->p.ports || used == 0);
        if (!ok) {
            c->st.blocked_bank++;
            return CACHE_BLOCKED;
        }
        uint32_t cyc = (per_bank[k] + c->p.ports - 1) / c->p.ports;
        if (cyc > cycles)
            cycles = cyc;
    }
    int way[MAX_LINES_PER_ACCESS], ms[MAX_LINES_PER_ACCESS], missing;
    int alloc_new = classify_lines(c, first, n, way, ms, &missing, req);
    if (alloc_new < 0)
        return CACHE_BLOCKED;
    /* accepted: take the port and banks */
    c->ports_used++;
    for (int k = 0; k < nb; k++) {
        uint32_t b = banks_used[k];
        uint32_t cyc = (per_bank[k] + c->p.ports - 1) / c->p.ports;
        bank_set_reads(c, b, now, cyc > 1 ? c->p.ports : bank_reads(c, b, now) + per_bank[k]);
        if (cyc > 1)
            c->bank_busy_until[b] = now + (int64_t)cyc - 1;
    }
    c->last_cycles = cycles;
    if (cycles > 1)
        c->st.bank_conflicts++;
    return accept_lines(c, first, n, way, ms, missing, alloc_new, req, now);
}

cache_result cache_core_access(cache_core *c, uint64_t addr, uint32_t bytes, int64_t now)
{
    return access_lines(c, addr, bytes, now, NULL);
}

cache_result cache_core_probe(void *ctx, uint64_t addr, uint32_t bytes, uint64_t now, uint32_t *cycles)
{
    cache_core *c = ctx;
    const cache_result r = access_lines(c, addr, bytes, (int64_t)now, NULL);
    if (r == CACHE_HIT)
        *cycles = c->last_cycles;
    return r;
}

cache_result cache_core_request(cache_core *c, const mem_req *req, int64_t now)
{
    return access_lines(c, req->addr, req->bytes, now, req);
}

uint32_t cache_core_last_access_cycles(const cache_core *c) { return c->last_cycles; }

bool cache_core_peek_miss(const cache_core *c, mem_req *out)
{
    if (!c->missq_n)
        return false;
    int k = c->missq[c->missq_head];
    memset(out, 0, sizeof *out);
    out->addr = addr_of(c, c->m[k].line);
    out->bytes = c->p.line_bytes;
    out->tag = (uint64_t)k;
    return true;
}

bool cache_core_pop_miss(cache_core *c, mem_req *out)
{
    if (!cache_core_peek_miss(c, out))
        return false;
    c->missq_head = (c->missq_head + 1) % (int)c->p.mshrs;
    c->missq_n--;
    return true;
}

/* Installs line in its set (set): an invalid way, else the LRU way. */
static inline void install_line(cache_core *c, uint64_t line, uint32_t set)
{
    size_t base = (size_t)set * c->p.ways, victim = base;
    for (uint32_t w = 0; w < c->p.ways; w++) {
        size_t i = base + w;
        if (!c->stamp[i]) {
            victim = i;
            break;
        }
        if (c->stamp[i] < c->stamp[victim])
            victim = i;
    }
    if (c->stamp[victim])
        c->st.evictions++;
    c->tag[victim] = line;
    c->stamp[victim] = ++c->clock;
    c->st.fills++;
    c->st.bytes_filled += c->p.line_bytes;
}

int cache_core_touch(cache_core *c, uint64_t addr, uint32_t bytes, uint64_t missed[CACHE_MAX_LINES_PER_ACCESS])
{
    const uint64_t first = line_of(c, addr), last = line_of(c, addr + (bytes ? bytes : 1) - 1);
    c->st.accesses++;
    if (first == last) {   /* every node access: one line */
        const int w = lookup(c, first);
        if (w >= 0) {
            c->stamp[w] = ++c->clock;
            c->st.hits++;
            return 0;
        }
        c->st.misses++;
        c->st.miss_lines++;
        install_line(c, first, set_of(c, first));
        missed[0] = addr_of(c, first);
        return 1;
    }
    const int n = (int)(last - first + 1);
    if (n > MAX_LINES_PER_ACCESS) {
        fprintf(stderr, "cache: access of %u bytes spans %d lines (at most %d)\n", bytes, n, MAX_LINES_PER_ACCESS);
        abort();
    }
    /* as accept_lines: the present lines' stamps first, then the fills */
    int way[MAX_LINES_PER_ACCESS], nmiss = 0;
    for (int i = 0; i < n; i++)
        if ((way[i] = lookup(c, first + (uint64_t)i)) >= 0)
            c->stamp[way[i]] = ++c->clock;
    for (int i = 0; i < n; i++)
        nmiss += way[i] < 0;
    if (!nmiss) {
        c->st.hits++;
        return 0;
    }
    c->st.misses++;
    int take = nmiss < (int)c->p.mshrs ? nmiss : (int)c->p.mshrs, k = 0;
    for (int i = 0; i < n && k < take; i++)
        if (way[i] < 0) {
            const uint64_t line = first + (uint64_t)i;
            c->st.miss_lines++;
            install_line(c, line, set_of(c, line));
            missed[k++] = addr_of(c, line);
        }
    return k;
}

int cache_core_fill(cache_core *c, const mem_resp *resp, int64_t now)
{
    (void)now;
    uint64_t line = line_of(c, resp->addr);
    if (resp->tag >= c->p.mshrs || !c->m[resp->tag].busy || c->m[resp->tag].line != line)
        return -1;
    mshr *m = &c->m[resp->tag];
    const uint32_t set = set_of(c, line);
    install_line(c, line, set);
    int released = 0;
    for (int i = 0; i < m->nwait; i++) {
        waiter *w = &c->w[m->wait[i]];
        if (--w->remaining == 0) {
            c->readyq[(c->ready_head + c->ready_n++) % c->nwaiters] = m->wait[i];
            released++;
        }
    }
    m->busy = false;
    m->nwait = 0;
    c->mline[resp->tag] = NO_LINE;
    c->mshr_busy--;
    {   /* off its set's chain */
        int *link = &c->set_mshr[set];
        while (*link != (int)resp->tag)
            link = &c->mnext[*link];
        *link = c->mnext[resp->tag];
    }
    return released;
}

bool cache_core_pop_ready(cache_core *c, mem_req *out)
{
    if (!c->ready_n)
        return false;
    int wi = c->readyq[c->ready_head];
    c->ready_head = (c->ready_head + 1) % c->nwaiters;
    c->ready_n--;
    *out = c->w[wi].req;
    c->w[wi].next_free = c->free_waiter;
    c->free_waiter = wi;
    return true;
}

bool cache_core_contains(const cache_core *c, uint64_t addr) { return lookup(c, line_of(c, addr)) >= 0; }

bool cache_core_present(void *ctx, uint64_t addr, uint32_t bytes)
{
    const cache_core *c = ctx;
    for (uint64_t l = line_of(c, addr), last = line_of(c, addr + (bytes ? bytes : 1) - 1); l <= last; l++)
        if (lookup(c, l) < 0)
            return false;
    return true;
}
bool cache_core_line_pending(const cache_core *c, uint64_t addr) { return find_mshr(c, line_of(c, addr)) >= 0; }
int cache_core_mshrs_busy(const cache_core *c) { return c->mshr_busy; }
int cache_core_misses_queued(const cache_core *c) { return c->missq_n; }
int cache_core_ready_count(const cache_core *c) { return c->ready_n; }
void cache_core_get_stats(const cache_core *c, cache_stats *out) { *out = c->st; }
const cache_stats *cache_core_stats_live(const cache_core *c) { return &c->st; }

void cache_core_set_miss_hook(cache_core *c, cache_core_miss_hook fn, void *user)
{
    c->hook = fn;
    c->hook_user = user;
}

void cache_core_describe(const cache_core *c, int64_t now, char *buf, size_t len)
{
    int oldest = -1;
    for (uint32_t i = 0; i < c->p.mshrs; i++)
        if (c->m[i].busy && (oldest < 0 || c->m[i].since < c->m[oldest].since))
            oldest = (int)i;
    int n = snprintf(buf, len, "mshrs %d/%u busy (%d unsent), ready %d", c->mshr_busy, c->p.mshrs, c->missq_n,
                     c->ready_n);
    if (oldest >= 0 && n >= 0 && (size_t)n < len)
        snprintf(buf + n, len - (size_t)n, ", oldest miss 0x%llx waiting %lld cycles",
                 (unsigned long long)addr_of(c, c->m[oldest].line), (long long)(now - c->m[oldest].since));
}

int cache_core_copy_contents(cache_core *c, const cache_core *src)
{
    if (c->nsets != src->nsets || c->p.ways != src->p.ways || c->p.line_bytes != src->p.line_bytes ||
        c->p.banks != src->p.banks || c->index != src->index)
        return -1;
    size_t nways = (size_t)c->nsets * c->p.ways;
    memcpy(c->tag, src->tag, nways * sizeof *c->tag);
    memcpy(c->stamp, src->stamp, nways * sizeof *c->stamp);
    c->clock = src->clock;
    return 0;
}
