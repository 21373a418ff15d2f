/* mem_arbiter.c — round-robin request arbiter with response routing; see
 * mem_arbiter.h. */
#include "model/mem/mem_arbiter.h"

#include <assert.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const ks_desc_item items[] = {
    {KS_DESC_PARAM, "inputs", "int", "4 / 2", "1..256", "requesters (TRV L1s at the L2; L2 + prim at memory)"},
    {KS_DESC_PORT, "req_in[i]", "in fifo<mem_req>", "", "", "requests of requester i"},
    {KS_DESC_PORT, "resp_out[i]", "out fifo<mem_resp>", "", "", "responses to requester i (by src mod N)"},
    {KS_DESC_PORT, "req_out", "out fifo<mem_req>", "", "", "granted requests, src = src * N + i"},
    {KS_DESC_PORT, "resp_in", "in fifo<mem_resp>", "", "", "responses from the shared side"},
    {KS_DESC_STAT, "grants", "requests", "", "", "requests granted"},
    {KS_DESC_STAT, "grants_#", "requests", "", "", "requests granted to input #"},
    {KS_DESC_STAT, "bytes_#", "bytes", "", "", "bytes requested by input # (granted requests x their line size)"},
    {KS_DESC_STAT, "first_touch_#", "requests", "", "",
     "requests of input # for a line no earlier request of the run touched: compulsory misses of the level above"},
    {KS_DESC_STAT, "refetches_#", "requests", "", "",
     "requests of input # for a line requested before: capacity and conflict misses of the level above"},
    {KS_DESC_STAT, "footprint_bytes_#", "bytes", "", "",
     "distinct bytes input # requested (32-byte granules): the run's footprint; bytes_# minus this is refetched"},
    {KS_DESC_STAT, "conflict_cycles", "cycles", "", "", "cycles with more than one requester ready"},
    {KS_DESC_STAT, "responses", "responses", "", "", "responses routed back"},
    {KS_DESC_END, 0, 0, 0, 0, 0},
};
const ks_module_desc mem_arbiter_module_desc = {"arbiter", "round-robin arbiter of memory requests", items, NULL};

struct mem_arbiter {
    char *name;
    ks_clocked *proc;
    int n, last;
    ks_fifo **req_in, **resp_out;
    ks_fifo *req_out, *resp_in;
    uint64_t *grants_per;
    uint64_t grants, conflict_cycles, responses;
    /* Which 32-byte granules of the address space some granted request has
     * covered (a bit each, grown on demand): first touch against refetch,
     * and the footprint, per input. */
    uint64_t *touched;
    size_t touched_words;
    uint64_t *bytes_per, *first_touch_per, *refetch_per, *footprint_per;
    bool touch_oom;
};

#define TOUCH_GRANULE 32u   /* bytes: one LPDDR3 BL8 burst of a 32-bit channel (docs/dram.md) */

/* Marks the granules of request r (input i) as touched and counts it. */
static void count_touch(mem_arbiter *a, int i, const mem_req *r)
{
    a->bytes_per[i] += r->bytes;
    if (a->touch_oom || r->bytes == 0)
        return;
    const uint64_t g0 = r->addr / TOUCH_GRANULE, g1 = (r->addr + r->bytes - 1) / TOUCH_GRANULE;
    if (g1 / 64 >= a->touched_words) {
        size_t n = a->touched_words ? a->touched_words : 1024;
        while (n <= g1 / 64)
            n *= 2;
        uint64_t *t = realloc(a->touched, n * sizeof *t);
        if (!t) {   /* the statistics stop; the model does not depend on them */
            a->touch_oom = true;
            return;
        }
        memset(t + a->touched_words, 0, (n - a->touched_words) * sizeof *t);
        a->touched = t, a->touched_words = n;
    }
    uint64_t fresh = 0;
    for (uint64_t g = g0; g <= g1; g++) {
        const uint64_t bit = 1ull << (g % 64);
        if (!(a->touched[g / 64] & bit))
            a->touched[g / 64] |= bit, fresh++;
    }
    a->footprint_per[i] += fresh * TOUCH_GRANULE;
    if (fresh)
        a->first_touch_per[i]++;
    else
        a->refetch_per[i]++;
}

