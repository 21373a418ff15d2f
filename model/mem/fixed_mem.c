/* fixed_mem.c — fixed-latency, bandwidth-limited memory; see fixed_mem.h. */
#include "model/mem/fixed_mem.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const ks_desc_item items[] = {
    {KS_DESC_PORT, "req_in", "in fifo<mem_req>", "", "", "line requests"},
    {KS_DESC_PORT, "resp_out", "out fifo<mem_resp>", "", "", "responses in request order"},
    {KS_DESC_STAT, "requests", "requests", "", "", "requests served"},
    {KS_DESC_STAT, "bytes", "bytes", "", "", "bytes transferred"},
    {KS_DESC_STAT, "latency_sum", "cycles", "", "", "sum over requests of accept-to-response cycles"},
    {KS_DESC_STAT, "bus_busy_cycles", "cycles", "", "", "cycles the data bus was transferring"},
    {KS_DESC_PART, "dram", "DRAM", "", "", "off chip, no area; bytes x energy.fixed_mem_pj_per_byte"},
    {KS_DESC_END, 0, 0, 0, 0, 0},
};
const ks_module_desc fixed_mem_module_desc = {"fixed_mem", "fixed-latency main memory with a bandwidth limit", items, "memory"};

#define FRAC 65536u

typedef struct inflight {
    uint64_t ready, accepted;
    mem_resp resp;
} inflight;

struct fixed_mem {
    char *name;
    ks_clocked *proc;
    ks_fifo *req_in, *resp_out;
    uint32_t latency, cap;
    uint64_t frac_per_byte;   /* bus time per byte in 1/65536 cycles (0 = unlimited) */
    uint64_t bus_free;        /* in 1/65536 cycles */
    inflight *q;
    uint32_t head, n;
    uint64_t requests, bytes, latency_sum, bus_busy_cycles, bus_frac_total;
};

static int step(void *user, uint64_t cycle)
{
    fixed_mem *m = user;
    int progress = 0;
    const mem_req *r = ks_fifo_peek(m->req_in);
    if (r && m->n < m->cap) {
        mem_req req = {0};
        KS_FIFO_READ(m->req_in, &req);
        uint64_t start = cycle * FRAC > m->bus_free ? cycle * FRAC : m->bus_free;
        uint64_t xfer = (uint64_t)req.bytes * m->frac_per_byte;
        m->bus_free = start + xfer;
        m->bus_frac_total += xfer;
        m->bus_busy_cycles = m->bus_frac_total / FRAC;
        inflight *e = &m->q[(m->head + m->n++) % m->cap];
        e->ready = (m->bus_free + FRAC - 1) / FRAC + m->latency;
        e->accepted = cycle;
        e->resp.addr = req.addr;
        e->resp.bytes = req.bytes;
        e->resp.src = req.src;
        e->resp.pad = 0;
        e->resp.tag = req.tag;
        m->requests++;
        m->bytes += req.bytes;
        progress++;
    }
    if (m->n && m->q[m->head].ready <= cycle && ks_fifo_can_write(m->resp_out)) {
        inflight *e = &m->q[m->head];
        KS_FIFO_WRITE(m->resp_out, &e->resp);
        m->latency_sum += cycle - e->accepted;
        m->head = (m->head + 1) % m->cap;
        m->n--;
        progress++;
    }
    if (!progress && m->n && m->q[m->head].ready > cycle)
        ks_clocked_sleep_until_cycle(m->proc, m->q[m->head].ready);
    return progress;
}

static int busy_cb(void *user) { return fixed_mem_busy(user); }
static void describe_cb(void *user, char *buf, unsigned cap) { fixed_mem_describe(user, buf, cap); }

fixed_mem *fixed_mem_create(ks_sim *sim, ks_clock *clk, const char *name, uint32_t latency, double bytes_per_cycle,
                            uint32_t max_outstanding, char *err, size_t errlen)
{
    (void)sim;
    if (latency < 1 || max_outstanding < 1 || !(bytes_per_cycle >= 0) || !isfinite(bytes_per_cycle)) {
        snprintf(err, errlen, "%s: needs latency >= 1, max_outstanding >= 1, bandwidth >= 0 (got %u, %u, %g)",
                 name, latency, max_outstanding, bytes_per_cycle);
        return NULL;
    }
    fixed_mem *m = calloc(1, sizeof *m);
    inflight *q = calloc(max_outstanding, sizeof *q);
    char *nm = strdup(name);
    if (!m || !q || !nm) {
        free(m);
        free(q);
        free(nm);
        snprintf(err, errlen, "%s: out of memory", name);
        return NULL;
    }
    m->name = nm;
    m->q = q;
    m->cap = max_outstanding;
    m->latency = latency;
    m->frac_per_byte = bytes_per_cycle > 0 ? (uint64_t)ceil(FRAC / bytes_per_cycle) : 0;
    m->proc = ks_clocked_create(clk, name, step, m);
    ks_clocked_set_describe(m->proc, busy_cb, describe_cb);
    return m;
}

void fixed_mem_connect(fixed_mem *m, ks_fifo *req_in, ks_fifo *resp_out)
{
    assert(req_in && resp_out);
    m->req_in = req_in;
    m->resp_out = resp_out;
    ks_clocked_wake_on(m->proc, ks_fifo_ev_written(req_in));
    ks_clocked_wake_on(m->proc, ks_fifo_ev_freed(resp_out));
}

void fixed_mem_destroy(fixed_mem *m)
{
    if (!m)
        return;
    free(m->q);
    free(m->name);
    free(m);
}

int fixed_mem_register(fixed_mem *m, ks_stats *reg, const char *prefix)
{
    struct {
        const char *n;
        const uint64_t *v;
    } f[] = {
        {"requests", &m->requests},
        {"bytes", &m->bytes},
        {"latency_sum", &m->latency_sum},
        {"bus_busy_cycles", &m->bus_busy_cycles},
    };
    for (size_t i = 0; i < sizeof f / sizeof f[0]; i++)
        if (ks_stat_decl_counter(reg, &fixed_mem_module_desc, prefix, f[i].n, f[i].v))
            return -1;
    return 0;
}

uint64_t fixed_mem_requests(const fixed_mem *m) { return m->requests; }
uint64_t fixed_mem_bytes(const fixed_mem *m) { return m->bytes; }
uint64_t fixed_mem_latency_sum(const fixed_mem *m) { return m->latency_sum; }
int fixed_mem_busy(const fixed_mem *m) { return m->n > 0; }

void fixed_mem_describe(const fixed_mem *m, char *buf, size_t len)
{
    int n = snprintf(buf, len, "%u/%u in flight", m->n, m->cap);
    if (m->n && n >= 0 && (size_t)n < len)
        snprintf(buf + n, len - (size_t)n, ", oldest ready at cycle %llu%s", (unsigned long long)m->q[m->head].ready,
                 ks_fifo_can_write(m->resp_out) ? "" : "; waits for space in the response FIFO");
}
