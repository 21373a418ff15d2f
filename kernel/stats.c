/* stats.c — statistics registry (contract in stats.h). */
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "kernel/json.h"
#include "kernel/stats.h"

enum { ST_COUNTER, ST_REAL, ST_HIST, ST_FORMULA, ST_RATIO };

struct ks_histogram {
    double lo, hi, width;
    unsigned bins;
    uint64_t *counts;
    uint64_t under, over, count;
    double sum, min, max;
};

typedef struct stat_entry {
    int kind;
    char *name, *unit, *desc;
    uint64_t own_u;
    double own_d;
    const uint64_t *u;
    const double *d;
    ks_histogram *h;
    ks_formula_fn fn;
    void *user;
    char *num, *den;
    const ks_module_desc *decl_m;   /* declared registration: the table and */
    const ks_desc_item *decl_item;  /* its item, else NULL */
} stat_entry;

struct ks_stats {
    stat_entry **e;
    unsigned n, cap;
    /* name -> index + 1 (0: empty), open addressing, a power of two at
     * least twice n: lookups by name (a registration's duplicate
     * check, a ratio's terms, ks_stats_value) in constant time */
    unsigned *slot, nslot;
    char error[256];
};

static uint64_t name_hash(const char *s)
{
    uint64_t h = 14695981039346656037ull;   /* FNV-1a 64 */
    for (; *s; s++)
        h = (h ^ (unsigned char)*s) * 1099511628211ull;
    return h;
}

static void *xrealloc(void *p, size_t n)
{
    void *q = realloc(p, n ? n : 1);
    if (!q) {
        fprintf(stderr, "rtsim kernel: out of memory\n");
        abort();
    }
    return q;
}

static char *xstrdup(const char *s)
{
    if (!s)
        s = "";
    size_t n = strlen(s) + 1;
    char *d = xrealloc(NULL, n);
    memcpy(d, s, n);
    return d;
}

static void set_error(ks_stats *reg, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reg->error, sizeof reg->error, fmt, ap);
    va_end(ap);
}

ks_stats *ks_stats_create(void)
{
    ks_stats *r = xrealloc(NULL, sizeof *r);
    memset(r, 0, sizeof *r);
    return r;
}

void ks_stats_destroy(ks_stats *reg)
{
    if (!reg)
        return;
    for (unsigned i = 0; i < reg->n; i++) {
        stat_entry *e = reg->e[i];
        free(e->name);
        free(e->unit);
        free(e->desc);
        free(e->num);
        free(e->den);
        if (e->h) {
            free(e->h->counts);
            free(e->h);
        }
        free(e);
    }
    free(reg->e);
    free(reg->slot);
    free(reg);
}

const char *ks_stats_error(const ks_stats *reg) { return reg->error; }
unsigned ks_stats_count(const ks_stats *reg) { return reg->n; }

static stat_entry *find(const ks_stats *reg, const char *name)
{
    if (!reg->nslot)
        return NULL;
    for (unsigned k = (unsigned)name_hash(name) & (reg->nslot - 1);; k = (k + 1) & (reg->nslot - 1)) {
        unsigned i = reg->slot[k];
        if (!i)
            return NULL;
        if (!strcmp(reg->e[i - 1]->name, name))
            return reg->e[i - 1];
    }
}

static void index_entry(ks_stats *reg, unsigned i)
{
    unsigned k = (unsigned)name_hash(reg->e[i]->name) & (reg->nslot - 1);
    while (reg->slot[k])
        k = (k + 1) & (reg->nslot - 1);
    reg->slot[k] = i + 1;
}

static int name_ok(ks_stats *reg, const char *name)
{
    if (!name || !*name) {
        set_error(reg, "statistic without a name");
        return 0;
    }
    for (const char *c = name; *c; c++)
        if (*c == '"' || *c == '\\' || *c == ',' || (unsigned char)*c < 32) {
            set_error(reg, "statistic '%s': name may not contain quotes, backslashes, commas or control characters", name);
            return 0;
        }
    return 1;
}