static int step(void *user, uint64_t cycle)
{
    (void)cycle;
    mem_arbiter *a = user;
    int progress = 0;
    if (ks_fifo_can_write(a->req_out)) {
        int ready = 0, pick = -1;
        for (int k = 1; k <= a->n; k++) {
            int i = (a->last + k) % a->n;
            if (ks_fifo_can_read(a->req_in[i])) {
                ready++;
                if (pick < 0)
                    pick = i;
            }
        }
        if (pick >= 0) {
            mem_req r = {0};
            KS_FIFO_READ(a->req_in[pick], &r);
            r.src = (uint16_t)(r.src * a->n + pick);
            KS_FIFO_WRITE(a->req_out, &r);
            a->last = pick;
            a->grants++;
            a->grants_per[pick]++;
            count_touch(a, pick, &r);
            a->conflict_cycles += ready > 1;
            progress++;
        }
    }
    const mem_resp *h = ks_fifo_peek(a->resp_in);
    if (h) {
        int i = h->src % a->n;
        ks_fifo *out = a->resp_out[i];
        if (!out) {
            fprintf(stderr, "%s: response for input %d, which has no response FIFO\n", a->name, i);
            abort(); /* wiring bug */
        }
        if (ks_fifo_can_write(out)) {
            mem_resp r = {0};
            KS_FIFO_READ(a->resp_in, &r);
            r.src = (uint16_t)(r.src / a->n);
            KS_FIFO_WRITE(out, &r);
            a->responses++;
            progress++;
        }
    }
    return progress;
}

static int busy_cb(void *user) { return mem_arbiter_busy(user); }
static void describe_cb(void *user, char *buf, unsigned cap) { mem_arbiter_describe(user, buf, cap); }

mem_arbiter *mem_arbiter_create(ks_sim *sim, ks_clock *clk, const char *name, int n, char *err, size_t errlen)
{
    (void)sim;
    if (n < 1 || n > 256) {
        snprintf(err, errlen, "%s: needs 1..256 inputs (got %d)", name, n);
        return NULL;
    }
    mem_arbiter *a = calloc(1, sizeof *a);
    if (!a)
        goto oom;
    a->n = n;
    a->last = n - 1;
    a->name = strdup(name);
    a->req_in = calloc((size_t)n, sizeof *a->req_in);
    a->resp_out = calloc((size_t)n, sizeof *a->resp_out);
    a->grants_per = calloc((size_t)n, sizeof *a->grants_per);
    a->bytes_per = calloc((size_t)n, sizeof *a->bytes_per);
    a->first_touch_per = calloc((size_t)n, sizeof *a->first_touch_per);
    a->refetch_per = calloc((size_t)n, sizeof *a->refetch_per);
    a->footprint_per = calloc((size_t)n, sizeof *a->footprint_per);
    if (!a->name || !a->req_in || !a->resp_out || !a->grants_per || !a->bytes_per || !a->first_touch_per ||
        !a->refetch_per || !a->footprint_per) {
        mem_arbiter_destroy(a);
        goto oom;
    }
    a->proc = ks_clocked_create(clk, name, step, a);
    ks_clocked_set_describe(a->proc, busy_cb, describe_cb);
    return a;
oom:
    snprintf(err, errlen, "%s: out of memory", name);
    return NULL;
}

