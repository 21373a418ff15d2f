/* mem_arbiter.h — round-robin arbiter of N mem_req FIFOs onto one, routing
 * the mem_resp stream back to the requester's FIFO.
 *
 * Contract (one clocked process):
 *  - Each cycle at most one request is granted: the first readable input at
 *    or after the one following the last grant (round robin), and only when
 *    req_out has room. The request leaves with src = src_in * N + input, so
 *    arbiters compose (the response path peels one level: input = src mod N,
 *    src_out = src / N); N * (largest src) must stay below 65536.
 *  - Each cycle at most one response is routed from resp_in to resp_out[src
 *    mod N]; a full output stalls the response stream (in order, like a bus).
 * Statistics: PREFIX.grants, PREFIX.grants_<i>, PREFIX.conflict_cycles
 * (cycles with more than one requester ready), PREFIX.responses; per input
 * the bytes requested and, from a bitmap of the 32-byte granules every
 * granted request covered, first-touch requests (compulsory misses of the
 * requester), refetches (capacity and conflict misses) and the footprint
 * (distinct bytes): PREFIX.bytes_<i>, first_touch_<i>, refetches_<i>,
 * footprint_bytes_<i>. At the memory arbiter, input 0 is the node L2 and
 * input 1 the primitive cache, so these split DRAM traffic by kind. */
#ifndef RTSIM_MODEL_MEM_ARBITER_H
#define RTSIM_MODEL_MEM_ARBITER_H

#include <stddef.h>
#include <stdint.h>

#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/module_desc.h"
#include "kernel/stats.h"
#include "model/mem/mem_msg.h"

typedef struct mem_arbiter mem_arbiter;

extern const ks_module_desc mem_arbiter_module_desc;

/* Lifecycle: create, connect, register, destroy (docs/design.md). n: the
 * requesters (1..256). */
mem_arbiter *mem_arbiter_create(ks_sim *sim, ks_clock *clk, const char *name, int n, char *err, size_t errlen);
/* req_in[i] / resp_out[i]: per requester (resp_out[i] may be NULL for a
 * requester that never gets responses); req_out / resp_in: the shared side. */
void mem_arbiter_connect(mem_arbiter *a, ks_fifo *const *req_in, ks_fifo *const *resp_out, ks_fifo *req_out,
                         ks_fifo *resp_in);
void mem_arbiter_destroy(mem_arbiter *a);
int mem_arbiter_register(mem_arbiter *a, ks_stats *reg, const char *prefix);
uint64_t mem_arbiter_grants(const mem_arbiter *a, int input);
/* The per-input statistics of input i (0 .. n-1), as registered:
 * bytes_<i>, footprint_bytes_<i>, first_touch_<i>, refetches_<i>. */
typedef struct mem_arbiter_input_stats {
    uint64_t bytes, footprint_bytes, first_touch, refetches;
} mem_arbiter_input_stats;
void mem_arbiter_input(const mem_arbiter *a, int input, mem_arbiter_input_stats *out);
int mem_arbiter_busy(const mem_arbiter *a);
void mem_arbiter_describe(const mem_arbiter *a, char *buf, size_t len);

#endif
