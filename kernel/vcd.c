/* vcd.c — VCD writer (contract in vcd.h). Values are formatted by hand
 * (binary through a byte -> 8 characters table) into one large buffer that
 * is written out in big blocks. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "kernel/out_file.h"
#include "kernel/sim_internal.h"

enum { VAR_BIT = 0, VAR_INT = 1, VAR_ENUM = 2 };
/* 128 kB: the buffer stays in the core's L2 cache while it is filled and
 * copied to the kernel (measurements against 1 MB on the shared machine:
 * docs/validation/kernel-speed.md, the VCD round). */
#define VCD_BUF (1u << 17)
#define VCD_LINE 80u   /* longest bit/integer change: b + 64 digits + " id\n" + 8 spare */
#define VCD_CHUNK (VCD_BUF / 4 / VCD_LINE) /* changes given room at once */

struct ks_vcd_var {
    /* same prefix as struct ks__vcd_var_head (vcd.h inline fast path) */
    ks_vcd *vcd;
    uint64_t value;            /* current value */
    uint64_t mask;
    ks_time stamp;             /* time of its dirty-list entry (listed at most
                                  once per time stamp; -1: never) */
    /* private */
    const uint32_t *src;       /* sampled: the traced location, else NULL */
    uint8_t kind;
    uint8_t idlen;
    uint64_t emitted;          /* value as of the last time written out */
    char id[8];                /* padded: copied as 8 bytes */
    char tail[8];              /* what follows the value: " id\n" (int), "id\n" (bit) */
    uint8_t tail_len;
    unsigned width;
    const char *const *names;
    unsigned n_names;
    char *name;
    unsigned order;
};

struct ks_vcd {
    /* same prefix as struct ks__vcd_head (vcd.h inline fast path) */
    const ks_time *now;
    ks_time cur_t;             /* time of the changes in the dirty list */
    ks_vcd_var **dirty, **dirty_end;
    unsigned cap_dirty;
    uint8_t header_done;
    /* private */
    uint8_t started, ended, io_error, discard;
    ks_sim *sim;
    FILE *f;
    char *path;
    ks_out *out;               /* the output layer's plan (out_file.h) */
    ks_time ts_ps;
    char ts_str[24];
    ks_time begin, end;
    char **pats;
    unsigned n_pats;
    ks_vcd_var **vars;
    unsigned n_vars, cap_vars;
    char *buf;
    size_t pos;
    uint64_t flushed;
    int64_t last_vt;
    uint64_t hi_val;           /* time stamp / 10000 formatted in hi_str (0: none) */
    char hi_str[24];
    uint8_t hi_len;
};

static char bin8[257][8]; /* one spare row: top-byte copies read past a row */
static char bin_small[256][8]; /* v < 256 in binary without leading zeros */
static uint8_t bin_small_len[256];
static char dec4[10000][4]; /* 0000..9999 */
static int bin8_ready;

static void init_tables(void)
{
    if (bin8_ready)
        return;
    for (int v = 0; v < 256; v++)
        for (int b = 0; b < 8; b++)
            bin8[v][b] = (char)('0' + ((v >> (7 - b)) & 1));
    for (int v = 0; v < 256; v++) {
        int nb = v ? 32 - __builtin_clz((unsigned)v) : 1;
        for (int b = 0; b < nb; b++)
            bin_small[v][b] = (char)('0' + ((v >> (nb - 1 - b)) & 1));
        bin_small_len[v] = (uint8_t)nb;
    }
    for (int v = 0; v < 10000; v++) {
        dec4[v][0] = (char)('0' + v / 1000);
        dec4[v][1] = (char)('0' + v / 100 % 10);
        dec4[v][2] = (char)('0' + v / 10 % 10);
        dec4[v][3] = (char)('0' + v % 10);
    }
    bin8_ready = 1;
}

static inline size_t n_dirty(const ks_vcd *d) { return (size_t)(d->dirty_end - d->dirty); }

/* ---- output buffer ---- */

static void flush_buf(ks_vcd *d)
{
    if (d->pos && !d->io_error) {
        if (fwrite(d->buf, 1, d->pos, d->f) != d->pos)
            d->io_error = 1;
    }
    d->flushed += d->pos;
    d->pos = 0;
}

