/* cache_core.h — one generic cache model: non-blocking, set-associative, true LRU,
 * miss status holding registers (MSHRs) with merging, configurable line size,
 * ports and banks. It models tags and timing only: data always comes from the
 * memory image (the model is execution-driven on the image's bytes), so a hit
 * means "the bytes may be used this cycle".
 *
 * Instances (paper sec. 3; docs/design.md "Hardware defaults"): per-TRV
 * node L1 (16 KB), shared node L2 (128 KB), primitive cache (128 KB, two
 * banks interleaved by 64 B line, so an unaligned 48 B triangle touching two lines is served in one
 * cycle when the lines sit in different banks). All 4-way by default.
 *
 * Protocol (synchronous probe, asynchronous fill — "looping for next chance"):
 *  - cache_core_access(c, addr, bytes, now) checks every line the access touches:
 *    CACHE_HIT when all are present (LRU updated); otherwise each missing line
 *    gets an MSHR (or merges into the MSHR already waiting for it) and a
 *    mem_req is queued on the miss port; the result says MISS (requester
 *    retries later) or BLOCKED (no MSHR / port slot / bank free this cycle:
 *    nothing changed, retry later). Accesses beyond the port count per cycle
 *    are BLOCKED too; each bank reads `ports` lines per cycle (bank = line
 *    number mod banks), an access needing more lines of one bank holds it
 *    for ceil(k / ports) cycles (cache_core_last_access_cycles).
 *  - The cache's kernel process sends queued misses downstream and installs
 *    returning fills (evicting the LRU way), freeing their MSHRs; a line is
 *    present from the cycle its fill is installed.
 *  - A cache can itself serve as the next level of others: the cache module (cache.h, the
 *    kernel module around this core) takes mem_req from upstream FIFOs,
 *    answers hits after its hit latency and misses after the fill.
 * Statistics (cache_stats): accesses, hits, misses, MSHR allocations,
 * merged lines, blocked by cause, bank conflicts, fills, evictions; the
 * kernel module registers them with units/descriptions (cache.h). */
#ifndef RTSIM_MODEL_CACHE_H
#define RTSIM_MODEL_CACHE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "model/mem/mem_msg.h"

/* An access touches at most this many lines (more is a programming error:
 * the configuration check, memsys_config.c, refuses machines whose node or
 * triangle reads could). */
#define CACHE_MAX_LINES_PER_ACCESS 8

typedef struct cache_params {
    uint32_t size_bytes;    /* capacity, power of two */
    uint32_t line_bytes;    /* power of two, >= 16 (index-addressed: any multiple of 16) */
    uint32_t ways;          /* >= 1; sets = size / (line * ways) must be a power of two */
    uint32_t banks;         /* 1 or a power of two; line-interleaved */
    uint32_t ports;         /* accesses accepted per cycle */
    uint32_t mshrs;         /* outstanding missing lines */
    uint32_t mshr_merge;    /* requesters that may wait on one MSHR */
    uint32_t hit_latency;   /* cycles from access to data (for the cache module, cache.h) */
    /* 0: byte-addressed (above). 1: index-addressed (paper sec. 3.1, the node
     * caches' alternative for nodes that are not a power of two): a line is
     * one word of line_bytes (a node, N x 32 B), its number is addr /
     * line_bytes (the node index), and a bank holds
     * sets = floor(size / (line * ways * banks)) >= 1 sets, any whole number,
     * set = (word / banks) mod sets; capacity used = sets * ways * banks *
     * line <= size (cache_core_capacity_bytes). */
    uint32_t index_addressed;
} cache_params;

typedef enum cache_result { CACHE_HIT, CACHE_MISS, CACHE_BLOCKED } cache_result;

typedef struct cache_core cache_core;   /* the tag/LRU/MSHR core; see cache.c */

/* Counters since creation. An access is one cache_core_access or cache_core_request
 * call that was not BLOCKED; it is a hit when every line it touches was
 * present, else a miss. */
typedef struct cache_stats {
    uint64_t accesses, hits, misses;
    uint64_t miss_lines;      /* MSHRs allocated = line requests sent downstream */
    uint64_t merged;          /* missing lines that joined an MSHR already waiting */
    uint64_t blocked_mshr;    /* BLOCKED: no free MSHR for a missing line */
    uint64_t blocked_merge;   /* BLOCKED: the MSHR already has mshr_merge waiters */
    uint64_t blocked_port;    /* BLOCKED: all ports used this cycle */
    uint64_t blocked_bank;    /* BLOCKED: a bank it needs is busy this cycle */
    uint64_t bank_conflicts;  /* accesses whose lines share a bank (take extra cycles) */
    uint64_t fills, evictions;
    uint64_t bytes_filled;    /* line bytes installed */
} cache_stats;

/* The geometry rules, written once: 0, or -1 with a message naming
 * SECTION.key and the allowed values (the configuration check of
 * model/mem/memsys_config.c calls it with the section, cache_core_create
 * with "cache"). */
int cache_core_check_params(const cache_params *p, const char *section, char *err, size_t errlen);
/* NULL with a message in err when the parameters are impossible. */
cache_core *cache_core_create(const cache_params *p, char *err, size_t errlen);
void cache_core_destroy(cache_core *c);
const cache_params *cache_core_get_params(const cache_core *c);
/* Bytes the data array holds: size_bytes, or for an index-addressed cache
 * sets * ways * banks * line_bytes (<= size_bytes). */
