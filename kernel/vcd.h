/* vcd.h — Value Change Dump writer (IEEE 1364 §18 VCD, opened by GTKWave).
 *
 * Contract:
 *  - ks_vcd_open(sim, path, timescale, window_begin, window_end, filter)
 *    attaches a writer to the sim. timescale is "1ps", "10ps", "1ns", ...;
 *    only changes at times in [window_begin, window_end) are written (the
 *    values at window_begin are dumped in full with $dumpvars); filter is a
 *    comma-separated list of glob patterns ('*', '?') matched against full
 *    dotted variable names (NULL or "" = everything). Variables the filter
 *    rejects get a NULL handle; every setter accepts NULL and does nothing.
 *  - Variable names are dotted paths: "top.trv0.state" is variable "state"
 *    in scope top -> trv0 ($scope module per path element).
 *  - Kinds: bit (wire 1), integer of 1..64 bits (reg, written in binary
 *    without leading zeros), enumerated (a GTKWave string variable holding
 *    the name of the value, set by index).
 *  - Change-only: setting the value a variable already has writes nothing.
 *  - All variables must be declared before the first value is written
 *    (the header is emitted then); later declarations return NULL.
 *  - While open, every FIFO and signal of the sim (existing or created
 *    later, before the header) is traced automatically.
 *  - Output is formatted by hand into one large buffer and written through
 *    the output layer (out_file.h): the plan a tool made for path before the
 *    run, else one made here; a regular file is written to a temporary name
 *    and renamed by ks_vcd_close, stdout, devices and pipes are written in
 *    place. ks_vcd_close returns 0, or -1 on an I/O error (message in
 *    ks_sim_error). ks_sim_destroy closes a writer still open. A writer
 *    closed early (an interrupted run) ends at the last complete time step. */
#ifndef KS_VCD_H
#define KS_VCD_H

#include <stdint.h>

#include "kernel/sim.h"
#include "kernel/time.h"

typedef struct ks_vcd ks_vcd;
typedef struct ks_vcd_var ks_vcd_var;

/* NULL on error (bad timescale, file cannot be created; see ks_sim_error). */
ks_vcd *ks_vcd_open(ks_sim *sim, const char *path, const char *timescale, ks_time window_begin,
                    ks_time window_end, const char *filter);
int ks_vcd_close(ks_vcd *vcd);
/* Closes without keeping the file (a run that never started): the
 * temporary is removed; an in-place output keeps what was written. */
void ks_vcd_discard(ks_vcd *vcd);
/* The writer open on a sim, or NULL. */
ks_vcd *ks_sim_vcd(const ks_sim *sim);

ks_vcd_var *ks_vcd_var_bit(ks_vcd *vcd, const char *name, int init);
ks_vcd_var *ks_vcd_var_int(ks_vcd *vcd, const char *name, unsigned width, uint64_t init);
/* names[0..n-1] are the value names (not copied: must stay valid). */
ks_vcd_var *ks_vcd_var_enum(ks_vcd *vcd, const char *name, const char *const *names, unsigned n,
                            unsigned init);

/* Sets the value at the sim's current time (bit: 0/1; int: masked to the
 * width; enum: index < n). */
/* ---- private: layout prefixes for the inline fast path of ks_vcd_set ---- */
struct ks__vcd_head {
    const ks_time *now;
    ks_time cur_t;             /* time of the changes in the dirty list */
    ks_vcd_var **dirty;        /* variables changed at cur_t ... */
    ks_vcd_var **dirty_end;    /* ... up to here */
    unsigned cap_dirty;
    uint8_t header_done;
};
struct ks__vcd_var_head {
    struct ks__vcd_head *vcd;
    uint64_t value, mask;
    ks_time stamp;             /* time of its dirty-list entry (-1: none) */
};
void ks__vcd_set(ks_vcd_var *var, uint64_t value);
static inline void ks_vcd_set(ks_vcd_var *var, uint64_t value)
{
    if (!var)
        return;
    struct ks__vcd_var_head *h = (struct ks__vcd_var_head *)var;
    value &= h->mask;
    if (value == h->value)
        return;
    struct ks__vcd_head *d = h->vcd;
    /* a change at the current time stamp: record it (the final value of
     * the time stamp is written when time moves on). cur_t is -1 until the
     * header is written, and the dirty list then has room for every
     * variable. */
    if (*d->now == d->cur_t) {
        h->value = value;
        if (h->stamp != d->cur_t) {
            h->stamp = d->cur_t;
            *d->dirty_end++ = var;
        }
        return;
    }
    ks__vcd_set(var, value);
}
/* Sampled variables (a FIFO's occupancy): the value is read from the
 * traced location when the time stamp is written out, so the owner only
 * lists the variable once per time stamp (it keeps track of that), before
 * its first change there. */
void ks__vcd_list_slow(ks_vcd_var *var, ks_time now);
static inline void ks__vcd_list(ks_vcd_var *var, ks_time now)
{
    struct ks__vcd_head *d = ((struct ks__vcd_var_head *)var)->vcd;
    if (d->cur_t == now) {
        *d->dirty_end++ = var;
        return;
    }
    ks__vcd_list_slow(var, now);
}
/* Bytes written so far (including what is still buffered). */
uint64_t ks_vcd_bytes(const ks_vcd *vcd);
/* Number of declared (traced) variables. */
unsigned ks_vcd_var_count(const ks_vcd *vcd);

#endif
