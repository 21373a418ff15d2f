/* dram_port.c — dram_ctrl as a clocked kernel module behind request/response
 * FIFOs (dram_port.h): burst splitting, lazy catch-up, back-pressure, statistics. */
#include "model/dram/dram_port.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/dram/dram_report.h"

/* Controller-derived statistics (formulas that catch the controller up first). */
enum {
    PS_CYCLES,
    PS_CMD_ACT,
    PS_CMD_PRE,
    PS_CMD_PREA,
    PS_CMD_REF,
    PS_CMD_RD,
    PS_CMD_WR,
    PS_ROW_HIT_RATE,
    PS_BURST_READ_LAT,
    PS_ENERGY_UJ,
    PS_BACKGROUND_UJ,
    PS_COUNT
};

typedef struct port_stat_ref {
    dram_port *p;
    int which;
} port_stat_ref;

/* One accepted request until its response leaves. */
typedef struct port_slot {
    dram_port_resp resp;
    uint32_t added, completed;   /* bursts entered / finished */
    int next_free;
} port_slot;

struct dram_port {
    ks_sim *sim;
    char name[64];
    const dram_spec *spec;
    const dram_power_spec *power;
    dram_ctrl *c;
    ks_clock *clk;
    ks_clocked *proc;
    ks_fifo *req, *resp;
    ks_time stats_end;           /* statistics end here (-1: the current time) */
    dram_cmd_fn sink;
    void *sink_user;
    /* outstanding requests */
    port_slot *slots;
    int nslots, free_head;
    int cur;                     /* slot of the request at the FIFO head being split, -1 none */
    uint64_t cur_base;           /* address of its first burst */
    /* finished responses waiting for room in the response FIFO (ring) */
    dram_port_resp *ready;
    int ready_head, ready_n, ready_cap; /* ready_cap: 0 or a power of two (index by mask) */
    int input_done, drained;
    int64_t stall_since, blocked_since;   /* -1 when not stalled / blocked */
    uint64_t progress;           /* commands + completions since the last step */
    /* statistics (registered by reference) */
    uint64_t n_req, n_read_req, n_write_req, n_bursts, n_bytes;
    uint64_t n_read_done, read_lat_sum, n_write_done, write_lat_sum;
    uint64_t stall_cycles, blocked_cycles;
    port_stat_ref refs[PS_COUNT];
};

static void *xrealloc(void *p, size_t n)
{
    p = realloc(p, n ? n : 1);
    if (!p) {
        fprintf(stderr, "dram_port: out of memory\n");
        exit(1);
    }
    return p;
}

static int slot_alloc(dram_port *p)
{
    if (p->free_head < 0) {
        int n = p->nslots ? 2 * p->nslots : 64;
        p->slots = xrealloc(p->slots, (size_t)n * sizeof *p->slots);
        for (int i = n - 1; i >= p->nslots; i--) {
            p->slots[i].next_free = p->free_head;
            p->free_head = i;
        }
        p->nslots = n;
    }
    int i = p->free_head;
    p->free_head = p->slots[i].next_free;
    return i;
}

static void ready_push(dram_port *p, const dram_port_resp *r)
{
    if (p->ready_n == p->ready_cap) {
        int n = p->ready_cap ? 2 * p->ready_cap : 16;
        dram_port_resp *v = xrealloc(NULL, (size_t)n * sizeof *v);
        for (int i = 0; i < p->ready_n; i++)
            v[i] = p->ready[(p->ready_head + i) % p->ready_cap];
        free(p->ready);
        p->ready = v;
        p->ready_cap = n;
        p->ready_head = 0;
    }
    p->ready[(p->ready_head + p->ready_n++) & (p->ready_cap - 1)] = *r;
}

/* Controller callback: one burst done (tag = slot). */
static void on_done(void *user, uint64_t addr, uint64_t tag, bool is_write, int64_t latency)
{
    (void)addr;
    (void)is_write;
    (void)latency;
    dram_port *p = user;
    port_slot *s = &p->slots[tag];
    s->completed++;
    p->progress++;
    /* a burst completes only after it entered, so the last completion ends the request */
    if (s->completed < s->resp.bursts)
        return;
    s->resp.done_cycle = dram_clock(p->c);
    const uint64_t lat = (uint64_t)(s->resp.done_cycle - s->resp.accept_cycle);
    if (s->resp.is_write) {
        p->n_write_done++;
        p->write_lat_sum += lat;
    } else {
        p->n_read_done++;
        p->read_lat_sum += lat;
    }
    ready_push(p, &s->resp);
    s->next_free = p->free_head;
    p->free_head = (int)tag;
}

