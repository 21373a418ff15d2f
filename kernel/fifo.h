/* fifo.h — timed FIFO channels between units.
 *
 * Contract:
 *  - Bounded capacity (>= 1 entry) of fixed-size items (elem_size bytes,
 *    copied in and out). Non-blocking: write fails when full, read when
 *    nothing is readable.
 *  - Latency: an item written at time t becomes readable at
 *    t + latency_cycles * clock period (the ready time is stored with the
 *    entry); with clock NULL the latency must be 0 and an item is readable
 *    at once. A read frees its slot at once.
 *  - Events: written (notified for the ready time of each item, so waiters
 *    wake when it becomes readable; delta notification when latency is 0)
 *    and freed (delta notification after a read). Clocked processes
 *    registered with ks_clocked_wake_on() on them wake at the matching edge.
 *  - Statistics: max occupancy, time-weighted mean occupancy (identical with
 *    or without idle skipping), total writes/reads, rejected writes.
 *  - When a VCD writer is open on the sim, the occupancy is traced as
 *    "<name>.occupancy" (scopes from the dots of the name).
 *  - ks_fifo_set_capacity before the run (or while empty) resizes, e.g. to
 *    ks_fifo_suggested_capacity(), the first power of two above the maximum
 *    occupancy seen (the paper's FIFO sizing, SPEC.md "FIFOs").
 * The struct is public only so that the hot queries can be inlined; its
 * fields are private. FIFOs are owned by the sim. */
#ifndef KS_FIFO_H
#define KS_FIFO_H

#include <stddef.h>
#include <stdint.h>

#include "kernel/clock.h"
#include "kernel/event.h"
#include "kernel/sim.h"

struct ks_vcd_var;

typedef struct ks_fifo {
    ks_sim *sim;
    const ks_time *now;      /* the sim's current time */
    ks_clock *clock;
    char *name;
    unsigned char *data;     /* capacity * elem_size */
    ks_time *ready;          /* ready time of each slot */
    uint32_t elem_size, capacity, latency;
    uint32_t head, count;    /* ring indices */
    ks_time latency_ps;
    ks_event ev_written, ev_freed;
    /* statistics */
    uint32_t max_occ;
    ks_time created, last_change;
    double occ_area;         /* integral of occupancy dt (ps) */
    uint64_t writes, reads, rejected;
    struct ks_vcd_var *vcd_occ;
} ks_fifo;

ks_fifo *ks_fifo_create(ks_sim *sim, const char *name, size_t elem_size, uint32_t capacity,
                        uint32_t latency_cycles, ks_clock *clock);
const char *ks_fifo_name(const ks_fifo *f);

static inline int ks_fifo_can_write(const ks_fifo *f) { return f->count < f->capacity; }
static inline uint32_t ks_fifo_occupancy(const ks_fifo *f) { return f->count; }
static inline uint32_t ks_fifo_capacity(const ks_fifo *f) { return f->capacity; }
static inline uint32_t ks_fifo_free(const ks_fifo *f) { return f->capacity - f->count; }
static inline int ks_fifo_can_read(const ks_fifo *f)
{
    return f->count && f->ready[f->head] <= *f->now;
}
/* The oldest readable item in place, or NULL. */
static inline const void *ks_fifo_peek(const ks_fifo *f)
{
    return ks_fifo_can_read(f) ? f->data + (size_t)f->head * f->elem_size : NULL;
}
/* 1 on success, 0 when full (counted as a rejected write). */
int ks_fifo_write(ks_fifo *f, const void *item);
/* 1 on success (item copied to out unless NULL), 0 when nothing readable. */
int ks_fifo_read(ks_fifo *f, void *out);
/* Ready time of the oldest item (KS_TIME_MAX when empty). */
ks_time ks_fifo_head_ready_time(const ks_fifo *f);

ks_event *ks_fifo_ev_written(ks_fifo *f);
ks_event *ks_fifo_ev_freed(ks_fifo *f);

uint32_t ks_fifo_max_occupancy(const ks_fifo *f);
double ks_fifo_mean_occupancy(const ks_fifo *f); /* time-weighted, up to now */
uint64_t ks_fifo_total_writes(const ks_fifo *f);
uint64_t ks_fifo_total_reads(const ks_fifo *f);
uint64_t ks_fifo_rejected_writes(const ks_fifo *f);
/* First power of two strictly above the max occupancy (>= 1). */
uint32_t ks_fifo_suggested_capacity(const ks_fifo *f);
/* 0 on success; -1 (error in ks_sim_error) when cap is 0 or smaller than the
 * current occupancy. */
int ks_fifo_set_capacity(ks_fifo *f, uint32_t capacity);

/* All FIFOs of a sim, in creation order (auto-sizing, reports). */
uint32_t ks_sim_fifo_count(const ks_sim *sim);
ks_fifo *ks_sim_fifo_at(const ks_sim *sim, uint32_t i);

#endif
