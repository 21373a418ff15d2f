/* cache.c — kernel module around a cache core; see cache.h. */
#include "model/mem/cache.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const ks_desc_item cache_items[] = {
    {KS_DESC_PORT, "probe", "direct call", "", "", "cache_core_access(core, addr, bytes, cycle) from the TRV/IST"},
    {KS_DESC_PORT, "req_in", "in fifo<mem_req>", "", "", "requests from the upper level (through an arbiter)"},
    {KS_DESC_PORT, "resp_out", "out fifo<mem_resp>", "", "", "responses to req_in requests"},
    {KS_DESC_PORT, "miss_out", "out fifo<mem_req>", "", "", "line requests to the next level"},
    {KS_DESC_PORT, "fill_in", "in fifo<mem_resp>", "", "", "lines from the next level"},
    {KS_DESC_STAT, "accesses", "accesses", "", "", "accesses accepted (not BLOCKED)"},
    {KS_DESC_STAT, "hits", "accesses", "", "", "accesses whose lines were all present"},
    {KS_DESC_STAT, "misses", "accesses", "", "", "accesses with a missing line"},
    {KS_DESC_STAT, "miss_lines", "lines", "", "", "MSHRs allocated = line requests sent down"},
    {KS_DESC_STAT, "merged", "lines", "", "", "missing lines merged into a waiting MSHR"},
    {KS_DESC_STAT, "blocked_mshr", "accesses", "", "", "refused: no free MSHR"},
    {KS_DESC_STAT, "blocked_merge", "accesses", "", "", "refused: MSHR waiter list full"},
    {KS_DESC_STAT, "blocked_port", "accesses", "", "", "refused: all ports used this cycle"},
    {KS_DESC_STAT, "blocked_bank", "accesses", "", "", "refused: bank busy this cycle"},
    {KS_DESC_STAT, "bank_conflicts", "accesses", "", "", "accesses needing a bank for >1 cycle"},
    {KS_DESC_STAT, "fills", "lines", "", "", "lines installed"},
    {KS_DESC_STAT, "evictions", "lines", "", "", "valid lines replaced"},
    {KS_DESC_STAT, "bytes_filled", "bytes", "", "", "bytes brought in from the next level"},
    {KS_DESC_STAT, "hit_rate", "ratio", "", "", "hits / accesses (every retry of a looping ray is an access)"},
    {KS_DESC_STAT, "line_hit_rate", "ratio", "", "", "hits / (hits + miss_lines): each missing line counted once"},
    {KS_DESC_PART, "sram", "SRAM", "", "",
     "banks arrays of size/banks, sequential access (CACTI); accesses read, fills write (docs/energy.md)"},
    {KS_DESC_END, 0, 0, 0, 0, 0},
};
const ks_module_desc cache_module_desc = {
    "cache", "non-blocking set-associative cache (node L1, node L2, primitive cache)", cache_items, "node_l1,node_l2,prim"};

typedef struct pending_resp {
    uint64_t ready;       /* cycle it may leave */
    mem_resp resp;
} pending_resp;

struct cache_unit {
    char *name;
    ks_sim *sim;
    ks_clock *clk;
    ks_clocked *proc;
    cache_core *core;
    cache_params p;
    ks_fifo *miss_out, *fill_in, *req_in, *resp_out;
    ks_event ev_filled;
    pending_resp *outq;   /* ring: responses in their hit pipeline */
    uint32_t outq_cap, outq_head, outq_n;
    uint64_t cycle;
};

static int step(void *user, uint64_t cycle);
static int busy_cb(void *user) { return cache_busy(user); }
static void describe_cb(void *user, char *buf, unsigned cap) { cache_describe(user, buf, cap); }
static void on_miss(void *user)
{
    cache_unit *u = user;
    ks_clocked_wake(u->proc);
}

