/* interrupt.h — Ctrl-C (SIGINT) and SIGTERM for the tools: a run stops
 * cleanly instead of dying mid-write.
 *
 * Contract:
 *  - ks_interrupt_install(tool) installs the handlers (tool names the
 *    program in its message).
 *  - While the tool is in a polling phase (ks_interrupt_polling(true): a
 *    loop that calls ks_interrupted() at least every ~0.1 s), the handler
 *    only records the signal; the loop stops, the tool finishes its outputs
 *    as partial (VCD up to the last complete time step, statistics marked
 *    "partial"), says so on stderr and exits ks_interrupt_exit_status().
 *  - Outside a polling phase (loading a scene, building a BVH: nothing
 *    written yet), or on a second signal, the handler removes the output
 *    layer's temporary files (out_file.h), prints "TOOL: interrupted by SIG;
 *    temporary files removed" and exits 128 + the signal number at once.
 *  - ks_interrupted() is a plain load of a volatile flag (0 or the signal):
 *    cheap enough for any loop. */
#ifndef KS_INTERRUPT_H
#define KS_INTERRUPT_H

#include <signal.h>
#include <stdbool.h>

extern volatile sig_atomic_t ks__interrupt_signal;

void ks_interrupt_install(const char *tool);
/* Enters (true) or leaves a polling phase; returns the previous state. */
bool ks_interrupt_polling(bool on);
static inline int ks_interrupted(void) { return ks__interrupt_signal; }
/* "SIGINT" or "SIGTERM" (or "signal"). */
const char *ks_interrupt_name(int sig);
/* 128 + the signal received (130 for SIGINT, 143 for SIGTERM). */
int ks_interrupt_exit_status(void);

#endif
