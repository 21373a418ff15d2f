/* signal.h — signals with request-update semantics (SystemC sc_signal).
 *
 * Contract: a signal holds an unsigned value of 1..64 bits. ks_signal_write
 * requests an update; the new value becomes visible (ks_signal_read) only
 * after the update phase of the current delta cycle, and if it differs from
 * the old one the value-changed event is delta-notified (so processes see it
 * in the next delta, never in the same one). Several writes in one delta:
 * the last wins. When a VCD writer is open the signal is traced under its
 * name (1 bit -> wire, wider -> integer). Signals are owned by the sim. */
#ifndef KS_SIGNAL_H
#define KS_SIGNAL_H

#include <stdint.h>

#include "kernel/event.h"
#include "kernel/sim.h"

typedef struct ks_signal ks_signal;

ks_signal *ks_signal_create(ks_sim *sim, const char *name, unsigned width, uint64_t init);
uint64_t ks_signal_read(const ks_signal *s);
void ks_signal_write(ks_signal *s, uint64_t value);
ks_event *ks_signal_ev_changed(ks_signal *s);
const char *ks_signal_name(const ks_signal *s);
unsigned ks_signal_width(const ks_signal *s);

#endif