cache_unit *cache_create(ks_sim *sim, ks_clock *clk, const char *name, const cache_params *p, char *err,
                              size_t errlen)
{
    char why[256];
    cache_core *core = cache_core_create(p, why, sizeof why);
    if (!core) {
        snprintf(err, errlen, "%s: %s", name, why);
        return NULL;
    }
    cache_unit *u = calloc(1, sizeof *u);
    size_t n = strlen(name) + 1;
    char *nm = malloc(n + 16);
    /* the hit pipeline holds hit_latency cycles of `ports` responses, plus
     * the waiters one fill can release */
    uint32_t cap = p->hit_latency * p->ports + p->mshr_merge + 1;
    pending_resp *q = calloc(cap, sizeof *q);
    if (!u || !nm || !q) {
        free(u);
        free(nm);
        free(q);
        cache_core_destroy(core);
        snprintf(err, errlen, "%s: out of memory", name);
        return NULL;
    }
    memcpy(nm, name, n);
    u->name = nm;
    u->sim = sim;
    u->clk = clk;
    u->core = core;
    u->p = *p;
    u->outq = q;
    u->outq_cap = cap;
    ks_event_init(&u->ev_filled, sim, name);
    u->proc = ks_clocked_create(clk, name, step, u);
    ks_clocked_set_describe(u->proc, busy_cb, describe_cb);
    cache_core_set_miss_hook(core, on_miss, u);
    return u;
}

void cache_destroy(cache_unit *u)
{
    if (!u)
        return;
    ks_event_destroy(&u->ev_filled);
    cache_core_destroy(u->core);
    free(u->outq);
    free(u->name);
    free(u);
}

void cache_connect(cache_unit *u, ks_fifo *miss_out, ks_fifo *fill_in, ks_fifo *req_in, ks_fifo *resp_out)
{
    u->miss_out = miss_out;
    u->fill_in = fill_in;
    u->req_in = req_in;
    u->resp_out = resp_out;
    if (fill_in)
        ks_clocked_wake_on(u->proc, ks_fifo_ev_written(fill_in));
    if (miss_out)
        ks_clocked_wake_on(u->proc, ks_fifo_ev_freed(miss_out));
    if (req_in)
        ks_clocked_wake_on(u->proc, ks_fifo_ev_written(req_in));
    if (resp_out)
        ks_clocked_wake_on(u->proc, ks_fifo_ev_freed(resp_out));
}

cache_core *cache_get_core(cache_unit *u) { return u->core; }
const char *cache_name(const cache_unit *u) { return u->name; }
ks_event *cache_ev_filled(cache_unit *u) { return &u->ev_filled; }
ks_clocked *cache_process(cache_unit *u) { return u->proc; }

static void outq_push(cache_unit *u, uint64_t ready, const mem_req *r)
{
    pending_resp *e = &u->outq[(u->outq_head + u->outq_n++) % u->outq_cap];
    e->ready = ready;
    e->resp.addr = r->addr;
    e->resp.bytes = r->bytes;
    e->resp.src = r->src;
    e->resp.pad = 0;
    e->resp.tag = r->tag;
}

