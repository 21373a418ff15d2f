/* fixed_mem.h — fixed-latency main memory with a peak-bandwidth limit: the
 * cheap fidelity option for the memory (docs/design.md "What rtsim is":
 * cheaper fidelities) and the default until the LPDDR3 port is selected.
 *
 * Contract (one clocked process on the accelerator clock):
 *  - Accepts at most one mem_req per cycle from req_in while fewer than
 *    max_outstanding requests are in flight. Its data transfer occupies a
 *    shared data bus for bytes / bytes_per_cycle cycles (fractional, carried
 *    exactly in 1/65536-cycle units; bytes_per_cycle 0 = unlimited), starting
 *    when the bus is free; the response (addr, bytes, src, tag of the request)
 *    becomes ready `latency` cycles after the transfer ends and is written to
 *    resp_out in request order (one per cycle, waiting while it is full).
 *  - No row buffers, banks or refresh: under saturation it errs (that is the
 *    accuracy cost the speed/accuracy chart reports).
 * Statistics: PREFIX.requests, .bytes, .latency_sum (cycles, request accepted
 * to response written), .bus_busy_cycles. */
#ifndef RTSIM_MODEL_FIXED_MEM_H
#define RTSIM_MODEL_FIXED_MEM_H

#include <stddef.h>
#include <stdint.h>

#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/module_desc.h"
#include "kernel/stats.h"
#include "model/mem/mem_msg.h"

typedef struct fixed_mem fixed_mem;

extern const ks_module_desc fixed_mem_module_desc;

/* Lifecycle: create, connect, register, destroy (docs/design.md). */
fixed_mem *fixed_mem_create(ks_sim *sim, ks_clock *clk, const char *name, uint32_t latency, double bytes_per_cycle,
                            uint32_t max_outstanding, char *err, size_t errlen);
/* req_in: fifo<mem_req>; resp_out: fifo<mem_resp>. */
void fixed_mem_connect(fixed_mem *m, ks_fifo *req_in, ks_fifo *resp_out);
void fixed_mem_destroy(fixed_mem *m);
int fixed_mem_register(fixed_mem *m, ks_stats *reg, const char *prefix);
uint64_t fixed_mem_requests(const fixed_mem *m);
uint64_t fixed_mem_bytes(const fixed_mem *m);
uint64_t fixed_mem_latency_sum(const fixed_mem *m);
int fixed_mem_busy(const fixed_mem *m);
void fixed_mem_describe(const fixed_mem *m, char *buf, size_t len);

#endif