static stat_entry *add(ks_stats *reg, int kind, const char *name, const char *unit,
                       const char *desc)
{
    if (!name_ok(reg, name))
        return NULL;
    if (find(reg, name)) {
        set_error(reg, "statistic '%s' registered twice", name);
        return NULL;
    }
    stat_entry *e = xrealloc(NULL, sizeof *e);
    memset(e, 0, sizeof *e);
    e->kind = kind;
    e->name = xstrdup(name);
    e->unit = xstrdup(unit);
    e->desc = xstrdup(desc);
    if (reg->n == reg->cap) {
        reg->cap = reg->cap ? reg->cap * 2 : 16;
        reg->e = xrealloc(reg->e, reg->cap * sizeof *reg->e);
    }
    reg->e[reg->n++] = e;
    if (2 * reg->n > reg->nslot) {   /* grow the index and rebuild it */
        reg->nslot = reg->nslot ? reg->nslot * 2 : 64;
        free(reg->slot);
        reg->slot = xrealloc(NULL, reg->nslot * sizeof *reg->slot);
        memset(reg->slot, 0, reg->nslot * sizeof *reg->slot);
        for (unsigned i = 0; i < reg->n; i++)
            index_entry(reg, i);
    } else {
        index_entry(reg, reg->n - 1);
    }
    return e;
}

uint64_t *ks_stat_counter(ks_stats *reg, const char *name, const char *unit, const char *desc)
{
    stat_entry *old = name ? find(reg, name) : NULL;
    if (old && old->kind == ST_COUNTER && old->u == &old->own_u)
        return &old->own_u;
    stat_entry *e = add(reg, ST_COUNTER, name, unit, desc);
    if (!e)
        return NULL;
    e->u = &e->own_u;
    return &e->own_u;
}

double *ks_stat_real(ks_stats *reg, const char *name, const char *unit, const char *desc)
{
    stat_entry *old = name ? find(reg, name) : NULL;
    if (old && old->kind == ST_REAL && old->d == &old->own_d)
        return &old->own_d;
    stat_entry *e = add(reg, ST_REAL, name, unit, desc);
    if (!e)
        return NULL;
    e->d = &e->own_d;
    return &e->own_d;
}

int ks_stat_counter_ref_in(ks_stats *reg, const char *scope, const char *name, const char *unit,
                           const char *desc, const uint64_t *value)
{
    char full[256];
    if (snprintf(full, sizeof full, "%s.%s", scope, name) >= (int)sizeof full) {
        set_error(reg, "statistic '%s.%s': name longer than %zu characters", scope, name, sizeof full - 1);
        return -1;
    }
    return ks_stat_counter_ref(reg, full, unit, desc, value);
}

int ks_stat_counter_ref(ks_stats *reg, const char *name, const char *unit, const char *desc,
                        const uint64_t *value)
{
    if (!value) {
        set_error(reg, "statistic '%s': no storage given", name ? name : "?");
        return -1;
    }
    stat_entry *e = add(reg, ST_COUNTER, name, unit, desc);
    if (!e)
        return -1;
    e->u = value;
    return 0;
}

int ks_stat_real_ref(ks_stats *reg, const char *name, const char *unit, const char *desc,
                     const double *value)
{
    if (!value) {
        set_error(reg, "statistic '%s': no storage given", name ? name : "?");
        return -1;
    }
    stat_entry *e = add(reg, ST_REAL, name, unit, desc);
    if (!e)
        return -1;
    e->d = value;
    return 0;
}

