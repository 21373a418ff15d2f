/* mem_dram_adapter.h — connects the memory side (mem_req / mem_resp, the
 * accelerator clock) to the LPDDR3 port (dram_port_req / dram_port_resp, the
 * DRAM clock, model/dram/dram_port.h): the memory controller's front end.
 *
 * Contract (one clocked process on the accelerator clock):
 *  - Each cycle it forwards at most one request from mem_in to dram_req (the
 *    port splits it into 32 B bursts) while fewer than max_outstanding are in
 *    flight, remembering the request's src and tag in a slot whose index is
 *    the DRAM tag; and at most one response from dram_resp to mem_out, with
 *    the original addr, bytes, src and tag restored. Responses may come back
 *    out of order (FR-FCFS); each is routed by its slot.
 *  - Clock crossing (500 MHz <-> 800 MHz) happens in the kernel FIFOs: items
 *    are time-stamped, each side reads them at its own next edge.
 * Statistics: PREFIX.requests, .bytes, .latency_sum (accelerator cycles from
 * forwarding to response). */
#ifndef RTSIM_MODEL_MEM_DRAM_ADAPTER_H
#define RTSIM_MODEL_MEM_DRAM_ADAPTER_H

#include <stddef.h>
#include <stdint.h>

#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/module_desc.h"
#include "kernel/stats.h"
#include "model/mem/mem_msg.h"

typedef struct mem_dram_adapter mem_dram_adapter;

extern const ks_module_desc mem_dram_adapter_module_desc;

/* Lifecycle: create, connect, register, destroy (docs/design.md). */
mem_dram_adapter *mem_dram_adapter_create(ks_sim *sim, ks_clock *clk, const char *name, uint32_t max_outstanding,
                                          char *err, size_t errlen);
/* mem_in/mem_out: fifo<mem_req>/fifo<mem_resp> of the memory side;
 * dram_req/dram_resp: fifo<dram_port_req>/fifo<dram_port_resp> of the port
 * (item sizes asserted). */
void mem_dram_adapter_connect(mem_dram_adapter *a, ks_fifo *mem_in, ks_fifo *mem_out, ks_fifo *dram_req,
                              ks_fifo *dram_resp);
void mem_dram_adapter_destroy(mem_dram_adapter *a);
int mem_dram_adapter_register(mem_dram_adapter *a, ks_stats *reg, const char *prefix);
uint64_t mem_dram_adapter_requests(const mem_dram_adapter *a);
uint64_t mem_dram_adapter_bytes(const mem_dram_adapter *a);
uint64_t mem_dram_adapter_latency_sum(const mem_dram_adapter *a);
uint32_t mem_dram_adapter_outstanding(const mem_dram_adapter *a);

#endif