static int step(void *user, uint64_t cycle)
{
    cache_unit *u = user;
    u->cycle = cycle;
    int progress = 0;
    int64_t now = (int64_t)cycle;

    /* 1. one fill per cycle (the fill write port) */
    const mem_resp *f = u->fill_in ? ks_fifo_peek(u->fill_in) : NULL;
    if (f) {
        /* released waiters need room in the response pipeline */
        if (u->outq_cap - u->outq_n >= u->p.mshr_merge) {
            mem_resp resp = {0};
            KS_FIFO_READ(u->fill_in, &resp);
            if (cache_core_fill(u->core, &resp, now) < 0) {
                fprintf(stderr, "%s: fill for 0x%llx (tag %llu) matches no MSHR\n", u->name,
                        (unsigned long long)resp.addr, (unsigned long long)resp.tag);
                abort(); /* a wiring bug, never input-dependent */
            }
            mem_req w;
            while (cache_core_pop_ready(u->core, &w))
                outq_push(u, cycle + u->p.hit_latency, &w);
            ks_event_notify_delta(&u->ev_filled);
            progress++;
        }
    }
    /* 2. requests from the upper level */
    for (uint32_t k = 0; u->req_in && k < u->p.ports && u->outq_n + 1 <= u->outq_cap - u->p.mshr_merge; k++) {
        const mem_req *r = ks_fifo_peek(u->req_in);
        if (!r)
            break;
        cache_result res = cache_core_request(u->core, r, now);
        if (res == CACHE_BLOCKED)
            break;
        if (res == CACHE_HIT)
            outq_push(u, cycle + u->p.hit_latency + cache_core_last_access_cycles(u->core) - 1, r);
        ks_fifo_pop(u->req_in);
        progress++;
    }
    /* 3. one miss request per cycle to the next level */
    mem_req m;
    if (u->miss_out && ks_fifo_can_write(u->miss_out) && cache_core_pop_miss(u->core, &m)) {
        KS_FIFO_WRITE(u->miss_out, &m);
        progress++;
    }
    /* 4. responses whose latency has elapsed */
    for (uint32_t k = 0; k < u->p.ports && u->outq_n; k++) {
        pending_resp *e = &u->outq[u->outq_head];
        if (e->ready > cycle || !u->resp_out || !ks_fifo_can_write(u->resp_out))
            break;
        KS_FIFO_WRITE(u->resp_out, &e->resp);
        u->outq_head = (u->outq_head + 1) % u->outq_cap;
        u->outq_n--;
        progress++;
    }
    /* idle: sleep until the oldest response is due (events wake us earlier) */
    if (!progress && u->outq_n && u->outq[u->outq_head].ready > cycle)
        ks_clocked_sleep_until_cycle(u->proc, u->outq[u->outq_head].ready);
    return progress;
}

static double line_hit_rate(const ks_stats *reg, void *user)
{
    (void)reg;
    const cache_stats *s = user;
    uint64_t d = s->hits + s->miss_lines;
    return d ? (double)s->hits / (double)d : 0.0;
}

int cache_register(cache_unit *u, ks_stats *reg, const char *prefix)
{
    const cache_stats *s = cache_core_stats_live(u->core);
    struct {
        const char *name;
        const uint64_t *v;
    } f[] = {
        {"accesses", &s->accesses},     {"hits", &s->hits},
        {"misses", &s->misses},         {"miss_lines", &s->miss_lines},
        {"merged", &s->merged},         {"blocked_mshr", &s->blocked_mshr},
        {"blocked_merge", &s->blocked_merge}, {"blocked_port", &s->blocked_port},
        {"blocked_bank", &s->blocked_bank},   {"bank_conflicts", &s->bank_conflicts},
        {"fills", &s->fills},           {"evictions", &s->evictions},
        {"bytes_filled", &s->bytes_filled},
    };
    for (size_t i = 0; i < sizeof f / sizeof f[0]; i++)
        if (ks_stat_decl_counter(reg, &cache_module_desc, prefix, f[i].name, f[i].v))
            return -1;
    if (ks_stat_decl_ratio(reg, &cache_module_desc, prefix, "hit_rate", "hits", "accesses"))
        return -1;
    return ks_stat_decl_formula(reg, &cache_module_desc, prefix, "line_hit_rate", line_hit_rate, (void *)s);
}

int cache_busy(const cache_unit *u)
{
    return cache_core_mshrs_busy(u->core) > 0 || u->outq_n > 0 || cache_core_ready_count(u->core) > 0;
}

void cache_describe(const cache_unit *u, char *buf, size_t len)
{
    char core[200];
    cache_core_describe(u->core, (int64_t)u->cycle, core, sizeof core);
    int n = snprintf(buf, len, "%s, %u responses in the hit pipeline", core, u->outq_n);
    if (n < 0 || (size_t)n >= len)
        return;
    if (cache_core_misses_queued(u->core) && u->miss_out && !ks_fifo_can_write(u->miss_out))
        snprintf(buf + n, len - (size_t)n, "; waits for space in %s", ks_fifo_name(u->miss_out));
    else if (u->outq_n && u->resp_out && !ks_fifo_can_write(u->resp_out))
        snprintf(buf + n, len - (size_t)n, "; waits for space in %s", ks_fifo_name(u->resp_out));
    else if (cache_core_mshrs_busy(u->core) && u->fill_in)
        snprintf(buf + n, len - (size_t)n, "; waits for fills on %s", ks_fifo_name(u->fill_in));
}