static void on_cmd(void *user, const dram_cmd_rec *r)
{
    dram_port *p = user;
    p->progress++;
    if (p->sink)
        p->sink(p->sink_user, r);
}

/* Moves finished responses into the response FIFO while it has room. */
static void deliver(dram_port *p, int64_t now)
{
    while (p->ready_n && ks_fifo_can_write(p->resp)) {
        KS_FIFO_WRITE(p->resp, &p->ready[p->ready_head]);
        p->ready_head = (p->ready_head + 1) & (p->ready_cap - 1);
        p->ready_n--;
        p->progress++;
    }
    if (p->ready_n && p->blocked_since < 0)
        p->blocked_since = now;
    if (!p->ready_n && p->blocked_since >= 0) {
        p->blocked_cycles += (uint64_t)(now - p->blocked_since);
        p->blocked_since = -1;
    }
}

/* Offers the next burst of the head request; 1 when one entered the controller. */
static int accept(dram_port *p, int64_t now)
{
    const uint64_t tx = (uint64_t)p->spec->tx_bytes;
    if (p->cur < 0) {
        const dram_port_req *q = ks_fifo_peek(p->req);
        if (!q)
            return 0;
        const uint64_t base = q->addr & ~(tx - 1);
        const uint64_t end = q->addr + (q->size ? q->size : 1);
        const int i = slot_alloc(p);
        port_slot *s = &p->slots[i];
        memset(s, 0, sizeof *s);
        s->resp.addr = q->addr;
        s->resp.tag = q->tag;
        s->resp.size = q->size;
        s->resp.is_write = q->is_write ? 1 : 0;
        s->resp.bursts = (uint32_t)((end - base + tx - 1) / tx);
        p->cur = i;
        p->cur_base = base;
    }
    port_slot *s = &p->slots[p->cur];
    const uint64_t addr = p->cur_base + (uint64_t)s->added * tx;
    if (!dram_add(p->c, addr, s->resp.is_write, (uint64_t)p->cur)) {
        if (p->stall_since < 0)
            p->stall_since = now;
        return 0;
    }
    if (p->stall_since >= 0) {
        p->stall_cycles += (uint64_t)(now - p->stall_since);
        p->stall_since = -1;
    }
    if (s->added++ == 0) {
        s->resp.accept_cycle = now;
        p->n_req++;
        if (s->resp.is_write)
            p->n_write_req++;
        else
            p->n_read_req++;
        p->n_bytes += s->resp.size;
    }
    p->n_bursts++;
    if (s->added == s->resp.bursts) {
        ks_fifo_pop(p->req);
        p->cur = -1;
    }
    return 1;
}

static int step(void *user, uint64_t cycle)
{
    dram_port *p = user;
    const int64_t now = (int64_t)cycle;
    p->progress = 0;
    /* Nothing in flight or offered: leave the controller at its last event (it catches
     * up when work arrives or statistics are read), so a finished run's controller
     * clock ends where the standalone driver's does. */
    if (!dram_pending(p->c) && !p->ready_n && p->cur < 0 && ks_fifo_occupancy(p->req) == 0 &&
        !(p->input_done && !p->drained))
        return 0;
    dram_advance_to(p->c, now);
    deliver(p, now);
    /* end of input: as the standalone driver, the cycle after the last burst entered
     * (before this cycle's offer, so the drain starts with the next tick) */
    if (p->input_done && !p->drained && p->cur < 0 && ks_fifo_occupancy(p->req) == 0) {
        dram_set_write_high_pct(p->c, 0);
        p->drained = 1;
    }
    int accepted = 0;
    if (!p->ready_n)
        accepted = accept(p, now);
    /* When must the next step run? Next cycle while requests can enter; else at the
     * controller's next event; FIFO events wake the process for everything else. */
    uint64_t made = p->progress + (uint64_t)accepted;
    uint64_t next = UINT64_MAX;
    const int drain_due = p->input_done && !p->drained && p->cur < 0 && ks_fifo_occupancy(p->req) == 0;
    /* Otherwise the port matters only where a request completes, or, while the
     * head request waits for a full controller queue, where a command may free an
     * entry (the controller's next event); the controller catches up lazily in
     * between (dram_advance_to), ticking exactly the cycles it would have. */
    if ((accepted && !p->ready_n && (p->cur >= 0 || ks_fifo_can_read(p->req))) || drain_due)
        next = cycle + 1;
    else if (dram_pending(p->c))
        next = (uint64_t)(p->stall_since >= 0 ? dram_next_event(p->c) : dram_next_completion(p->c));
    /* a request still in flight in the FIFO (latency): wake at its ready time
     * explicitly rather than rely on its written notification alone (an event keeps
     * one pending notification, event.h) */
    if (!p->ready_n && p->cur < 0 && ks_fifo_occupancy(p->req) && !ks_fifo_can_read(p->req)) {
        const uint64_t k = ks_clock_cycle_at_or_after(p->clk, ks_fifo_head_ready_time(p->req));
        if (k < next)
            next = k;
    }
    if (next == cycle + 1 && made == 0)
        made = 1; /* must run next cycle: stay awake (cheaper than a timer); counts as progress */
    if (next != UINT64_MAX && next != cycle + 1)
        ks_clocked_sleep_until_cycle(p->proc, next);
    return made > 0x7fffffff ? 0x7fffffff : (int)made;
}

