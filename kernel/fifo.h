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
 *    A method that starts waiting on one of them is notified from the
 *    channel's state (an item becoming readable, free space), possibly
 *    spuriously, never missing an item.
 *  - Statistics: max occupancy, time-weighted mean occupancy (identical with
 *    or without idle skipping), total writes/reads, rejected writes.
 *  - When a VCD writer is open on the sim, the occupancy is traced as
 *    "<name>.occupancy" (scopes from the dots of the name).
 *  - ks_fifo_set_capacity before the run (or while empty) resizes, e.g. to
 *    ks_fifo_suggested_capacity(), the first power of two above the maximum
 *    occupancy seen (the paper's FIFO sizing; docs/design.md, "Conventions
 *    of the model").
 * The struct is public only so that the hot queries can be inlined; its
 * fields are private. FIFOs are owned by the sim. */
#ifndef KS_FIFO_H
#define KS_FIFO_H

#include "kernel/module_desc.h"
#include <stddef.h>
#include <stdint.h>
#include <string.h>

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
    ks_time created;
    /* Occupancy integral = sum of read times + count * now - sum of write
     * times (each item contributes its residence time); exact. */
    unsigned __int128 sum_write_t, sum_read_t;
    uint64_t reads, rejected;  /* writes = reads + count */
    struct ks_vcd_var *vcd_occ;
    /* Time stamp at which vcd_occ was last put in the VCD writer's list of
     * changed variables (it is sampled when the time stamp is written);
     * KS_TIME_MAX while not traced, so one comparison covers both. */
    ks_time vcd_listed;
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
static inline int ks_fifo_write(ks_fifo *f, const void *item);
/* 1 on success (item copied to out unless NULL), 0 when nothing readable. */
static inline int ks_fifo_read(ks_fifo *f, void *out);
/* The same with the item size known at the call site (sizeof *ptr), which
 * lets the compiler inline the copy; the size must equal elem_size. */
#define KS_FIFO_WRITE(f, ptr) ks_fifo_write_sized((f), (ptr), sizeof *(ptr))
#define KS_FIFO_READ(f, ptr) ks_fifo_read_sized((f), (ptr), sizeof *(ptr))
static inline int ks_fifo_write_sized(ks_fifo *f, const void *item, size_t size);
static inline int ks_fifo_read_sized(ks_fifo *f, void *out, size_t size);
/* Zero-copy access. ks_fifo_write_slot: the slot the next write will use
 * (NULL when full), to be filled in place and then made an item by
 * ks_fifo_commit (same effects as ks_fifo_write). ks_fifo_pop: drops the
 * oldest readable item (ks_fifo_read without a copy); 1 on success. */
static inline void *ks_fifo_write_slot(ks_fifo *f);
static inline void ks_fifo_commit(ks_fifo *f);
static inline int ks_fifo_pop(ks_fifo *f);
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
/* Description of a FIFO as a module (--help-module fifo): its parameters,
 * statistics and its energy and area part (a RAM of capacity x record). */
extern const ks_module_desc ks_fifo_module_desc;

uint32_t ks_sim_fifo_count(const ks_sim *sim);
ks_fifo *ks_sim_fifo_at(const ks_sim *sim, uint32_t i);


/* ---- inline hot paths (private) ----
 * The generic read/write copy with memcpy(elem_size); the KS_FIFO_READ /
 * KS_FIFO_WRITE forms pass sizeof at the call site, so the copy is inlined. */
#include "kernel/sched_types.h"

#define KS_ALWAYS_INLINE inline __attribute__((always_inline))

__attribute__((noreturn, cold)) void ks__fifo_size_mismatch(const ks_fifo *f, size_t size);

/* Lists the traced occupancy for the time stamp now (called once per time
 * stamp, when vcd_listed < now, before the first change). */
static KS_ALWAYS_INLINE void ks__fifo_vcd_list(ks_fifo *f, ks_time now)
{
    f->vcd_listed = now;
    ks__vcd_list(f->vcd_occ, now);
}

/* mode: 0 copy elem_size bytes, 1 copy `size` bytes (known at the call
 * site), 2 no copy (the slot was filled in place). */
static KS_ALWAYS_INLINE int ks__fifo_write(ks_fifo *f, const void *item, int mode, size_t size)
{
    if (f->count == f->capacity) {
        f->rejected++;
        return 0;
    }
    ks_time now = *f->now;
    f->sum_write_t += (uint64_t)now;
    uint32_t i = f->head + f->count;
    if (i >= f->capacity)
        i -= f->capacity;
    if (mode == 1)
        memcpy(f->data + (size_t)i * size, item, size);
    else if (mode == 0)
        memcpy(f->data + (size_t)i * f->elem_size, item, f->elem_size);
    ks_time ready = now + f->latency_ps;
    f->ready[i] = ready;
    if (f->vcd_listed < now) /* traced, not listed yet at now; before the change */
        ks__fifo_vcd_list(f, now);
    f->count++;
    if (f->count > f->max_occ)
        f->max_occ = f->count;
    if (ready > now)
        ks__event_notify_at(&f->ev_written, ready);
    else
        ks__event_notify_delta(&f->ev_written);
    return 1;
}

static KS_ALWAYS_INLINE int ks__fifo_read(ks_fifo *f, void *out, int sized, size_t size)
{
    ks_time now = *f->now;
    if (!f->count || f->ready[f->head] > now)
        return 0;
    f->sum_read_t += (uint64_t)now;
    if (out) {
        if (sized)
            memcpy(out, f->data + (size_t)f->head * size, size);
        else
            memcpy(out, f->data + (size_t)f->head * f->elem_size, f->elem_size);
    }
    if (++f->head == f->capacity)
        f->head = 0;
    if (f->vcd_listed < now)
        ks__fifo_vcd_list(f, now);
    f->count--;
    f->reads++;
    ks__event_notify_delta(&f->ev_freed);
    /* Method waiters only: the event keeps just its earliest pending
     * notification, so the next item's one may have been dropped while an
     * earlier one was pending; re-announce it. (Clocked waiters got their
     * own wake-up for every write.) */
    if (f->ev_written.has_methods && f->count &&
        f->ready[f->head] > now)
        ks__event_notify_at_methods(&f->ev_written, f->ready[f->head]);
    return 1;
}

static KS_ALWAYS_INLINE int ks_fifo_write(ks_fifo *f, const void *item)
{
    return ks__fifo_write(f, item, 0, 0);
}

static KS_ALWAYS_INLINE int ks_fifo_read(ks_fifo *f, void *out)
{
    return ks__fifo_read(f, out, 0, 0);
}

static KS_ALWAYS_INLINE void *ks_fifo_write_slot(ks_fifo *f)
{
    if (f->count == f->capacity)
        return NULL;
    uint32_t i = f->head + f->count;
    if (i >= f->capacity)
        i -= f->capacity;
    return f->data + (size_t)i * f->elem_size;
}

static KS_ALWAYS_INLINE void ks_fifo_commit(ks_fifo *f) { ks__fifo_write(f, NULL, 2, 0); }

static KS_ALWAYS_INLINE int ks_fifo_pop(ks_fifo *f) { return ks__fifo_read(f, NULL, 0, 0); }

static KS_ALWAYS_INLINE int ks_fifo_write_sized(ks_fifo *f, const void *item, size_t size)
{
    if (size != f->elem_size)
        ks__fifo_size_mismatch(f, size);
    return ks__fifo_write(f, item, 1, size);
}

static KS_ALWAYS_INLINE int ks_fifo_read_sized(ks_fifo *f, void *out, size_t size)
{
    if (size != f->elem_size)
        ks__fifo_size_mismatch(f, size);
    return ks__fifo_read(f, out, 1, size);
}

#endif
