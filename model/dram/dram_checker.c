/* dram_checker.c — replaying timing checker (dram_checker.h). */
#include "model/dram/dram_checker.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#define NONE INT64_MIN

typedef struct hist {
    int64_t t[DRAM_NCMD][DRAM_MAX_WINDOW]; /* newest first */
} hist;

struct dram_checker {
    const dram_spec *spec;
    FILE *report;
    int max_report;
    uint64_t violations, commands;
    char first[256];
    hist *ch, *rank, *bank;      /* per channel; per channel*rank; per channel*rank*bank */
    int32_t *open_row;           /* per bank: -1 closed, else the row (or -2 open, row unknown) */
    int *nopen;                  /* per rank */
    int64_t *last_ref;           /* per rank: cycle of the latest REF (0 = start) */
    int64_t *last_cycle;         /* per channel: cycle of the latest command */
};

static void *xcalloc(size_t n, size_t sz)
{
    void *p = calloc(n ? n : 1, sz);
    if (!p) {
        fprintf(stderr, "dram_checker: out of memory\n");
        exit(1);
    }
    return p;
}

static void hist_init(hist *h, size_t n)
{
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < DRAM_NCMD; c++)
            for (int w = 0; w < DRAM_MAX_WINDOW; w++)
                h[i].t[c][w] = NONE;
}

dram_checker *dram_checker_create(const dram_spec *spec, FILE *report, int max_report)
{
    dram_checker *k = xcalloc(1, sizeof *k);
    k->spec = spec;
    k->report = report;
    k->max_report = max_report;
    size_t nch = (size_t)spec->channels, nrk = nch * (size_t)spec->ranks, nbk = nrk * (size_t)spec->banks;
    k->ch = xcalloc(nch, sizeof *k->ch);
    k->rank = xcalloc(nrk, sizeof *k->rank);
    k->bank = xcalloc(nbk, sizeof *k->bank);
    hist_init(k->ch, nch);
    hist_init(k->rank, nrk);
    hist_init(k->bank, nbk);
    k->open_row = xcalloc(nbk, sizeof *k->open_row);
    for (size_t i = 0; i < nbk; i++)
        k->open_row[i] = -1;
    k->nopen = xcalloc(nrk, sizeof *k->nopen);
    k->last_ref = xcalloc(nrk, sizeof *k->last_ref);
    k->last_cycle = xcalloc(nch, sizeof *k->last_cycle);
    for (size_t i = 0; i < nch; i++)
        k->last_cycle[i] = NONE;
    return k;
}

void dram_checker_destroy(dram_checker *k)
{
    if (!k)
        return;
    free(k->ch);
    free(k->rank);
    free(k->bank);
    free(k->open_row);
    free(k->nopen);
    free(k->last_ref);
    free(k->last_cycle);
    free(k);
}