static int port_busy(void *user)
{
    const dram_port *p = user;
    return dram_port_outstanding(p) > 0;
}

static void port_describe(void *user, char *buf, unsigned cap)
{
    const dram_port *p = user;
    snprintf(buf, cap, "%s: %llu requests outstanding, %d responses waiting for the response FIFO, "
             "%d controller entries, request FIFO %u/%u", p->name, (unsigned long long)dram_port_outstanding(p),
             p->ready_n, dram_pending(p->c), ks_fifo_occupancy(p->req), ks_fifo_capacity(p->req));
}

void dram_port_sync(dram_port *p)
{
    ks_time t = ks_sim_now(p->sim);
    if (p->stats_end >= 0 && p->stats_end < t)
        t = p->stats_end;
    dram_advance_to(p->c, t / ks_clock_period(p->clk));
}

void dram_port_set_stats_end(dram_port *p, ks_time t) { p->stats_end = t; }

double dram_port_row_hit_rate(dram_port *p)
{
    dram_port_sync(p);
    uint64_t hits = 0, all = 0;
    for (int i = 0; i < p->spec->channels; i++) {
        dram_chan_stats st;
        dram_chan_stats_get(p->c, i, &st);
        hits += st.row_hits;
        all += st.row_hits + st.row_misses + st.row_conflicts;
    }
    return all ? (double)hits / (double)all : 0.0;
}

void dram_port_energy_uJ(dram_port *p, double *total, double *background)
{
    dram_port_sync(p);
    dram_summary s;
    dram_summary_compute(p->c, p->power, &s);
    *total = s.energy_uJ;
    *background = (s.energy.act_stby_pJ + s.energy.pre_stby_pJ) / 1e6;
}

static double port_stat(const ks_stats *reg, void *user)
{
    (void)reg;
    const port_stat_ref *r = user;
    dram_port *p = r->p;
    double total, background;
    switch (r->which) {   /* the figures the accelerator's top level reads too */
    case PS_ROW_HIT_RATE: return dram_port_row_hit_rate(p);
    case PS_ENERGY_UJ: dram_port_energy_uJ(p, &total, &background); return total;
    case PS_BACKGROUND_UJ: dram_port_energy_uJ(p, &total, &background); return background;
    default: break;
    }
    dram_port_sync(p);
    uint64_t cmd[DRAM_NCMD] = {0}, lat = 0, nlat = 0;
    for (int i = 0; i < p->spec->channels; i++) {
        dram_chan_stats st;
        dram_chan_stats_get(p->c, i, &st);
        for (int k = 0; k < DRAM_NCMD; k++)
            cmd[k] += st.n_cmd[k];
        lat += st.read_latency_sum;
        nlat += st.reads_done;
    }
    switch (r->which) {
    case PS_CYCLES: return (double)dram_clock(p->c);
    case PS_CMD_ACT: return (double)cmd[DRAM_ACT];
    case PS_CMD_PRE: return (double)cmd[DRAM_PRE];
    case PS_CMD_PREA: return (double)cmd[DRAM_PREA];
    case PS_CMD_REF: return (double)cmd[DRAM_REF];
    case PS_CMD_RD: return (double)cmd[DRAM_RD];
    case PS_CMD_WR: return (double)cmd[DRAM_WR];
    case PS_BURST_READ_LAT: return nlat ? (double)lat / (double)nlat : 0.0;
    default: return 0.0;
    }
}

