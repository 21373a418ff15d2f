/* cache.h — one generic cache model: non-blocking, set-associative, true LRU,
 * miss status holding registers (MSHRs) with merging, configurable line size,
 * ports and banks. It models tags and timing only: data always comes from the
 * memory image (the model is execution-driven on the image's bytes), so a hit
 * means "the bytes may be used this cycle".
 *
 * Instances (paper sec. 3, SPEC "Caches"): per-TRV node L1 (16 KB), shared
 * node L2 (128 KB), primitive cache (128 KB, two banks interleaved by 64 B
 * line, so an unaligned 48 B triangle touching two lines is served in one
 * cycle when the lines sit in different banks). All 4-way by default.
 *
 * Protocol (synchronous probe, asynchronous fill — "looping for next chance"):
 *  - cache_access(c, addr, bytes, now) checks every line the access touches:
 *    CACHE_HIT when all are present (LRU updated); otherwise each missing line
 *    gets an MSHR (or merges into the MSHR already waiting for it) and a
 *    mem_req is queued on the miss port; the result says MISS (requester
 *    retries later) or BLOCKED (no MSHR / port slot / bank free this cycle:
 *    nothing changed, retry later). Accesses beyond the port count per cycle
 *    are BLOCKED too.
 *  - The cache's kernel process sends queued misses downstream and installs
 *    returning fills (evicting the LRU way), freeing their MSHRs; a line is
 *    present from the cycle its fill is installed.
 *  - A cache can itself serve as the next level of others: cache_unit (the
 *    kernel module around this core) takes mem_req from upstream FIFOs,
 *    answers hits after its hit latency and misses after the fill.
 * Statistics: accesses, hits, misses, merged misses, blocked, fills,
 * evictions, per-bank conflicts; all registered with units/descriptions. */
#ifndef RTSIM_MODEL_CACHE_H
#define RTSIM_MODEL_CACHE_H

#include <stdbool.h>
#include <stdint.h>

typedef struct cache_params {
    uint32_t size_bytes;    /* capacity, power of two */
    uint32_t line_bytes;    /* power of two, >= 16 */
    uint32_t ways;          /* >= 1; sets = size / (line * ways) must be a power of two */
    uint32_t banks;         /* 1 or a power of two; line-interleaved */
    uint32_t ports;         /* accesses accepted per cycle */
    uint32_t mshrs;         /* outstanding missing lines */
    uint32_t mshr_merge;    /* requesters that may wait on one MSHR */
    uint32_t hit_latency;   /* cycles from access to data (for cache_unit) */
} cache_params;

typedef enum cache_result { CACHE_HIT, CACHE_MISS, CACHE_BLOCKED } cache_result;

typedef struct cache cache;   /* the tag/LRU/MSHR core; see cache.c */

#endif