void mem_arbiter_connect(mem_arbiter *a, ks_fifo *const *req_in, ks_fifo *const *resp_out, ks_fifo *req_out,
                         ks_fifo *resp_in)
{
    int n = a->n;
    assert(req_out && resp_in);
    for (int i = 0; i < n; i++)
        assert(req_in[i]);
    memcpy(a->req_in, req_in, (size_t)n * sizeof *a->req_in);
    if (resp_out)
        memcpy(a->resp_out, resp_out, (size_t)n * sizeof *a->resp_out);
    a->req_out = req_out;
    a->resp_in = resp_in;
    for (int i = 0; i < n; i++) {
        ks_clocked_wake_on(a->proc, ks_fifo_ev_written(req_in[i]));
        if (a->resp_out[i])
            ks_clocked_wake_on(a->proc, ks_fifo_ev_freed(a->resp_out[i]));
    }
    ks_clocked_wake_on(a->proc, ks_fifo_ev_freed(req_out));
    ks_clocked_wake_on(a->proc, ks_fifo_ev_written(resp_in));
}

void mem_arbiter_destroy(mem_arbiter *a)
{
    if (!a)
        return;
    free(a->name);
    free(a->req_in);
    free(a->resp_out);
    free(a->grants_per);
    free(a->bytes_per);
    free(a->first_touch_per);
    free(a->refetch_per);
    free(a->footprint_per);
    free(a->touched);
    free(a);
}

int mem_arbiter_register(mem_arbiter *a, ks_stats *reg, const char *prefix)
{
    const ks_module_desc *d = &mem_arbiter_module_desc;
    if (ks_stat_decl_counter(reg, d, prefix, "grants", &a->grants))
        return -1;
    for (int i = 0; i < a->n; i++) {
        const struct {
            const char *stem;
            uint64_t *v;
        } per[] = {{"grants", a->grants_per}, {"bytes", a->bytes_per}, {"first_touch", a->first_touch_per},
                   {"refetches", a->refetch_per}, {"footprint_bytes", a->footprint_per}};
        for (size_t k = 0; k < sizeof per / sizeof per[0]; k++) {
            char name[48];
            snprintf(name, sizeof name, "%s_%d", per[k].stem, i);
            if (ks_stat_decl_counter(reg, d, prefix, name, &per[k].v[i]))
                return -1;
        }
    }
    if (ks_stat_decl_counter(reg, d, prefix, "conflict_cycles", &a->conflict_cycles))
        return -1;
    return ks_stat_decl_counter(reg, d, prefix, "responses", &a->responses);
}

uint64_t mem_arbiter_grants(const mem_arbiter *a, int input)
{
    return input < 0 ? a->grants : input < a->n ? a->grants_per[input] : 0;
}

void mem_arbiter_input(const mem_arbiter *a, int input, mem_arbiter_input_stats *out)
{
    assert(input >= 0 && input < a->n);
    out->bytes = a->bytes_per[input];
    out->footprint_bytes = a->footprint_per[input];
    out->first_touch = a->first_touch_per[input];
    out->refetches = a->refetch_per[input];
}

int mem_arbiter_busy(const mem_arbiter *a)
{
    (void)a;
    return 0; /* holds nothing of its own: all its work sits in FIFOs */
}

void mem_arbiter_describe(const mem_arbiter *a, char *buf, size_t len)
{
    int waiting = 0;
    for (int i = 0; i < a->n; i++)
        waiting += ks_fifo_can_read(a->req_in[i]);
    const mem_resp *h = ks_fifo_peek(a->resp_in);
    int n = snprintf(buf, len, "%d requesters waiting, last grant %d", waiting, a->last);
    if (n < 0 || (size_t)n >= len)
        return;
    if (waiting && !ks_fifo_can_write(a->req_out))
        n += snprintf(buf + n, len - (size_t)n, "; waits for space in %s", ks_fifo_name(a->req_out));
    if (h && n >= 0 && (size_t)n < len && a->resp_out[h->src % a->n] &&
        !ks_fifo_can_write(a->resp_out[h->src % a->n]))
        snprintf(buf + n, len - (size_t)n, "; response waits for space in %s",
                 ks_fifo_name(a->resp_out[h->src % a->n]));
}