static inline void ensure(ks_vcd *d, size_t n)
{
    if (d->pos + n > VCD_BUF)
        flush_buf(d);
}

static void put_str(ks_vcd *d, const char *s)
{
    size_t n = strlen(s);
    if (n > VCD_BUF / 2) { /* very long text: write through */
        flush_buf(d);
        if (!d->io_error && fwrite(s, 1, n, d->f) != n)
            d->io_error = 1;
        d->flushed += n;
        return;
    }
    ensure(d, n);
    memcpy(d->buf + d->pos, s, n);
    d->pos += n;
}

static const char digits2[201] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

static const uint64_t pow10_tab[20] = {1ull,
                                       10ull,
                                       100ull,
                                       1000ull,
                                       10000ull,
                                       100000ull,
                                       1000000ull,
                                       10000000ull,
                                       100000000ull,
                                       1000000000ull,
                                       10000000000ull,
                                       100000000000ull,
                                       1000000000000ull,
                                       10000000000000ull,
                                       100000000000000ull,
                                       1000000000000000ull,
                                       10000000000000000ull,
                                       100000000000000000ull,
                                       1000000000000000000ull,
                                       10000000000000000000ull};

/* Decimal: the digit count from the bit length (1233 / 4096 ~ log10 2),
 * then four digits per step written backwards in place. */
static inline char *put_u64(char *p, uint64_t v)
{
    unsigned nd = ((unsigned)(64 - __builtin_clzll(v | 1)) * 1233u) >> 12;
    nd += nd < 20 && v >= pow10_tab[nd];
    if (nd == 0)
        nd = 1;
    char *end = p + nd, *q = end;
    while (v >= 10000) {
        unsigned r = (unsigned)(v % 10000);
        v /= 10000;
        q -= 4;
        memcpy(q, dec4[r], 4);
    }
    if (v >= 100) {
        q -= 2;
        memcpy(q, digits2 + 2 * (v % 100), 2);
        v /= 100;
    }
    if (v >= 10) {
        q -= 2;
        memcpy(q, digits2 + 2 * v, 2);
    } else {
        *--q = (char)('0' + v);
    }
    return end;
}

/* Binary without leading zeros ("0" for zero). */
static inline char *put_bin(char *p, uint64_t v)
{
    if (v < 256) { /* the usual case for counters, states, occupancies */
        memcpy(p, bin_small[v], 8);
        return p + bin_small_len[v];
    }
    if (v == 0) {
        *p++ = '0';
        return p;
    }
    int nb = 64 - __builtin_clzll(v);
    int sh = ((nb - 1) >> 3) << 3;  /* bit offset of the top byte */
    int lead = nb - sh;             /* 1..8 significant bits in it */
    memcpy(p, bin8[(v >> sh) & 255] + (8 - lead), 8);
    p += lead;
    while (sh > 0) {
        sh -= 8;
        memcpy(p, bin8[(v >> sh) & 255], 8);
        p += 8;
    }
    return p;
}

static __attribute__((noinline)) void emit_enum(ks_vcd *d, const ks_vcd_var *v)
{
    const char *s = v->emitted < v->n_names && v->names[v->emitted] ? v->names[v->emitted] : "?";
    size_t n = strlen(s);
    if (n > 4096)
        n = 4096;
    ensure(d, n + 16);
    char *p = d->buf + d->pos;
    *p++ = 's';
    for (size_t i = 0; i < n; i++)
        *p++ = (s[i] == ' ' || s[i] == '\n' || s[i] == '\t') ? '_' : s[i];
    *p++ = ' ';
    memcpy(p, v->id, v->idlen);
    p += v->idlen;
    *p++ = '\n';
    d->pos = (size_t)(p - d->buf);
}

static inline void emit_value(ks_vcd *d, const ks_vcd_var *v)
{
    if (v->kind == VAR_ENUM) {
        emit_enum(d, v);
        return;
    }
    ensure(d, 96);
    char *p = d->buf + d->pos;
    if (v->kind == VAR_INT) {
        *p++ = 'b';
        p = put_bin(p, v->emitted);
    } else {
        *p++ = (char)('0' + (v->emitted & 1));
    }
    memcpy(p, v->tail, 8); /* padded: the extra bytes are overwritten next */
    p += v->tail_len;
    d->pos = (size_t)(p - d->buf);
}

