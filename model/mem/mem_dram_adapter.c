/* mem_dram_adapter.c — memory side <-> LPDDR3 port; see mem_dram_adapter.h. */
#include "model/mem/mem_dram_adapter.h"

#include <assert.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/dram/dram_port.h"

static const ks_desc_item items[] = {
    {KS_DESC_PORT, "mem_in", "in fifo<mem_req>", "", "", "line requests from the memory arbiter"},
    {KS_DESC_PORT, "mem_out", "out fifo<mem_resp>", "", "", "responses to the memory arbiter"},
    {KS_DESC_PORT, "dram_req", "out fifo<dram_port_req>", "", "", "requests to the LPDDR3 port"},
    {KS_DESC_PORT, "dram_resp", "in fifo<dram_port_resp>", "", "", "responses from the LPDDR3 port"},
    {KS_DESC_STAT, "requests", "requests", "", "", "requests forwarded to the DRAM"},
    {KS_DESC_STAT, "bytes", "bytes", "", "", "bytes requested from the DRAM"},
    {KS_DESC_STAT, "latency_sum", "cycles", "", "", "sum of forward-to-response accelerator cycles"},
    {KS_DESC_END, 0, 0, 0, 0, 0},
};
const ks_module_desc mem_dram_adapter_module_desc = {"dram_adapter", "memory-side front end of the LPDDR3 port", items, "memory"};

typedef struct slot {
    uint16_t src;
    uint64_t tag, sent;
    uint32_t bytes;
    int next_free;
} slot;

struct mem_dram_adapter {
    char *name;
    ks_clocked *proc;
    ks_fifo *mem_in, *mem_out, *dram_req, *dram_resp;
    slot *s;
    uint32_t cap, used;
    int free_head;
    uint64_t requests, bytes, latency_sum;
};

static int step(void *user, uint64_t cycle)
{
    mem_dram_adapter *a = user;
    int progress = 0;
    if (a->free_head >= 0 && ks_fifo_can_read(a->mem_in) && ks_fifo_can_write(a->dram_req)) {
        mem_req r = {0};
        KS_FIFO_READ(a->mem_in, &r);
        int k = a->free_head;
        a->free_head = a->s[k].next_free;
        a->used++;
        a->s[k].src = r.src;
        a->s[k].tag = r.tag;
        a->s[k].bytes = r.bytes;
        a->s[k].sent = cycle;
        dram_port_req d = {r.addr, (uint64_t)k, r.bytes, r.is_write};
        KS_FIFO_WRITE(a->dram_req, &d);
        a->requests++;
        a->bytes += r.bytes;
        progress++;
    }
    if (ks_fifo_can_read(a->dram_resp) && ks_fifo_can_write(a->mem_out)) {
        dram_port_resp d = {0};
        KS_FIFO_READ(a->dram_resp, &d);
        if (d.tag >= a->cap) {
            fprintf(stderr, "%s: DRAM response with unknown tag %llu\n", a->name, (unsigned long long)d.tag);
            abort(); /* wiring bug */
        }
        slot *s = &a->s[d.tag];
        mem_resp r = {d.addr, s->bytes, s->src, 0, s->tag};
        KS_FIFO_WRITE(a->mem_out, &r);
        a->latency_sum += cycle - s->sent;
        s->next_free = a->free_head;
        a->free_head = (int)d.tag;
        a->used--;
        progress++;
    }
    return progress;
}

static int busy_cb(void *user) { return ((mem_dram_adapter *)user)->used > 0; }
static void describe_cb(void *user, char *buf, unsigned cap)
{
    mem_dram_adapter *a = user;
    snprintf(buf, cap, "%u/%u requests at the DRAM%s", a->used, a->cap,
             ks_fifo_can_read(a->dram_resp) && !ks_fifo_can_write(a->mem_out) ? "; waits for space in the response FIFO"
                                                                            : "");
}

mem_dram_adapter *mem_dram_adapter_create(ks_sim *sim, ks_clock *clk, const char *name, uint32_t max_outstanding,
                                          char *err, size_t errlen)
{
    (void)sim;
    if (max_outstanding < 1) {
        snprintf(err, errlen, "%s: needs max_outstanding >= 1", name);
        return NULL;
    }
    mem_dram_adapter *a = calloc(1, sizeof *a);
    slot *s = calloc(max_outstanding, sizeof *s);
    char *nm = strdup(name);
    if (!a || !s || !nm) {
        free(a);
        free(s);
        free(nm);
        snprintf(err, errlen, "%s: out of memory", name);
        return NULL;
    }
    a->name = nm;
    a->s = s;
    a->cap = max_outstanding;
    for (uint32_t i = 0; i < max_outstanding; i++)
        s[i].next_free = i + 1 < max_outstanding ? (int)i + 1 : -1;
    a->free_head = 0;
    a->proc = ks_clocked_create(clk, name, step, a);
    ks_clocked_set_describe(a->proc, busy_cb, describe_cb);
    return a;
}

void mem_dram_adapter_connect(mem_dram_adapter *a, ks_fifo *mem_in, ks_fifo *mem_out, ks_fifo *dram_req,
                              ks_fifo *dram_resp)
{
    assert(mem_in && mem_out && dram_req && dram_resp && mem_in->elem_size == sizeof(mem_req) &&
           mem_out->elem_size == sizeof(mem_resp) && dram_req->elem_size == sizeof(dram_port_req) &&
           dram_resp->elem_size == sizeof(dram_port_resp));
    a->mem_in = mem_in;
    a->mem_out = mem_out;
    a->dram_req = dram_req;
    a->dram_resp = dram_resp;
    ks_clocked_wake_on(a->proc, ks_fifo_ev_written(mem_in));
    ks_clocked_wake_on(a->proc, ks_fifo_ev_freed(mem_out));
    ks_clocked_wake_on(a->proc, ks_fifo_ev_freed(dram_req));
    ks_clocked_wake_on(a->proc, ks_fifo_ev_written(dram_resp));
}

void mem_dram_adapter_destroy(mem_dram_adapter *a)
{
    if (!a)
        return;
    free(a->s);
    free(a->name);
    free(a);
}

int mem_dram_adapter_register(mem_dram_adapter *a, ks_stats *reg, const char *prefix)
{
    const ks_module_desc *d = &mem_dram_adapter_module_desc;
    int rc = 0;
    rc |= ks_stat_decl_counter(reg, d, prefix, "requests", &a->requests);
    rc |= ks_stat_decl_counter(reg, d, prefix, "bytes", &a->bytes);
    rc |= ks_stat_decl_counter(reg, d, prefix, "latency_sum", &a->latency_sum);
    return rc;
}

uint64_t mem_dram_adapter_requests(const mem_dram_adapter *a) { return a->requests; }
uint64_t mem_dram_adapter_bytes(const mem_dram_adapter *a) { return a->bytes; }
uint64_t mem_dram_adapter_latency_sum(const mem_dram_adapter *a) { return a->latency_sum; }
uint32_t mem_dram_adapter_outstanding(const mem_dram_adapter *a) { return a->used; }
