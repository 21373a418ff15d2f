/* fifo.c — timed FIFO channels (contract in fifo.h): a ring buffer of
 * fixed-size items with the ready time stored per entry. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "kernel/sim_internal.h"

static const ks_desc_item fifo_items[] = {
    {KS_DESC_STAT, "writes", "entries", "", "", "entries written to the FIFO"},
    {KS_DESC_STAT, "reads", "entries", "", "", "entries read from the FIFO"},
    {KS_DESC_PART, "ram", "SRAM", "", "",
     "a 1R1W RAM of capacity x record width; writes and reads each access it once"},
    {KS_DESC_END, 0, 0, 0, 0, 0}};
const ks_module_desc ks_fifo_module_desc = {"fifo", "timed FIFO channel between units: bounded, with a latency",
                                            fifo_items, "fifo"};

/* A method starts waiting on a FIFO event: notify it as the channel's state
 * says (an item readable from now: next delta; the first item not ready
 * yet: at its ready time; free space: next delta). Such a trigger may be
 * spurious, never missing. */
static void written_on_wait(ks_event *ev, void *ctx)
{
    ks_fifo *f = ctx;
    ks_time now = *f->now;
    for (uint32_t k = 0; k < f->count; k++) {
        uint32_t i = (f->head + k) % f->capacity;
        if (f->ready[i] == now) {
            ks_event_notify_delta(ev);
            return;
        }
        if (f->ready[i] > now) {
            ks_event_notify_at(ev, f->ready[i]);
            return;
        }
    }
}

static void freed_on_wait(ks_event *ev, void *ctx)
{
    ks_fifo *f = ctx;
    if (f->count < f->capacity && f->reads)
        ks_event_notify_delta(ev);
}

ks_fifo *ks_fifo_create(ks_sim *sim, const char *name, size_t elem_size, uint32_t capacity,
                        uint32_t latency_cycles, ks_clock *clock)
{
    if (!name)
        name = "fifo";
    if (elem_size == 0 || elem_size > (1u << 20)) {
        ks__set_error(sim, "fifo '%s': element size %zu out of range 1..1048576", name, elem_size);
        return NULL;
    }
    if (capacity == 0 || capacity > (1u << 24)) {
        ks__set_error(sim, "fifo '%s': capacity %u out of range 1..16777216", name, capacity);
        return NULL;
    }
    if (latency_cycles && !clock) {
        ks__set_error(sim, "fifo '%s': a latency of %u cycles needs a clock", name, latency_cycles);
        return NULL;
    }
    ks_fifo *f = ks__xcalloc(1, sizeof *f);
    f->sim = sim;
    f->now = &sim->now;
    f->clock = clock;
    f->name = ks__xstrdup(name);
    f->elem_size = (uint32_t)elem_size;
    f->capacity = capacity;
    f->latency = latency_cycles;
    f->latency_ps = clock ? (ks_time)latency_cycles * ks_clock_period(clock) : 0;
    f->data = ks__xcalloc(capacity, elem_size);
    f->ready = ks__xcalloc(capacity, sizeof *f->ready);
    char ev[512];
    snprintf(ev, sizeof ev, "%s.written", name);
    ks_event_init(&f->ev_written, sim, ev);
    snprintf(ev, sizeof ev, "%s.freed", name);
    ks_event_init(&f->ev_freed, sim, ev);
    f->created = sim->now;
    f->vcd_listed = KS_TIME_MAX;
    f->ev_written.no_record = f->ev_freed.no_record = 1;
    ks__event_refresh(&f->ev_written);
    ks__event_refresh(&f->ev_freed);
    f->ev_written.on_wait = written_on_wait;
    f->ev_written.on_wait_ctx = f;
    f->ev_freed.on_wait = freed_on_wait;
    f->ev_freed.on_wait_ctx = f;
    KS_GROW(sim->fifos, sim->n_fifos, sim->cap_fifos);
    sim->fifos[sim->n_fifos++] = f;
    if (sim->vcd)
        ks__vcd_trace_fifo(sim->vcd, f);
    return f;
}

void ks__fifo_free(ks_fifo *f)
{
    ks_event_destroy(&f->ev_written);
    ks_event_destroy(&f->ev_freed);
    free(f->data);
    free(f->ready);
    free(f->name);
    free(f);
}

const char *ks_fifo_name(const ks_fifo *f) { return f->name; }
ks_event *ks_fifo_ev_written(ks_fifo *f) { return &f->ev_written; }
ks_event *ks_fifo_ev_freed(ks_fifo *f) { return &f->ev_freed; }
uint32_t ks_fifo_max_occupancy(const ks_fifo *f) { return f->max_occ; }
uint64_t ks_fifo_total_writes(const ks_fifo *f) { return f->reads + f->count; }
uint64_t ks_fifo_total_reads(const ks_fifo *f) { return f->reads; }
uint64_t ks_fifo_rejected_writes(const ks_fifo *f) { return f->rejected; }

ks_time ks_fifo_head_ready_time(const ks_fifo *f)
{
    return f->count ? f->ready[f->head] : KS_TIME_MAX;
}

double ks_fifo_mean_occupancy(const ks_fifo *f)
{
    ks_time now = *f->now;
    ks_time span = now - f->created;
    if (span <= 0)
        return (double)f->count;
    unsigned __int128 area = f->sum_read_t + (unsigned __int128)f->count * (uint64_t)now - f->sum_write_t;
    return (double)area / (double)span;
}

uint32_t ks_fifo_suggested_capacity(const ks_fifo *f)
{
    uint32_t c = 1;
    while (c <= f->max_occ && c < (1u << 31))
        c <<= 1;
    return c;
}

int ks_fifo_set_capacity(ks_fifo *f, uint32_t capacity)
{
    if (capacity == 0 || capacity > (1u << 24)) {
        ks__set_error(f->sim, "fifo '%s': capacity %u out of range 1..16777216", f->name, capacity);
        return -1;
    }
    if (capacity < f->count) {
        ks__set_error(f->sim, "fifo '%s': capacity %u below its occupancy %u", f->name, capacity,
                      f->count);
        return -1;
    }
    unsigned char *data = ks__xcalloc(capacity, f->elem_size);
    ks_time *ready = ks__xcalloc(capacity, sizeof *ready);
    for (uint32_t i = 0; i < f->count; i++) {
        uint32_t j = (f->head + i) % f->capacity;
        memcpy(data + (size_t)i * f->elem_size, f->data + (size_t)j * f->elem_size, f->elem_size);
        ready[i] = f->ready[j];
    }
    free(f->data);
    free(f->ready);
    f->data = data;
    f->ready = ready;
    f->head = 0;
    f->capacity = capacity;
    return 0;
}

void ks__fifo_size_mismatch(const ks_fifo *f, size_t size)
{
    fprintf(stderr, "rtsim kernel: fifo '%s' holds %u-byte items, accessed with %zu bytes\n", f->name,
            f->elem_size, size);
    abort();
}

uint32_t ks_sim_fifo_count(const ks_sim *sim) { return (uint32_t)sim->n_fifos; }
ks_fifo *ks_sim_fifo_at(const ks_sim *sim, uint32_t i)
{
    return i < sim->n_fifos ? sim->fifos[i] : NULL;
}