static __attribute__((noinline)) int64_t scale_time(ks_time t, ks_time ts_ps) { return t / ts_ps; }

static inline __attribute__((always_inline)) void emit_time_inline(ks_vcd *d, ks_time t)
{
    /* no division for the usual 1 ps timescale (a 64-bit division costs
     * tens of cycles; the compiler would otherwise divide by 1) */
    int64_t vt = __builtin_expect(d->ts_ps == 1, 1) ? t : scale_time(t, d->ts_ps);
    if (vt == d->last_vt)
        return;
    d->last_vt = vt;
    ensure(d, 48);
    char *p = d->buf + d->pos;
    *p++ = '#';
    /* Consecutive time stamps mostly share all but their last four digits:
     * those are formatted once and copied. */
    uint64_t hi = (uint64_t)vt / 10000;
    if (hi == 0) {
        p = put_u64(p, (uint64_t)vt);
    } else {
        if (hi != d->hi_val) {
            d->hi_val = hi;
            d->hi_len = (uint8_t)(put_u64(d->hi_str, hi) - d->hi_str);
        }
        memcpy(p, d->hi_str, sizeof d->hi_str);
        p += d->hi_len;
        memcpy(p, dec4[(uint64_t)vt - hi * 10000], 4);
        p += 4;
    }
    *p++ = '\n';
    d->pos = (size_t)(p - d->buf);
}

static void emit_time(ks_vcd *d, ks_time t) { emit_time_inline(d, t); }

/* ---- header ---- */

/* Compares the scope parts (all but the last element) of two dotted names
 * element by element, so that sorting groups each scope's variables. */
static int scope_cmp(const char *a, const char *b)
{
    const char *ea = strrchr(a, '.'), *eb = strrchr(b, '.');
    size_t la = ea ? (size_t)(ea - a) : 0, lb = eb ? (size_t)(eb - b) : 0;
    size_t i = 0, j = 0;
    for (;;) {
        int enda = i >= la, endb = j >= lb;
        if (enda || endb)
            return enda && endb ? 0 : enda ? -1 : 1;
        size_t si = i, sj = j;
        while (i < la && a[i] != '.')
            i++;
        while (j < lb && b[j] != '.')
            j++;
        size_t na = i - si, nb = j - sj;
        int c = memcmp(a + si, b + sj, na < nb ? na : nb);
        if (c)
            return c;
        if (na != nb)
            return na < nb ? -1 : 1;
        if (i < la)
            i++;
        if (j < lb)
            j++;
    }
}

static int var_cmp(const void *pa, const void *pb)
{
    const ks_vcd_var *a = *(ks_vcd_var *const *)pa, *b = *(ks_vcd_var *const *)pb;
    int c = scope_cmp(a->name, b->name);
    if (c)
        return c;
    return a->order < b->order ? -1 : a->order > b->order;
}

