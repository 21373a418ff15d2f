/* cache.h — the kernel module around one cache core (model/mem/cache_core.h).
 *
 * Contract (one clocked process on the accelerator clock):
 *  - Requesters either probe the core directly (cache_core_access on
 *    cache_get_core(): node L1 from its TRV, primitive cache from the IST;
 *    "looping for next chance", no response) or send mem_req on req_in
 *    (next-level use: the node L2 behind the L1 arbiter); both may coexist.
 *  - Each cycle, in this order: install at most one fill from fill_in
 *    (mem_resp answering our own miss requests); read up to `ports` requests
 *    from req_in (head first; a BLOCKED head waits); send at most one queued
 *    miss to miss_out (mem_req, one line); send up to `ports` responses to
 *    resp_out. A response (mem_resp with the request's addr, bytes, src, tag)
 *    leaves hit_latency cycles after a hit, or hit_latency cycles after the
 *    fill that completed a waiting request.
 *  - ev_filled is notified (delta) after every installed fill, so probing
 *    requesters may sleep until their line may have arrived.
 *  - Idle skipping: the process sleeps when it can do nothing; it wakes on
 *    its FIFOs' events, on a miss allocated by a direct probe (the core's miss
 *    hook) and at the ready cycle of its oldest pending response.
 * Statistics: the core's counters as PREFIX.* plus PREFIX.hit_rate (hits /
 * accesses, where every retry of a looping ray is an access) and
 * PREFIX.line_hit_rate (hits / (hits + miss_lines), each missing line once);
 * see cache_module_desc. Deterministic. */
#ifndef RTSIM_MODEL_CACHE_UNIT_H
#define RTSIM_MODEL_CACHE_UNIT_H

#include <stddef.h>

#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/module_desc.h"
#include "kernel/sim.h"
#include "kernel/stats.h"
#include "model/mem/cache_core.h"

typedef struct cache_unit cache_unit;

extern const ks_module_desc cache_module_desc;

/* NULL with a message when the parameters are impossible. */
cache_unit *cache_create(ks_sim *sim, ks_clock *clk, const char *name, const cache_params *p, char *err,
                              size_t errlen);
void cache_destroy(cache_unit *u);
/* Channels (fifo<mem_req> / fifo<mem_resp>); req_in/resp_out may be NULL for
 * a probe-only cache. Call before the run. */
void cache_connect(cache_unit *u, ks_fifo *miss_out, ks_fifo *fill_in, ks_fifo *req_in, ks_fifo *resp_out);

cache_core *cache_get_core(cache_unit *u);
const char *cache_name(const cache_unit *u);
ks_event *cache_ev_filled(cache_unit *u);
ks_clocked *cache_process(cache_unit *u);

/* Registers PREFIX.accesses, .hits, ... and PREFIX.hit_rate; 0 or -1. */
int cache_register(cache_unit *u, ks_stats *reg, const char *prefix);

/* Work still held (MSHRs busy, responses or ready waiters pending). */
int cache_busy(const cache_unit *u);
void cache_describe(const cache_unit *u, char *buf, size_t len);

#endif