uint64_t cache_core_capacity_bytes(const cache_params *p);

/* Probe [addr, addr+bytes) for a requester that retries on a miss (TRV node
 * L1, IST primitive cache). Missing lines get an MSHR (or merge into one; a
 * probe records no waiter, so merging is not limited). All-or-nothing: when
 * BLOCKED nothing changed; the exception is a probe needing more new lines
 * than the cache has MSHRs at all, which could never be accepted: it gets
 * the free MSHRs for its first missing lines (MISS) and retries for the
 * rest. Present lines of an accepted access become MRU.
 * `now` is the cycle (non-decreasing); ports and banks are per cycle. */
cache_result cache_core_access(cache_core *c, uint64_t addr, uint32_t bytes, int64_t now);
/* cache_core_access for a unit's synchronous probe port (the accel_probe_fn shape of
 * accel_ray.h, ctx = the cache): on a hit *cycles gets cache_core_last_access_cycles.
 * One call per probe on the hottest path of the model. */
cache_result cache_core_probe(void *ctx, uint64_t addr, uint32_t bytes, uint64_t now, uint32_t *cycles);
/* Cycles the last accepted access occupied its busiest bank. Each bank reads
 * `ports` lines per cycle, so this is 1, or ceil(k / ports) when k of its
 * lines share a bank (e.g. an unaligned 48 B read over two lines of a one-bank
 * one-port cache: 2); the bank is then busy for those cycles and a requester
 * should add cycles - 1 to its hit latency. */
uint32_t cache_core_last_access_cycles(const cache_core *c);

/* Request from an upstream cache (the cache module, cache.h): like cache_core_access, but a miss
 * records the request as a waiter on each missing line's MSHR (at most
 * mshr_merge per MSHR, else BLOCKED); once all its lines are filled it comes
 * back, unchanged, from cache_core_pop_ready. Caches are read-only: is_write is
 * not modeled (the BVH and triangles are never written). */
cache_result cache_core_request(cache_core *c, const mem_req *req, int64_t now);

/* Downstream requests, in MSHR allocation order: addr = line address,
 * bytes = line_bytes, tag = MSHR index, src = 0 (arbiters rewrite it). */
bool cache_core_peek_miss(const cache_core *c, mem_req *out);
bool cache_core_pop_miss(cache_core *c, mem_req *out);
/* Installs the line of a response to one of our requests (matched by tag and
 * addr), evicting the set's LRU line if needed; frees the MSHR. Returns the
 * number of waiters that became ready, or -1 if resp matches no MSHR. */
int cache_core_fill(cache_core *c, const mem_resp *resp, int64_t now);
/* The functional levels' access (fidelity/functional.h: no timing, every
 * miss filled at once): what cache_core_access and a cache_core_fill of each
 * queued miss do to an idle cache, without its ports, banks and MSHRs.
 * Present lines become MRU; the missing ones are installed in order (at
 * most `mshrs` of them, as many as an idle cache's MSHRs take), each
 * evicting its set's LRU line. The same contents and the same counts
 * (accesses, hits, misses, miss_lines, fills, evictions, bytes_filled) as
 * that sequence; the miss hook is not called. missed: the installed lines'
 * first bytes, for the next level. Returns how many (0: a hit). */
int cache_core_touch(cache_core *c, uint64_t addr, uint32_t bytes, uint64_t missed[CACHE_MAX_LINES_PER_ACCESS]);
/* Waiting requests whose lines are all present now, in completion order. */
bool cache_core_pop_ready(cache_core *c, mem_req *out);

/* Called whenever an access allocates an MSHR (a downstream request was
 * queued): the kernel module wakes its process with it, so requesters may
 * probe the core directly. One hook per cache; NULL removes it. */
typedef void (*cache_core_miss_hook)(void *user);
void cache_core_set_miss_hook(cache_core *c, cache_core_miss_hook fn, void *user);

/* Introspection (tests, deadlock reports, statistics). */
/* Functional warming (fidelity/windowed.c): src's contents (tags and LRU
 * order) copied into c, a core of the same geometry whose MSHRs are idle;
 * c's statistics, MSHRs and port and bank timing stay its own. 0, or -1
 * when the geometries differ. */
int cache_core_copy_contents(cache_core *c, const cache_core *src);
/* The bytes a core of these parameters takes (cache_core_create's
 * allocations): what a copy of one costs (fidelity/windowed.c). */
size_t cache_core_bytes(const cache_params *p);
bool cache_core_contains(const cache_core *c, uint64_t addr);        /* no side effects */
/* Every line of [addr, addr+bytes) present (ctx = the cache; no side
 * effects: no LRU update, no statistics). */
bool cache_core_present(void *ctx, uint64_t addr, uint32_t bytes);
bool cache_core_line_pending(const cache_core *c, uint64_t addr);    /* an MSHR waits for it */
int cache_core_mshrs_busy(const cache_core *c);
int cache_core_misses_queued(const cache_core *c);                   /* not yet popped */
int cache_core_ready_count(const cache_core *c);
void cache_core_get_stats(const cache_core *c, cache_stats *out);
/* The live counters (for registering them in a statistics registry). */
const cache_stats *cache_core_stats_live(const cache_core *c);
/* One line: "mshrs 3/8 busy (2 unsent), ready 1, oldest miss 0x1c0 since 123". */
void cache_core_describe(const cache_core *c, int64_t now, char *buf, size_t len);

#endif