ks_histogram *ks_stat_histogram(ks_stats *reg, const char *name, const char *unit,
                                const char *desc, double lo, double hi, unsigned bins)
{
    if (!(hi > lo) || bins == 0 || bins > (1u << 20) || !isfinite(lo) || !isfinite(hi)) {
        set_error(reg, "histogram '%s': needs lo < hi (finite) and 1..1048576 bins (got [%g, %g), %u)",
                  name ? name : "?", lo, hi, bins);
        return NULL;
    }
    stat_entry *e = add(reg, ST_HIST, name, unit, desc);
    if (!e)
        return NULL;
    ks_histogram *h = xrealloc(NULL, sizeof *h);
    memset(h, 0, sizeof *h);
    h->lo = lo;
    h->hi = hi;
    h->bins = bins;
    h->width = (hi - lo) / bins;
    h->counts = xrealloc(NULL, bins * sizeof *h->counts);
    memset(h->counts, 0, bins * sizeof *h->counts);
    e->h = h;
    return h;
}

int ks_stat_formula(ks_stats *reg, const char *name, const char *unit, const char *desc,
                    ks_formula_fn fn, void *user)
{
    if (!fn) {
        set_error(reg, "formula '%s': no function given", name ? name : "?");
        return -1;
    }
    stat_entry *e = add(reg, ST_FORMULA, name, unit, desc);
    if (!e)
        return -1;
    e->fn = fn;
    e->user = user;
    return 0;
}

int ks_stat_ratio(ks_stats *reg, const char *name, const char *unit, const char *desc,
                  const char *numerator, const char *denominator)
{
    if (!numerator || !denominator) {
        set_error(reg, "ratio '%s': numerator and denominator names needed", name ? name : "?");
        return -1;
    }
    stat_entry *e = add(reg, ST_RATIO, name, unit, desc);
    if (!e)
        return -1;
    e->num = xstrdup(numerator);
    e->den = xstrdup(denominator);
    return 0;
}

/* '#' matches one or more digits, '*' one or more of [a-z0-9_]; the rest
 * literally. Backtracking on '*' keeps "energy.*_dynamic_mj" exact. */
static bool decl_match(const char *pat, const char *s)
{
    for (;;) {
        if (*pat == '#') {
            if (!(*s >= '0' && *s <= '9'))
                return false;
            while (*s >= '0' && *s <= '9')
                s++;
            pat++;
        } else if (*pat == '*') {
            const char *t = s;
            while ((*t >= 'a' && *t <= 'z') || (*t >= '0' && *t <= '9') || *t == '_') {
                t++;
                if (decl_match(pat + 1, t))
                    return true;
            }
            return false;
        } else if (!*pat) {
            return !*s;
        } else if (*pat++ != *s++) {
            return false;
        }
    }
}

const ks_desc_item *ks_desc_stat_match(const ks_module_desc *m, const char *name)
{
    for (const ks_desc_item *it = m->items; it && it->kind != KS_DESC_END; it++)
        if (it->kind == KS_DESC_STAT && it->name && decl_match(it->name, name))
            return it;
    return NULL;
}

/* The item of a declared name, and the full name; NULL with the error set. */
static const ks_desc_item *decl_begin(ks_stats *reg, const ks_module_desc *m, const char *scope, const char *name,
                                      char *full, size_t cap)
{
    const ks_desc_item *it = m && name ? ks_desc_stat_match(m, name) : NULL;
    if (!it) {
        set_error(reg, "statistic '%s%s%s' is not declared in the description of module %s", scope ? scope : "",
                  scope ? "." : "", name ? name : "?", m && m->name ? m->name : "?");
        return NULL;
    }
    int n = scope && *scope ? snprintf(full, cap, "%s.%s", scope, name) : snprintf(full, cap, "%s", name);
    if (n < 0 || (size_t)n >= cap) {
        set_error(reg, "statistic '%s.%s': name longer than %zu characters", scope, name, cap - 1);
        return NULL;
    }
    return it;
}

/* The item's description for this name: a '#' or '*' in it stands for what
 * the same wildcard of a one-wildcard name matched ("requests granted to
 * input #", "energy of the * unit(s)"). */