static void violation(dram_checker *k, const dram_cmd_rec *r, const char *fmt, ...)
{
    char msg[200], line[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (r)
        snprintf(line, sizeof line, "cycle %lld ch%d rank%d bank%d %s: %s", (long long)r->cycle, r->channel, r->rank,
                 r->bank, dram_cmd_name[r->cmd], msg);
    else
        snprintf(line, sizeof line, "%s", msg);
    if (k->violations == 0)
        snprintf(k->first, sizeof k->first, "%s", line);
    if (k->report && k->violations < (uint64_t)k->max_report)
        fprintf(k->report, "violation: %s\n", line);
    k->violations++;
}

static void push(hist *h, int cmd, int64_t t)
{
    memmove(&h->t[cmd][1], &h->t[cmd][0], (DRAM_MAX_WINDOW - 1) * sizeof(int64_t));
    h->t[cmd][0] = t;
}

void dram_checker_feed(dram_checker *k, const dram_cmd_rec *r)
{
    const dram_spec *s = k->spec;
    k->commands++;
    if (r->channel < 0 || r->channel >= s->channels || r->rank < 0 || r->rank >= s->ranks || r->cmd < 0 ||
        r->cmd >= DRAM_NCMD || (dram_cmd_is_bank_scoped(r->cmd) && (r->bank < 0 || r->bank >= s->banks))) {
        violation(k, NULL, "cycle %lld: command outside the organization (channel %d rank %d bank %d)",
                  (long long)r->cycle, r->channel, r->rank, r->bank);
        return;
    }
    const int bank_scoped = dram_cmd_is_bank_scoped(r->cmd);
    const int rk_i = r->channel * s->ranks + r->rank;
    hist *hc = &k->ch[r->channel], *hr = &k->rank[rk_i];
    hist *banks = &k->bank[rk_i * s->banks];
    int32_t *open = &k->open_row[rk_i * s->banks];
    /* command bus */
    if (k->last_cycle[r->channel] != NONE && r->cycle <= k->last_cycle[r->channel])
        violation(k, r, "command bus: previous command on this channel at cycle %lld",
                  (long long)k->last_cycle[r->channel]);
    k->last_cycle[r->channel] = r->cycle;
    /* constraint rows with TO = this command */
    for (int i = 0; i < s->nconstraints; i++) {
        const dram_constraint *c = &s->constraint[i];
        if (c->to != r->cmd)
            continue;
        int64_t from = NONE;
        switch (c->scope) {
        case DRAM_SCOPE_CHANNEL: from = hc->t[c->from][c->window - 1]; break;
        case DRAM_SCOPE_RANK: from = hr->t[c->from][c->window - 1]; break;
        case DRAM_SCOPE_BANK:
            if (bank_scoped)
                from = banks[r->bank].t[c->from][c->window - 1];
            break;
        case DRAM_SCOPE_SIBLING:
            if (bank_scoped)
                for (int b = 0; b < s->banks; b++)
                    if (b != r->bank && banks[b].t[c->from][0] > from)
                        from = banks[b].t[c->from][0];
            break;
        }
        if (from != NONE && r->cycle - from < c->cycles)
            violation(k, r, "%s %s -> %s%s needs %d cycles, got %lld (%s at %lld)", dram_scope_name[c->scope],
                      dram_cmd_name[c->from], dram_cmd_name[c->to], c->window > 1 ? " (window)" : "", c->cycles,
                      (long long)(r->cycle - from), dram_cmd_name[c->from], (long long)from);
    }
    /* bank state */
    int *nopen = &k->nopen[rk_i];
    switch (r->cmd) {
    case DRAM_ACT:
        if (open[r->bank] != -1)
            violation(k, r, "state: ACT to an open bank");
        else
            ++*nopen;
        open[r->bank] = r->row >= 0 ? r->row : -2;
        break;
    case DRAM_RD:
    case DRAM_WR:
        if (open[r->bank] == -1)
            violation(k, r, "state: %s to a closed bank", dram_cmd_name[r->cmd]);
        break;
    case DRAM_PRE:
        if (open[r->bank] != -1)
            --*nopen;
        open[r->bank] = -1;
        break;
    case DRAM_PREA:
        for (int b = 0; b < s->banks; b++)
            open[b] = -1;
        *nopen = 0;
        break;
    case DRAM_REF: {
        if (*nopen)
            violation(k, r, "state: REF with %d open bank(s)", *nopen);
        int64_t gap = r->cycle - k->last_ref[rk_i];
        int64_t allowed = (int64_t)(1 + s->max_postponed_refresh) * s->refresh_interval;
        if (gap > allowed)
            violation(k, r, "refresh: %lld cycles since the previous REF, allowed %lld", (long long)gap,
                      (long long)allowed);
        k->last_ref[rk_i] = r->cycle;
        break;
    }
    }
    /* histories */
    push(hc, r->cmd, r->cycle);
    push(hr, r->cmd, r->cycle);
    if (bank_scoped)
        push(&banks[r->bank], r->cmd, r->cycle);
}

uint64_t dram_checker_finish(dram_checker *k, int64_t end_cycle)
{
    const dram_spec *s = k->spec;
    int64_t allowed = (int64_t)(1 + s->max_postponed_refresh) * s->refresh_interval;
    for (int i = 0; i < s->channels * s->ranks; i++)
        if (end_cycle - k->last_ref[i] > allowed)
            violation(k, NULL, "end cycle %lld ch%d rank%d: refresh: %lld cycles since the previous REF, allowed %lld",
                      (long long)end_cycle, i / s->ranks, i % s->ranks, (long long)(end_cycle - k->last_ref[i]),
                      (long long)allowed);
    return k->violations;
}

uint64_t dram_checker_violations(const dram_checker *k) { return k->violations; }
uint64_t dram_checker_commands(const dram_checker *k) { return k->commands; }
const char *dram_checker_first(const dram_checker *k) { return k->first; }

void dram_cmd_format(const dram_cmd_rec *r, char *buf, size_t n)
{
    snprintf(buf, n, "%lld,%d,%d,%d,%s,%d\n", (long long)r->cycle, r->channel, r->rank, r->bank,
             dram_cmd_name[r->cmd], r->row);
}