static void write_header(ks_vcd *d)
{
    d->header_done = 1;
    /* the declarations are final: room for every variable in the dirty list
     * (each is in it at most once), so ks_vcd_set need not check */
    if (d->cap_dirty < d->n_vars) {
        size_t n = n_dirty(d);
        d->cap_dirty = d->n_vars;
        d->dirty = ks__xrealloc(d->dirty, d->cap_dirty * sizeof *d->dirty);
        d->dirty_end = d->dirty + n;
    }
    put_str(d, "$version rtsim kernel VCD writer $end\n$timescale ");
    put_str(d, d->ts_str);
    put_str(d, " $end\n");
    ks_vcd_var **sorted = ks__xmalloc((d->n_vars + 1) * sizeof *sorted);
    if (d->n_vars)
        memcpy(sorted, d->vars, d->n_vars * sizeof *sorted);
    qsort(sorted, d->n_vars, sizeof *sorted, var_cmp);
    /* stack of open scopes as (start, length) into the current var name */
    char open_scope[4096] = "";
    size_t open_len = 0; /* length of the dotted scope path that is open */
    int depth = 0;
    char line[4608];
    for (unsigned k = 0; k < d->n_vars; k++) {
        const ks_vcd_var *v = sorted[k];
        const char *dot = strrchr(v->name, '.');
        size_t slen = dot ? (size_t)(dot - v->name) : 0;
        if (slen >= sizeof open_scope)
            slen = sizeof open_scope - 1;
        /* common prefix in whole elements */
        size_t common = 0, i = 0;
        while (i < slen && i < open_len && v->name[i] == open_scope[i]) {
            i++;
            if ((i == slen || v->name[i] == '.') && (i == open_len || open_scope[i] == '.'))
                common = i;
        }
        /* close scopes beyond `common` */
        int keep = 0;
        for (size_t q = 0; q < common; q++)
            keep += open_scope[q] == '.';
        if (common)
            keep++;
        for (; depth > keep; depth--)
            put_str(d, "$upscope $end\n");
        /* open the rest */
        size_t pos = common;
        while (pos < slen) {
            if (v->name[pos] == '.')
                pos++;
            size_t e = pos;
            while (e < slen && v->name[e] != '.')
                e++;
            snprintf(line, sizeof line, "$scope module %.*s $end\n", (int)(e - pos), v->name + pos);
            put_str(d, line);
            depth++;
            pos = e;
        }
        memcpy(open_scope, v->name, slen);
        open_scope[slen] = 0;
        open_len = slen;
        const char *leaf = dot ? dot + 1 : v->name;
        const char *type = v->kind == VAR_BIT ? "wire" : v->kind == VAR_INT ? "reg" : "string";
        unsigned w = v->kind == VAR_ENUM ? 1 : v->width;
        snprintf(line, sizeof line, "$var %s %u %.*s %s $end\n", type, w, (int)v->idlen, v->id,
                 leaf);
        put_str(d, line);
    }
    for (; depth > 0; depth--)
        put_str(d, "$upscope $end\n");
    put_str(d, "$enddefinitions $end\n");
    free(sorted);
}

/* Enters the window: header if needed, then every value at window_begin. */
static void start_window(ks_vcd *d)
{
    if (!d->header_done)
        write_header(d);
    d->started = 1;
    emit_time(d, d->begin);
    put_str(d, "$dumpvars\n");
    for (unsigned i = 0; i < d->n_vars; i++)
        emit_value(d, d->vars[i]);
    put_str(d, "$end\n");
}

/* Writes out the changes recorded at d->cur_t: only variables whose value
 * at the end of that time differs from the one last written (glitches
 * within one time stamp vanish, as in a sampled waveform). */
static inline void sample(ks_vcd_var *v)
{
    if (v->src)
        v->value = *v->src;
}

static void flush_dirty(ks_vcd *d)
{
    ks_time t = d->cur_t;
    if (t < d->begin || d->ended) {
        for (ks_vcd_var **v = d->dirty; v < d->dirty_end; v++) {
            sample(*v);
            (*v)->emitted = (*v)->value;
        }
        d->dirty_end = d->dirty;
        return;
    }
    if (!d->started && t == d->begin) {
        /* changes at the first time of the window go into its $dumpvars */
        for (ks_vcd_var **v = d->dirty; v < d->dirty_end; v++) {
            sample(*v);
            (*v)->emitted = (*v)->value;
        }
        d->dirty_end = d->dirty;
        start_window(d);
        return;
    }
    if (!d->started)
        start_window(d);
    if (t >= d->end) {
        emit_time(d, d->end);
        d->ended = 1;
        d->dirty_end = d->dirty;
        return;
    }
    ks_vcd_var **list = d->dirty;
    unsigned n = n_dirty(d), i = 0;
    d->dirty_end = d->dirty;
    for (; i < n; i++) { /* up to the first real change */
        ks_vcd_var *v = list[i];
        if ((v->src ? *v->src : v->value) != v->emitted)
            break;
    }
    if (i == n)
        return;
    emit_time_inline(d, t);
    /* Bit and integer lines take at most VCD_LINE bytes: room for a chunk of
     * them is made once, enumerations (any length) make their own. */
    while (i < n) {
        unsigned chunk_end = n - i > VCD_CHUNK ? i + VCD_CHUNK : n;
        ensure(d, (size_t)(chunk_end - i) * VCD_LINE);
        char *p = d->buf + d->pos;
        for (; i < chunk_end; i++) {
            ks_vcd_var *v = list[i];
            uint64_t val = v->src ? *v->src : v->value;
            if (val == v->emitted)
                continue;
            v->emitted = val;
            if (v->kind == VAR_INT) {
                *p++ = 'b';
                p = put_bin(p, val);
            } else if (v->kind == VAR_BIT) {
                *p++ = (char)('0' + (val & 1));
            } else {
                d->pos = (size_t)(p - d->buf);
                emit_enum(d, v);
                ensure(d, (size_t)(chunk_end - i) * VCD_LINE);
                p = d->buf + d->pos;
                continue;
            }
            memcpy(p, v->tail, 8); /* padded: the extra bytes are overwritten next */
            p += v->tail_len;
        }
        d->pos = (size_t)(p - d->buf);
    }
}

