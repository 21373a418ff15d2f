/* dram_port.h — the LPDDR3 memory as a kernel module: dram_ctrl behind timed FIFOs.
 *
 * Contract:
 *  - Ports: a request FIFO in (items dram_port_req) and a response FIFO out
 *    (items dram_port_resp), both created by the caller (any capacity, latency
 *    and clock) and checked for their item size. One response per request,
 *    writes included (acknowledged when their last WR command issues).
 *  - A request of `size` bytes covers the bursts (spec tx_bytes each, 32 B for
 *    LPDDR3 x32 BL8) overlapping [addr, addr+size); they enter the controller
 *    in address order, at most one burst per DRAM cycle, and the response
 *    leaves when the last one completes. size 0 counts as one burst.
 *  - Clock: the port creates the DRAM clock (period = the spec's tck_ps, 1250 ps
 *    for LPDDR3-1600); DRAM cycle k of the controller is kernel cycle k of that
 *    clock. Each edge: catch the controller up to the cycle, deliver finished
 *    responses, offer the head request's next burst (Ramulator's injection:
 *    a rejected burst is retried, in order).
 *  - Back-pressure: a full controller queue leaves the request in the request
 *    FIFO (the producer sees it full); a full response FIFO holds finished
 *    responses in the port and stops accepting requests until it drains.
 *  - Idle costs nothing: the process sleeps until the controller's next event
 *    (dram_next_event), a request FIFO write or a response FIFO read, and the
 *    controller catches up lazily (dram_advance_to), so with FIFOs that never
 *    block, latencies and command streams equal the standalone driver's on the
 *    same request sequence (tests: testbench/model/dram/tb_dram_port.c).
 *  - Statistics are registered under "<name>." with units and descriptions
 *    (dram_port_module_desc lists them); controller-derived ones (commands, row hits,
 *    energy) are formulas that first catch the controller up to the sim time.
 * Deterministic; no host state. */
#ifndef RTSIM_DRAM_PORT_H
#define RTSIM_DRAM_PORT_H

#include <stddef.h>
#include <stdint.h>

#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/module_desc.h"
#include "kernel/sim.h"
#include "kernel/stats.h"
#include "model/dram/dram_ctrl.h"
#include "model/dram/dram_energy.h"
#include "model/dram/dram_timing.h"

typedef struct dram_port_req {
    uint64_t addr;     /* byte address */
    uint64_t tag;      /* returned unchanged in the response */
    uint32_t size;     /* bytes (e.g. a 64 B cache line = 2 bursts) */
    uint8_t is_write;
} dram_port_req;

typedef struct dram_port_resp {
    uint64_t addr, tag;
    uint32_t size;
    uint8_t is_write;
    uint32_t bursts;           /* DRAM bursts the request took */
    int64_t accept_cycle;      /* DRAM cycle its first burst entered the controller */
    int64_t done_cycle;        /* DRAM cycle its last burst completed (= when the response was ready) */
} dram_port_resp;

typedef struct dram_port dram_port;

/* Creates the module "name" on sim: its DRAM clock and clocked process. spec (and
 * power, which may be NULL: no energy statistic) must outlive the sim; stats may
 * be NULL. Returns NULL with a message in err on a bad FIFO item size, a
 * duplicate statistic name or a bad spec. */
dram_port *dram_port_create(ks_sim *sim, const char *name, const dram_spec *spec, const dram_power_spec *power,
                            ks_fifo *req_in, ks_fifo *resp_out, ks_stats *stats, char *err, size_t errlen);
/* Frees what the sim does not own (controller, bookkeeping); call before or after
 * ks_sim_destroy. */
void dram_port_destroy(dram_port *p);

ks_clock *dram_port_clock(const dram_port *p);
/* The controller (for inspection; catch it up with dram_port_sync first). */
dram_ctrl *dram_port_ctrl(const dram_port *p);
/* Catches the controller up to the current sim time (bit-identical), or to
 * the end time set with dram_port_set_stats_end when that is earlier. */
void dram_port_sync(dram_port *p);
/* The time the statistics end at (e.g. the accelerator's frame end): the
 * controller is caught up no further than its DRAM cycle when statistics are
 * read, so they do not depend on how long the simulation went on idling
 * (with --exhaustive the DRAM clock may tick once more after the frame). */
void dram_port_set_stats_end(dram_port *p, ks_time t);
/* Row hits / (hits + misses + conflicts) over every channel so far, 0
 * before any row access (the statistic row_hit_rate). */
double dram_port_row_hit_rate(dram_port *p);
/* The DRAM energy so far, DRAMPower method, in uJ: *total, and the part of
 * it spent in active and precharge standby, *background (the statistics
 * energy_uJ and background_energy_uJ). Only with a power spec. Both catch
 * the controller up first, as dram_port_sync. */
void dram_port_energy_uJ(dram_port *p, double *total, double *background);
/* Forwards every issued command (e.g. to a timing checker), in issue order. */
void dram_port_set_cmd_sink(dram_port *p, dram_cmd_fn fn, void *user);
/* The producer will send no more requests: once the request FIFO is empty, queued
 * writes drain (write-high watermark 0), as Ramulator's trace mode does at the end
 * of a trace. */
void dram_port_input_done(dram_port *p);
/* Requests accepted but not yet answered (including responses held by back-pressure). */
uint64_t dram_port_outstanding(const dram_port *p);

/* Parameters, ports and statistics of the module. */
extern const ks_module_desc dram_port_module_desc;

#endif