static const char *decl_desc(const ks_desc_item *it, const char *name, char *buf, size_t cap)
{
    const char *w = strpbrk(it->name, "#*");
    const char *dw = w ? strchr(it->desc, *w) : NULL;
    if (!w || !dw || strpbrk(w + 1, "#*"))
        return it->desc;
    size_t pre = (size_t)(w - it->name), suf = strlen(w + 1), n = strlen(name);
    if (n < pre + suf)
        return it->desc;
    snprintf(buf, cap, "%.*s%.*s%s", (int)(dw - it->desc), it->desc, (int)(n - pre - suf), name + pre, dw + 1);
    return buf;
}

static int decl_end(ks_stats *reg, const ks_module_desc *m, const ks_desc_item *it, const char *full, int rc)
{
    if (rc)
        return rc;
    stat_entry *e = find(reg, full);
    e->decl_m = m;
    e->decl_item = it;
    return 0;
}

int ks_stat_decl_counter(ks_stats *reg, const ks_module_desc *m, const char *scope, const char *name,
                         const uint64_t *value)
{
    char full[256];
    const ks_desc_item *it = decl_begin(reg, m, scope, name, full, sizeof full);
    char desc[256];
    return it ? decl_end(reg, m, it, full, ks_stat_counter_ref(reg, full, it->type, decl_desc(it, name, desc, sizeof desc), value)) : -1;
}

int ks_stat_decl_real(ks_stats *reg, const ks_module_desc *m, const char *scope, const char *name,
                      const double *value)
{
    char full[256];
    const ks_desc_item *it = decl_begin(reg, m, scope, name, full, sizeof full);
    char desc[256];
    return it ? decl_end(reg, m, it, full, ks_stat_real_ref(reg, full, it->type, decl_desc(it, name, desc, sizeof desc), value)) : -1;
}

int ks_stat_decl_formula(ks_stats *reg, const ks_module_desc *m, const char *scope, const char *name,
                         ks_formula_fn fn, void *user)
{
    char full[256];
    const ks_desc_item *it = decl_begin(reg, m, scope, name, full, sizeof full);
    char desc[256];
    return it ? decl_end(reg, m, it, full, ks_stat_formula(reg, full, it->type, decl_desc(it, name, desc, sizeof desc), fn, user)) : -1;
}

ks_histogram *ks_stat_decl_histogram(ks_stats *reg, const ks_module_desc *m, const char *scope, const char *name,
                                     double lo, double hi, unsigned bins)
{
    char full[256];
    const ks_desc_item *it = decl_begin(reg, m, scope, name, full, sizeof full);
    char desc[256];
    ks_histogram *h = it ? ks_stat_histogram(reg, full, it->type, decl_desc(it, name, desc, sizeof desc), lo, hi, bins)
                         : NULL;
    if (h)
        decl_end(reg, m, it, full, 0);
    return h;
}

int ks_stat_decl_ratio(ks_stats *reg, const ks_module_desc *m, const char *scope, const char *name,
                       const char *numerator, const char *denominator)
{
    char full[256], num[256], den[256];
    const ks_desc_item *it = decl_begin(reg, m, scope, name, full, sizeof full);
    if (!it)
        return -1;
    snprintf(num, sizeof num, "%s%s%s", scope && *scope ? scope : "", scope && *scope ? "." : "", numerator);
    snprintf(den, sizeof den, "%s%s%s", scope && *scope ? scope : "", scope && *scope ? "." : "", denominator);
    char desc[256];
    return decl_end(reg, m, it, full, ks_stat_ratio(reg, full, it->type, decl_desc(it, name, desc, sizeof desc), num, den));
}

bool ks_stats_registered_from(const ks_stats *reg, const ks_module_desc *m, const ks_desc_item *item)
{
    for (unsigned i = 0; i < reg->n; i++)
        if (reg->e[i]->decl_m == m && reg->e[i]->decl_item == item)
            return true;
    return false;
}