/* First change of a new time stamp: write out the previous one. */
static __attribute__((noinline)) void new_time(ks_vcd *d, ks_time now)
{
    if (d->dirty_end != d->dirty)
        flush_dirty(d);
    d->cur_t = now;
    if (!d->header_done)
        write_header(d); /* freezes the declarations */
}

void ks__vcd_list_slow(ks_vcd_var *v, ks_time now)
{
    ks_vcd *d = v->vcd;
    if (now != d->cur_t || !d->header_done)
        new_time(d, now);
    *d->dirty_end++ = v; /* room for every variable once the header is out */
}

static __attribute__((noinline)) void grow_dirty(ks_vcd *d)
{
    size_t n = n_dirty(d);
    d->cap_dirty *= 2;
    d->dirty = ks__xrealloc(d->dirty, d->cap_dirty * sizeof *d->dirty);
    d->dirty_end = d->dirty + n;
}

void ks__vcd_set(ks_vcd_var *v, uint64_t value)
{
    value &= v->mask;
    if (value == v->value)
        return;
    ks_vcd *d = v->vcd;
    ks_time now = *d->now;
    if (now != d->cur_t || !d->header_done)
        new_time(d, now);
    v->value = value;
    if (v->stamp != now) {
        v->stamp = now;
        if (n_dirty(d) == d->cap_dirty)
            grow_dirty(d);
        *d->dirty_end++ = v;
    }
}

/* ---- declarations ---- */

static int glob_match(const char *p, const char *pe, const char *s)
{
    while (p < pe) {
        if (*p == '*') {
            while (p < pe && *p == '*')
                p++;
            if (p == pe)
                return 1;
            for (; *s; s++)
                if (glob_match(p, pe, s))
                    return 1;
            return 0;
        }
        if (!*s || (*p != '?' && *p != *s))
            return 0;
        p++;
        s++;
    }
    return *s == 0;
}

static int filter_ok(const ks_vcd *d, const char *name)
{
    if (!d->n_pats)
        return 1;
    for (unsigned i = 0; i < d->n_pats; i++)
        if (glob_match(d->pats[i], d->pats[i] + strlen(d->pats[i]), name))
            return 1;
    return 0;
}

static ks_vcd_var *declare(ks_vcd *d, const char *name, int kind, unsigned width, uint64_t init)
{
    if (!d || !name || !*name || d->header_done || !filter_ok(d, name))
        return NULL;
    for (const char *c = name; *c; c++)
        if (*c == ' ' || *c == '\t' || *c == '\n')
            return NULL; /* VCD identifiers cannot hold white space */
    ks_vcd_var *v = ks__xcalloc(1, sizeof *v);
    v->vcd = d;
    v->kind = (uint8_t)kind;
    v->width = width;
    v->mask = width >= 64 ? UINT64_MAX : (((uint64_t)1 << width) - 1);
    v->value = v->emitted = init & v->mask;
    v->stamp = -1;
    v->name = ks__xstrdup(name);
    v->order = d->n_vars;
    unsigned n = d->n_vars;
    int len = 0;
    do {
        v->id[len++] = (char)('!' + n % 94);
        n /= 94;
    } while (n && len < 5);
    v->idlen = (uint8_t)len;
    int tl = 0;
    if (kind == VAR_INT)
        v->tail[tl++] = ' ';
    memcpy(v->tail + tl, v->id, (size_t)len);
    tl += len;
    v->tail[tl++] = '\n';
    v->tail_len = (uint8_t)tl;
    KS_GROW(d->vars, d->n_vars, d->cap_vars);
    d->vars[d->n_vars++] = v;
    return v;
}