/* Statistic table: name, unit, description (also in dram_port_module_desc). */
static const ks_desc_item port_items[] = {
    {KS_DESC_PORT, "req", "in fifo<dram_port_req>", "", "", "requests (address, size, read/write, tag)"},
    {KS_DESC_PORT, "resp", "out fifo<dram_port_resp>", "", "", "one response per request when its last burst is done"},
    {KS_DESC_STAT, "requests", "requests", "", "", "requests accepted"},
    {KS_DESC_STAT, "read_requests", "requests", "", "", "read requests accepted"},
    {KS_DESC_STAT, "write_requests", "requests", "", "", "write requests accepted"},
    {KS_DESC_STAT, "bursts", "bursts", "", "", "DRAM bursts the requests were split into"},
    {KS_DESC_STAT, "bytes", "bytes", "", "", "bytes requested"},
    {KS_DESC_STAT, "reads_done", "requests", "", "", "read requests completed"},
    {KS_DESC_STAT, "read_latency_sum", "cycles", "", "", "sum of read request latencies (first burst in -> last data)"},
    {KS_DESC_STAT, "read_latency_mean", "cycles", "", "", "mean read request latency in DRAM cycles"},
    {KS_DESC_STAT, "writes_done", "requests", "", "", "write requests completed (last WR issued)"},
    {KS_DESC_STAT, "stall_cycles", "cycles", "", "", "cycles the head request waited for a full controller queue"},
    {KS_DESC_STAT, "resp_blocked_cycles", "cycles", "", "", "cycles finished responses waited for the response FIFO"},
    {KS_DESC_STAT, "dram_cycles", "cycles", "", "", "DRAM clock cycles simulated"},
    {KS_DESC_STAT, "cmd_act", "commands", "", "", "ACT commands"},
    {KS_DESC_STAT, "cmd_pre", "commands", "", "", "PRE commands"},
    {KS_DESC_STAT, "cmd_prea", "commands", "", "", "PREA commands (before refresh)"},
    {KS_DESC_STAT, "cmd_ref", "commands", "", "", "all-bank REF commands"},
    {KS_DESC_STAT, "cmd_rd", "commands", "", "", "RD commands (bursts)"},
    {KS_DESC_STAT, "cmd_wr", "commands", "", "", "WR commands (bursts)"},
    {KS_DESC_STAT, "row_hit_rate", "fraction", "", "", "row hits / (hits + misses + conflicts)"},
    {KS_DESC_STAT, "burst_read_latency_mean", "cycles", "", "", "mean burst read latency (Ramulator's figure)"},
    {KS_DESC_STAT, "energy_uJ", "uJ", "", "", "DRAM energy, DRAMPower method (only with a power file)"},
    {KS_DESC_STAT, "background_energy_uJ", "uJ", "", "", "part of energy_uJ spent in active and precharge standby (static)"},
    {KS_DESC_PART, "dram", "DRAM", "", "",
     "off chip, no area; ACT/PRE/RD/WR/REF energy and background standby (DRAMPower method)"},
    {KS_DESC_END, 0, 0, 0, 0, 0}};

const ks_module_desc dram_port_module_desc = {"dram", "LPDDR3 memory: command-level controller behind timed FIFOs",
                                       port_items, "dram"};


static int reg_counter(dram_port *p, ks_stats *st, const char *name, const uint64_t *v)
{
    return ks_stat_decl_counter(st, &dram_port_module_desc, p->name, name, v);
}

static int reg_formula(dram_port *p, ks_stats *st, const char *name, int which)
{
    p->refs[which] = (port_stat_ref){p, which};
    return ks_stat_decl_formula(st, &dram_port_module_desc, p->name, name, port_stat, &p->refs[which]);
}