void ks_histogram_add(ks_histogram *h, double v)
{
    if (!h)
        return;
    if (h->count == 0 || v < h->min)
        h->min = v;
    if (h->count == 0 || v > h->max)
        h->max = v;
    h->count++;
    h->sum += v;
    if (v < h->lo)
        h->under++;
    else if (v >= h->hi)
        h->over++;
    else {
        unsigned b = (unsigned)((v - h->lo) / h->width);
        if (b >= h->bins)
            b = h->bins - 1;
        h->counts[b]++;
    }
}

uint64_t ks_histogram_count(const ks_histogram *h) { return h->count; }
double ks_histogram_mean(const ks_histogram *h) { return h->count ? h->sum / (double)h->count : 0; }

static double value_of(const ks_stats *reg, const stat_entry *e, int depth);

static double by_name(const ks_stats *reg, const char *name, int depth)
{
    const stat_entry *e = find(reg, name);
    return e ? value_of(reg, e, depth + 1) : NAN;
}

static double value_of(const ks_stats *reg, const stat_entry *e, int depth)
{
    if (depth > 32)
        return NAN; /* a cycle of ratios */
    switch (e->kind) {
    case ST_COUNTER: return (double)*e->u;
    case ST_REAL: return *e->d;
    case ST_HIST: return ks_histogram_mean(e->h);
    case ST_FORMULA: return e->fn(reg, e->user);
    case ST_RATIO: {
        double n = by_name(reg, e->num, depth), d = by_name(reg, e->den, depth);
        if (isnan(n) || isnan(d))
            return NAN;
        return d == 0 ? 0 : n / d;
    }
    }
    return NAN;
}

double ks_stats_value_or(const ks_stats *reg, const char *name, double fallback)
{
    double v;
    return ks_stats_value(reg, name, &v) == 0 ? v : fallback;
}

int ks_stats_value(const ks_stats *reg, const char *name, double *out)
{
    const stat_entry *e = find(reg, name);
    if (!e)
        return -1;
    *out = value_of(reg, e, 0);
    return 0;
}

/* ---- output ---- */


/* Shortest form that reads back to the same double. */
static void fmt_real(char *buf, size_t cap, double v)
{
    for (int prec = 6; prec <= 17; prec++) {
        snprintf(buf, cap, "%.*g", prec, v);
        if (strtod(buf, NULL) == v)
            return;
    }
}

static void json_real(FILE *o, double v)
{
    if (!isfinite(v)) {
        fputs("null", o);
        return;
    }
    char b[40];
    fmt_real(b, sizeof b, v);
    fputs(b, o);
}

int ks_stats_write_json(const ks_stats *reg, FILE *o)
{
    fputs("{\n", o);
    for (unsigned i = 0; i < reg->n; i++) {
        const stat_entry *e = reg->e[i];
        fputs("  ", o);
        ks_json_string(o, e->name);
        fputs(": ", o);
        if (e->kind == ST_COUNTER)
            fprintf(o, "%llu", (unsigned long long)*e->u);
        else if (e->kind == ST_HIST) {
            const ks_histogram *h = e->h;
            fprintf(o, "{\"count\": %llu, \"mean\": ", (unsigned long long)h->count);
            json_real(o, ks_histogram_mean(h));
            fputs(", \"min\": ", o);
            json_real(o, h->count ? h->min : 0);
            fputs(", \"max\": ", o);
            json_real(o, h->count ? h->max : 0);
            fputs(", \"lo\": ", o);
            json_real(o, h->lo);
            fputs(", \"hi\": ", o);
            json_real(o, h->hi);
            fprintf(o, ", \"underflow\": %llu, \"overflow\": %llu, \"bins\": [",
                    (unsigned long long)h->under, (unsigned long long)h->over);
            for (unsigned b = 0; b < h->bins; b++)
                fprintf(o, "%s%llu", b ? ", " : "", (unsigned long long)h->counts[b]);
            fputs("]}", o);
        } else
            json_real(o, value_of(reg, e, 0));
        fputs(",\n", o);
    }
    fputs("  \"_units\": {", o);
    for (unsigned i = 0; i < reg->n; i++) {
        fputs(i ? ", " : "", o);
        ks_json_string(o, reg->e[i]->name);
        fputs(": ", o);
        ks_json_string(o, reg->e[i]->unit);
    }
    fputs("},\n  \"_descriptions\": {", o);
    for (unsigned i = 0; i < reg->n; i++) {
        fputs(i ? ",\n    " : "\n    ", o);
        ks_json_string(o, reg->e[i]->name);
        fputs(": ", o);
        ks_json_string(o, reg->e[i]->desc);
    }
    fputs(reg->n ? "\n  }\n}\n" : "}\n}\n", o);
    return ferror(o) ? -1 : 0;
}