ks_vcd_var *ks_vcd_var_bit(ks_vcd *d, const char *name, int init)
{
    return declare(d, name, VAR_BIT, 1, init ? 1 : 0);
}

ks_vcd_var *ks_vcd_var_int(ks_vcd *d, const char *name, unsigned width, uint64_t init)
{
    if (width < 1 || width > 64)
        return NULL;
    return declare(d, name, VAR_INT, width, init);
}

ks_vcd_var *ks_vcd_var_enum(ks_vcd *d, const char *name, const char *const *names, unsigned n,
                            unsigned init)
{
    if (!names || n == 0)
        return NULL;
    ks_vcd_var *v = declare(d, name, VAR_ENUM, 64, init);
    if (v) {
        v->names = names;
        v->n_names = n;
    }
    return v;
}

void ks__vcd_trace_fifo(ks_vcd *d, ks_fifo *f)
{
    char name[600];
    snprintf(name, sizeof name, "%s.occupancy", f->name);
    f->vcd_occ = ks_vcd_var_int(d, name, 32, f->count);
    if (f->vcd_occ) {
        f->vcd_occ->src = &f->count; /* sampled: the FIFO lists it, no value per change */
        f->vcd_listed = -1;
    }
}

void ks__vcd_trace_signal(ks_vcd *d, ks_signal *s)
{
    s->vcd_var = s->width == 1 ? ks_vcd_var_bit(d, s->name, (int)s->cur)
                               : ks_vcd_var_int(d, s->name, s->width, s->cur);
}

/* ---- open / close ---- */

static int parse_timescale(const char *s, ks_time *ps)
{
    if (!s || !*s)
        s = "1ps";
    char *end;
    long n = strtol(s, &end, 10);
    if (n != 1 && n != 10 && n != 100)
        return -1;
    while (*end == ' ')
        end++;
    ks_time unit;
    if (!strcmp(end, "ps"))
        unit = 1;
    else if (!strcmp(end, "ns"))
        unit = 1000;
    else if (!strcmp(end, "us"))
        unit = 1000000;
    else if (!strcmp(end, "ms"))
        unit = 1000000000;
    else if (!strcmp(end, "s"))
        unit = 1000000000000;
    else
        return -1;
    *ps = n * unit;
    return 0;
}

