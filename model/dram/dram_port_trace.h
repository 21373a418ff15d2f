/* dram_port_trace.h — runs a request trace through the kernel module (dram_port.h)
 * on a fresh simulation, the kernel-path twin of dram_trace_run (dram_trace.h):
 * a producer offers the trace lines in order, one burst-sized request each (32 B
 * for LPDDR3 x32), through a request FIFO it keeps full; a consumer drains the
 * response FIFO; at the end of the file the producer calls dram_port_input_done().
 * Contract: same trace format and errors as dram_trace_run (name:line), and the same
 * results — command stream, cycles, statistics — at the kernel's cost (tests:
 * tb_dram_port, tb_dram_cli.sh, tb_dram_ref.sh). rtdram --kernel uses it. Returns
 * 0, 1 (the kernel run did not finish the trace), 2 (bad trace, err names
 * file:line) or 3 (interrupted, kernel/interrupt.h: sum holds the run so far). */
#ifndef RTSIM_DRAM_PORT_TRACE_H
#define RTSIM_DRAM_PORT_TRACE_H

#include <stddef.h>
#include <stdio.h>

#include "model/dram/dram_ctrl.h"
#include "model/dram/dram_energy.h"
#include "model/dram/dram_report.h"
#include "model/dram/dram_timing.h"
#include "model/dram/dram_trace.h"

/* sink (may be NULL) sees every command; exhaustive selects the controller's and
 * the DRAM clock's reference modes. On success fills res and sum (energy with
 * power, required) and returns 0; 2 on malformed input, 1 if the simulation did not finish
 * (message in err). */
int dram_port_trace_run(const dram_spec *spec, const dram_power_spec *power, FILE *f, const char *name,
                        dram_cmd_fn sink, void *sink_user, int exhaustive, dram_trace_result *res,
                        dram_summary *sum, char *err, size_t errlen);

#endif