static int register_stats(dram_port *p, ks_stats *st, char *err, size_t errlen)
{
    char full[128];
    /* refuse before registering anything: a half-registered module would leave the
     * registry pointing into a freed struct */
    for (const ks_desc_item *d = dram_port_module_desc.items; d->kind != KS_DESC_END; d++) {
        double v;
        snprintf(full, sizeof full, "%s.%s", p->name, d->name);
        if (d->kind == KS_DESC_STAT && ks_stats_value(st, full, &v) == 0) {
            snprintf(err, errlen, "%s: cannot register statistics: '%s' already exists", p->name, full);
            return -1;
        }
    }
    int rc = 0;
    rc |= reg_counter(p, st, "requests", &p->n_req);
    rc |= reg_counter(p, st, "read_requests", &p->n_read_req);
    rc |= reg_counter(p, st, "write_requests", &p->n_write_req);
    rc |= reg_counter(p, st, "bursts", &p->n_bursts);
    rc |= reg_counter(p, st, "bytes", &p->n_bytes);
    rc |= reg_counter(p, st, "reads_done", &p->n_read_done);
    rc |= reg_counter(p, st, "read_latency_sum", &p->read_lat_sum);
    rc |= ks_stat_decl_ratio(st, &dram_port_module_desc, p->name, "read_latency_mean", "read_latency_sum", "reads_done");
    rc |= reg_counter(p, st, "writes_done", &p->n_write_done);
    rc |= reg_counter(p, st, "stall_cycles", &p->stall_cycles);
    rc |= reg_counter(p, st, "resp_blocked_cycles", &p->blocked_cycles);
    rc |= reg_formula(p, st, "dram_cycles", PS_CYCLES);
    rc |= reg_formula(p, st, "cmd_act", PS_CMD_ACT);
    rc |= reg_formula(p, st, "cmd_pre", PS_CMD_PRE);
    rc |= reg_formula(p, st, "cmd_prea", PS_CMD_PREA);
    rc |= reg_formula(p, st, "cmd_ref", PS_CMD_REF);
    rc |= reg_formula(p, st, "cmd_rd", PS_CMD_RD);
    rc |= reg_formula(p, st, "cmd_wr", PS_CMD_WR);
    rc |= reg_formula(p, st, "row_hit_rate", PS_ROW_HIT_RATE);
    rc |= reg_formula(p, st, "burst_read_latency_mean", PS_BURST_READ_LAT);
    if (p->power)
        rc |= reg_formula(p, st, "energy_uJ", PS_ENERGY_UJ);
    if (p->power)
        rc |= reg_formula(p, st, "background_energy_uJ", PS_BACKGROUND_UJ);
    if (rc)
        snprintf(err, errlen, "%s: cannot register statistics: %s", p->name, ks_stats_error(st));
    return rc;
}

dram_port *dram_port_create(ks_sim *sim, const char *name, const dram_spec *spec, const dram_power_spec *power,
                            ks_fifo *req_in, ks_fifo *resp_out, ks_stats *stats, char *err, size_t errlen)
{
    if (!req_in || !resp_out || req_in->elem_size != sizeof(dram_port_req) ||
        resp_out->elem_size != sizeof(dram_port_resp)) {
        snprintf(err, errlen, "%s: request FIFO must carry dram_port_req (%zu bytes) and response FIFO "
                 "dram_port_resp (%zu bytes)", name, sizeof(dram_port_req), sizeof(dram_port_resp));
        return NULL;
    }
    if (spec->tck_ps <= 0) {
        snprintf(err, errlen, "%s: %s: tck_ps must be > 0", name, spec->source);
        return NULL;
    }
    dram_port *p = calloc(1, sizeof *p);
    if (!p) {
        snprintf(err, errlen, "%s: out of memory", name);
        return NULL;
    }
    snprintf(p->name, sizeof p->name, "%s", name);
    p->sim = sim;
    p->spec = spec;
    p->power = power;
    p->req = req_in;
    p->resp = resp_out;
    p->cur = -1;
    p->stats_end = -1;
    p->free_head = -1;
    p->stall_since = p->blocked_since = -1;
    p->c = dram_ctrl_create(spec, on_done, p, err, errlen);
    if (!p->c) {
        free(p);
        return NULL;
    }
    dram_set_cmd_sink(p->c, on_cmd, p);
    if (stats && register_stats(p, stats, err, errlen)) {
        dram_port_destroy(p);
        return NULL;
    }
    char n[96];
    snprintf(n, sizeof n, "%s.clk", name);
    p->clk = ks_clock_create(sim, n, (ks_time)spec->tck_ps);
    p->proc = p->clk ? ks_clocked_create(p->clk, name, step, p) : NULL;
    if (!p->proc) {
        snprintf(err, errlen, "%s: cannot create the DRAM clock/process: %s", name, ks_sim_error(sim));
        dram_port_destroy(p);
        return NULL;
    }
    ks_clocked_wake_on(p->proc, ks_fifo_ev_written(req_in));
    ks_clocked_wake_on(p->proc, ks_fifo_ev_freed(resp_out));
    ks_clocked_set_describe(p->proc, port_busy, port_describe);
    return p;
}

void dram_port_destroy(dram_port *p)
{
    if (!p)
        return;
    dram_ctrl_destroy(p->c);
    free(p->slots);
    free(p->ready);
    free(p);
}

ks_clock *dram_port_clock(const dram_port *p) { return p->clk; }
dram_ctrl *dram_port_ctrl(const dram_port *p) { return p->c; }

void dram_port_set_cmd_sink(dram_port *p, dram_cmd_fn fn, void *user)
{
    p->sink = fn;
    p->sink_user = user;
}

void dram_port_input_done(dram_port *p)
{
    p->input_done = 1;
    ks_clocked_wake(p->proc);
}

uint64_t dram_port_outstanding(const dram_port *p)
{
    return p->n_req - p->n_read_done - p->n_write_done + (uint64_t)p->ready_n;
}