ks_vcd *ks_vcd_open(ks_sim *sim, const char *path, const char *timescale, ks_time window_begin,
                    ks_time window_end, const char *filter)
{
    ks_time ts;
    if (!path || !*path) {
        ks__set_error(sim, "VCD: no output path given");
        return NULL;
    }
    if (sim->vcd) {
        ks__set_error(sim, "VCD %s: a writer is already open on this simulation", path);
        return NULL;
    }
    if (parse_timescale(timescale, &ts)) {
        ks__set_error(sim, "VCD %s: timescale '%s' invalid (allowed: 1|10|100 followed by s, ms, us, ns or ps)",
                      path, timescale);
        return NULL;
    }
    if (window_begin < 0 || window_end <= window_begin) {
        ks__set_error(sim, "VCD %s: time window [%lld, %lld) ps is empty or negative", path,
                      (long long)window_begin, (long long)window_end);
        return NULL;
    }
    init_tables();
    ks_vcd *d = ks__xcalloc(1, sizeof *d);
    d->sim = sim;
    d->now = &sim->now;
    d->cur_t = -1; /* no time stamp yet: every set goes through new_time */
    d->path = ks__xstrdup(path);
    /* the tool planned the path with its other outputs (checked, reserved
     * before the run); a caller that did not gets a plan here */
    char oerr[512];
    d->out = ks_out_find(path, "--vcd");
    if (!d->out)
        d->out = ks_out_plan("VCD", path, oerr, sizeof oerr);
    d->f = d->out ? ks_out_begin(d->out, oerr, sizeof oerr) : NULL;
    if (!d->f) {
        ks__set_error(sim, "%s", oerr);
        if (d->out)
            ks_out_discard(d->out);
        free(d->path);
        free(d);
        return NULL;
    }
    d->ts_ps = ts;
    snprintf(d->ts_str, sizeof d->ts_str, "%s", timescale && *timescale ? timescale : "1ps");
    d->begin = window_begin;
    d->end = window_end;
    d->last_vt = -1;
    d->buf = ks__xmalloc(VCD_BUF);
    d->cap_dirty = 64;
    d->dirty = d->dirty_end = ks__xmalloc(d->cap_dirty * sizeof *d->dirty);
    if (filter && *filter) {
        const char *p = filter;
        while (*p) {
            const char *e = strchr(p, ',');
            size_t n = e ? (size_t)(e - p) : strlen(p);
            while (n && *p == ' ')
                p++, n--;
            while (n && p[n - 1] == ' ')
                n--;
            if (n) {
                d->pats = ks__xrealloc(d->pats, (d->n_pats + 1) * sizeof *d->pats);
                char *s = ks__xmalloc(n + 1);
                memcpy(s, p, n);
                s[n] = 0;
                d->pats[d->n_pats++] = s;
            }
            if (!e)
                break;
            p = e + 1;
        }
    }
    sim->vcd = d;
    for (size_t i = 0; i < sim->n_fifos; i++)
        ks__vcd_trace_fifo(d, sim->fifos[i]);
    for (size_t i = 0; i < sim->n_signals; i++)
        ks__vcd_trace_signal(d, sim->signals[i]);
    return d;
}

void ks__vcd_finish(ks_vcd *d)
{
    if (!d->header_done)
        write_header(d);
    if (d->dirty_end != d->dirty)
        flush_dirty(d);
    ks_time now = *d->now;
    if (!d->started && now >= d->begin)
        start_window(d);
    if (d->started && !d->ended)
        emit_time(d, now < d->end ? now : d->end);
    flush_buf(d);
}

void ks_vcd_discard(ks_vcd *d)
{
    if (!d)
        return;
    d->discard = 1;
    ks_vcd_close(d);
}

int ks_vcd_close(ks_vcd *d)
{
    if (!d)
        return 0;
    ks_sim *sim = d->sim;
    if (!d->discard)
        ks__vcd_finish(d);
    int rc = 0;
    char oerr[512];
    if (d->discard) {
        ks_out_discard(d->out);
    } else if (d->io_error) {
        ks__set_error(sim, "VCD %s: write error (disk full?)", d->path);
        ks_out_discard(d->out);
        rc = -1;
    } else if (ks_out_commit(d->out, oerr, sizeof oerr) != 0) {
        ks__set_error(sim, "%s", oerr);
        rc = -1;
    }
    for (size_t i = 0; i < sim->n_fifos; i++) {
        sim->fifos[i]->vcd_occ = NULL;
        sim->fifos[i]->vcd_listed = KS_TIME_MAX;
    }
    for (size_t i = 0; i < sim->n_signals; i++)
        sim->signals[i]->vcd_var = NULL;
    sim->vcd = NULL;
    for (unsigned i = 0; i < d->n_vars; i++) {
        free(d->vars[i]->name);
        free(d->vars[i]);
    }
    for (unsigned i = 0; i < d->n_pats; i++)
        free(d->pats[i]);
    free(d->pats);
    free(d->dirty);
    free(d->vars);
    free(d->buf);
    free(d->path);
    free(d);
    return rc;
}

ks_vcd *ks_sim_vcd(const ks_sim *sim) { return sim->vcd; }
uint64_t ks_vcd_bytes(const ks_vcd *d) { return d->flushed + d->pos; }
unsigned ks_vcd_var_count(const ks_vcd *d) { return d->n_vars; }