static void csv_field(FILE *o, const char *s)
{
    if (strpbrk(s, ",\"\n")) {
        fputc('"', o);
        for (; *s; s++) {
            if (*s == '"')
                fputc('"', o);
            fputc(*s, o);
        }
        fputc('"', o);
    } else
        fputs(s, o);
}

int ks_stats_write_csv(const ks_stats *reg, FILE *o)
{
    fputs("name,value,unit,description\n", o);
    char b[40];
    for (unsigned i = 0; i < reg->n; i++) {
        const stat_entry *e = reg->e[i];
        fputs(e->name, o);
        fputc(',', o);
        if (e->kind == ST_COUNTER)
            fprintf(o, "%llu", (unsigned long long)*e->u);
        else {
            double v = value_of(reg, e, 0);
            if (isfinite(v)) {
                fmt_real(b, sizeof b, v);
                fputs(b, o);
            }
        }
        fputc(',', o);
        csv_field(o, e->unit);
        fputc(',', o);
        csv_field(o, e->desc);
        fputc('\n', o);
    }
    return ferror(o) ? -1 : 0;
}

int ks_stats_write_summary(const ks_stats *reg, FILE *o)
{
    int wn = 4, wv = 5, wu = 4;
    /* Room for the longest histogram line: "n=" + 20 digits + " mean=" + 11
     * (%.4g of -DBL_MAX) + " max=" + 11 + NUL = 56 (gcc's -Wformat-truncation
     * flags anything smaller when it sees the ranges, e.g. with -O3 or PGO). */
    char (*vals)[64] = xrealloc(NULL, (reg->n + 1) * sizeof *vals);
    for (unsigned i = 0; i < reg->n; i++) {
        const stat_entry *e = reg->e[i];
        if (e->kind == ST_COUNTER)
            snprintf(vals[i], sizeof vals[i], "%llu", (unsigned long long)*e->u);
        else if (e->kind == ST_HIST)
            snprintf(vals[i], sizeof vals[i], "n=%llu mean=%.4g max=%.4g",
                     (unsigned long long)e->h->count, ks_histogram_mean(e->h),
                     e->h->count ? e->h->max : 0.0);
        else
            snprintf(vals[i], sizeof vals[i], "%.6g", value_of(reg, e, 0));
        int l = (int)strlen(e->name);
        if (l > wn)
            wn = l;
        l = (int)strlen(vals[i]);
        if (l > wv)
            wv = l;
        l = (int)strlen(e->unit);
        if (l > wu)
            wu = l;
    }
    fprintf(o, "%-*s  %*s  %-*s  %s\n", wn, "name", wv, "value", wu, "unit", "description");
    for (unsigned i = 0; i < reg->n; i++) {
        const stat_entry *e = reg->e[i];
        fprintf(o, "%-*s  %*s  %-*s  %s\n", wn, e->name, wv, vals[i], wu, e->unit, e->desc);
    }
    free(vals);
    return ferror(o) ? -1 : 0;
}
