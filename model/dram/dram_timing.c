/* dram_timing.c — loads a DRAM standard (dram_timing.h) from an INI file with
 * the shared INI reader (config/ini_file.h), applies --set overrides,
 * evaluates expressions, validates ranges. */
#include "model/dram/dram_timing.h"

#include "config/ini_file.h"
#include "model/dram/dram_addrmap.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *const dram_cmd_name[DRAM_NCMD] = {"ACT", "PRE", "PREA", "RD", "WR", "REF"};
const char *const dram_scope_name[DRAM_NSCOPE] = {"channel", "rank", "bank", "sibling"};

int dram_cmd_from_name(const char *name)
{
    for (int c = 0; c < DRAM_NCMD; c++)
        if (strcmp(name, dram_cmd_name[c]) == 0)
            return c;
    return -1;
}


/* ---- raw entries of the file (section, key, value, line) ---- */
#define MAX_ENTRIES DRAM_MAX_ENTRIES
#define VAL_LEN DRAM_VALUE_LEN
typedef struct entry {
    char section[DRAM_NAME_LEN];
    char key[DRAM_KEY_LEN];
    char value[VAL_LEN];
    int line;          /* line in the file; 0 = from an override */
    const char *set;   /* the override text when line == 0 */
    const char *origin; /* where the override came from, for messages (NULL: "--set TEXT") */
} entry;

typedef struct loader {
    const char *path;
    entry e[MAX_ENTRIES];
    int n;
    char *err;
    size_t errlen;
    int failed;
} loader;

static void fail(loader *L, const char *fmt, ...)
{
    if (L->failed++)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(L->err, L->errlen, fmt, ap);
    va_end(ap);
}

/* Where an entry came from, for messages: "file:line" or "--set text"; a
 * path is held whole (PATH_MAX and the line or the --set text). */
#define DRAM_WHERE_MAX (4096 + 256)
static const char *where(const loader *L, const entry *e, char *buf, size_t n)
{
    if (e->line > 0)
        snprintf(buf, n, "%s:%d", L->path, e->line);
    else if (e->origin)
        snprintf(buf, n, "%s", e->origin);
    else
        snprintf(buf, n, "--set %s", e->set);
    return buf;
}

/* Keeps the file's entries (ini_file refuses a key given twice); --set
 * overrides and the evaluation come after the whole file has read. */
static int handler(ini_file *f, void *user, const char *section, const char *name, const char *value)
{
    loader *L = user;
    if (L->n == MAX_ENTRIES)
        return ini_file_error(f, "too many entries (at most %d)", MAX_ENTRIES);
    if (strlen(section) >= DRAM_NAME_LEN || strlen(name) >= sizeof L->e[0].key || strlen(value) >= VAL_LEN)
        return ini_file_error(f, "section, key or value too long");
    entry *e = &L->e[L->n++];
    snprintf(e->section, sizeof e->section, "%s", section);
    snprintf(e->key, sizeof e->key, "%s", name);
    snprintf(e->value, sizeof e->value, "%s", value);
    e->line = ini_file_line(f);
    e->set = NULL;
    return 0;
}

/* ---- integer expressions: sum of products of integers, names, parentheses ---- */
typedef struct expr {
    const char *s;
    const dram_spec *spec;
    int nparams;       /* names visible: the first nparams parameters */
    char msg[128];
} expr;

static void skip_ws(expr *x) { while (isspace((unsigned char)*x->s)) x->s++; }
static int parse_sum(expr *x, long *out);

static int parse_atom(expr *x, long *out)
{
    skip_ws(x);
    if (*x->s == '(') {
        x->s++;
        if (parse_sum(x, out))
            return -1;
        skip_ws(x);
        if (*x->s != ')') {
            snprintf(x->msg, sizeof x->msg, "missing ')'");
            return -1;
        }
        x->s++;
        return 0;
    }
    if (*x->s == '-') {
        x->s++;
        if (parse_atom(x, out))
            return -1;
        *out = -*out;
        return 0;
    }
    if (isdigit((unsigned char)*x->s)) {
        errno = 0;
        char *end;
        long v = strtol(x->s, &end, 10);
        if (errno || v > 100000000L) {
            snprintf(x->msg, sizeof x->msg, "number too large");
            return -1;
        }
        x->s = end;
        *out = v;
        return 0;
    }
    if (isalpha((unsigned char)*x->s) || *x->s == '_') {
        char name[DRAM_NAME_LEN];
        size_t n = 0;
        while ((isalnum((unsigned char)*x->s) || *x->s == '_') && n + 1 < sizeof name)
            name[n++] = *x->s++;
        name[n] = 0;
        for (int i = 0; i < x->nparams; i++)
            if (strcmp(x->spec->param_name[i], name) == 0) {
                *out = x->spec->param_value[i];
                return 0;
            }
        snprintf(x->msg, sizeof x->msg, "unknown name '%s' (names must be defined earlier in [timing])", name);
        return -1;
    }
    snprintf(x->msg, sizeof x->msg, "expected a number, a name or '(' at '%.20s'", x->s);
    return -1;
}

static int parse_product(expr *x, long *out)
{
    if (parse_atom(x, out))
        return -1;
    for (;;) {
        skip_ws(x);
        if (*x->s != '*')
            return 0;
        x->s++;
        long r;
        if (parse_atom(x, &r))
            return -1;
        *out *= r;
        if (*out > 100000000L || *out < -100000000L) {
            snprintf(x->msg, sizeof x->msg, "value too large");
            return -1;
        }
    }
}

static int parse_sum(expr *x, long *out)
{
    if (parse_product(x, out))
        return -1;
    for (;;) {
        skip_ws(x);
        char op = *x->s;
        if (op != '+' && op != '-')
            return 0;
        x->s++;
        long r;
        if (parse_product(x, &r))
            return -1;
        *out = op == '+' ? *out + r : *out - r;
    }
}

/* Evaluates e->value; on error reports it with the entry's location. */
static int eval(loader *L, const dram_spec *spec, int nparams, const entry *e, long lo, long hi, long *out)
{
    char w[DRAM_WHERE_MAX];
    expr x = {.s = e->value, .spec = spec, .nparams = nparams, .msg = ""};
    if (parse_sum(&x, out) == 0) {
        skip_ws(&x);
        if (*x.s)
            snprintf(x.msg, sizeof x.msg, "unexpected '%.20s'", x.s);
    }
    if (x.msg[0]) {
        fail(L, "%s: [%s] %s = '%s': %s", where(L, e, w, sizeof w), e->section, e->key, e->value, x.msg);
        return -1;
    }
    if (*out < lo || *out > hi) {
        fail(L, "%s: [%s] %s = %ld out of range, allowed %ld..%ld", where(L, e, w, sizeof w), e->section, e->key,
             *out, lo, hi);
        return -1;
    }
    return 0;
}

/* ---- known scalar keys ---- */
typedef struct known {
    const char *section, *key;
    long lo, hi;
    size_t offset;     /* int field in dram_spec */
} known;

#define K(sec, key, lo, hi, field) {sec, key, lo, hi, offsetof(dram_spec, field)}
static const known known_keys[] = {
    K("organization", "channels", 1, 16, channels),
    K("organization", "ranks", 1, 8, ranks),
    K("organization", "banks", 1, 64, banks),
    K("organization", "rows", 1, 1 << 20, rows),
    K("organization", "columns", 8, 1 << 16, columns),
    K("organization", "dq_bits", 4, 512, dq_bits),
    K("organization", "prefetch", 1, 64, prefetch),
    K("organization", "tck_ps", 100, 100000, tck_ps),
    K("controller", "read_queue", 1, 4096, read_queue),
    K("controller", "write_queue", 1, 4096, write_queue),
    K("controller", "row_hit_cap", 0, 1000000, row_hit_cap),
    K("controller", "write_high_pct", 0, 100, write_high_pct),
    K("controller", "write_low_pct", 0, 100, write_low_pct),
    K("controller", "read_latency", 1, 100000, read_latency),
    K("controller", "refresh_interval", 1, 10000000, refresh_interval),
    K("controller", "max_postponed_refresh", 0, 64, max_postponed_refresh),
};
#define NKNOWN (int)(sizeof known_keys / sizeof known_keys[0])

/* [timing] names of JEDEC latencies (JESD209-3 LPDDR3, Ramulator's LPDDR3.h
 * speed table): each is a positive number of clocks, so 0 is refused (nCL
 * or nBL = 0 once ran as if data took no time). Other names (nDQSCK,
 * user-defined helpers) may be 0. */
static int is_jedec_latency(const char *name)
{
    static const char *const names[] = {"nBL", "nCCD", "nCL", "nCWL", "nRCD", "nRP", "nRPpb", "nRPab",
                                        "nRAS", "nRC", "nWR", "nRTP", "nWTR", "nRRD", "nFAW", "nRFC",
                                        "nRFCab", "nRFCpb", "nREFI"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (!strcmp(name, names[i]))
            return 1;
    return 0;
}

static int is_pow2(int v) { return v > 0 && (v & (v - 1)) == 0; }

/* The ranges of eval() calls below: [timing] 0..10000000, [constraints] 0..1000000. */
void dram_spec_describe_key(const char *section, const char *key, char *buf, size_t len)
{
    for (int j = 0; j < NKNOWN; j++)
        if (strcmp(known_keys[j].section, section) == 0 && strcmp(known_keys[j].key, key) == 0) {
            snprintf(buf, len, "integer expression %ld..%ld", known_keys[j].lo, known_keys[j].hi);
            return;
        }
    if (strcmp(section, "timing") == 0)
        snprintf(buf, len, "integer expression 0..10000000 (DRAM cycles)");
    else if (strcmp(section, "constraints") == 0)
        snprintf(buf, len, "integer expression 0..1000000 (DRAM cycles)");
    else if (strcmp(section, "controller") == 0 && strcmp(key, "mapping") == 0)
        snprintf(buf, len, "address mapping, e.g. RoBaRaCoCh");
    else
        snprintf(buf, len, "unknown key");
}

/* "<scope> <FROM> -> <TO> [window N]" */
static int parse_constraint_key(const char *key, dram_constraint *c, char *why, size_t n)
{
    char scope[32], from[16], arrow[8], to[16], wword[16];
    int window = 1, consumed = 0;
    int k = sscanf(key, "%31s %15s %7s %15s %n", scope, from, arrow, to, &consumed);
    if (k < 4 || strcmp(arrow, "->") != 0) {
        snprintf(why, n, "expected '<scope> <FROM> -> <TO> [window N]'");
        return -1;
    }
    const char *rest = key + consumed;
    if (*rest) {
        /* strtol, not sscanf's %d: that has no defined result when N does not
         * fit an int (glibc wraps it: "window 4294967300" was taken as 4) */
        int c2 = 0;
        long w = 0;
        char *end = NULL;
        if (sscanf(rest, "%15s %n", wword, &c2) == 1 && strcmp(wword, "window") == 0) {
            errno = 0;
            w = strtol(rest + c2, &end, 10);
            if (end == rest + c2)
                end = NULL;
            else
                while (isspace((unsigned char)*end))
                    end++;
        }
        if (!end || *end) {
            snprintf(why, n, "trailing text '%s' (only 'window N' allowed)", rest);
            return -1;
        }
        if (errno || w < 1 || w > DRAM_MAX_WINDOW) {
            snprintf(why, n, "window %.20s out of range, allowed 1..%d", rest + c2, DRAM_MAX_WINDOW);
            return -1;
        }
        window = (int)w;
    }
    int s = -1;
    for (int i = 0; i < DRAM_NSCOPE; i++)
        if (strcmp(scope, dram_scope_name[i]) == 0)
            s = i;
    if (s < 0) {
        snprintf(why, n, "unknown scope '%s' (channel, rank, bank, sibling)", scope);
        return -1;
    }
    int f = dram_cmd_from_name(from), t = dram_cmd_from_name(to);
    if (f < 0 || t < 0) {
        snprintf(why, n, "unknown command '%s' (ACT PRE PREA RD WR REF)", f < 0 ? from : to);
        return -1;
    }
    if ((s == DRAM_SCOPE_BANK || s == DRAM_SCOPE_SIBLING) && window > 1) {
        snprintf(why, n, "window > 1 is only supported for channel and rank scope");
        return -1;
    }
    if ((s == DRAM_SCOPE_BANK || s == DRAM_SCOPE_SIBLING) && (!dram_cmd_is_bank_scoped(f) || !dram_cmd_is_bank_scoped(t))) {
        snprintf(why, n, "bank/sibling scope needs bank commands (ACT PRE RD WR)");
        return -1;
    }
    c->scope = (uint8_t)s;
    c->from = (uint8_t)f;
    c->to = (uint8_t)t;
    c->window = (uint8_t)window;
    return 0;
}

static int apply_set(loader *L, const char *set, const char *origin)
{
    const char *eq = strchr(set, '=');
    const char *dot = strchr(set, '.');
    if (!eq || !dot || dot > eq) {
        fail(L, "%s%s: expected section.key=value (e.g. timing.nCL=12)", origin ? "" : "--set ", origin ? origin : set);
        return -1;
    }
    char section[DRAM_NAME_LEN], key[64];
    size_t ls = (size_t)(dot - set), lk = (size_t)(eq - dot - 1);
    if (ls >= sizeof section || lk >= sizeof key || strlen(eq + 1) >= VAL_LEN) {
        fail(L, "%s%s: too long", origin ? "" : "--set ", origin ? origin : set);
        return -1;
    }
    memcpy(section, set, ls);
    section[ls] = 0;
    memcpy(key, dot + 1, lk);
    key[lk] = 0;
    for (int i = 0; i < L->n; i++)
        if (strcmp(L->e[i].section, section) == 0 && strcmp(L->e[i].key, key) == 0) {
            snprintf(L->e[i].value, VAL_LEN, "%s", eq + 1);
            L->e[i].line = 0;
            L->e[i].set = set;
            L->e[i].origin = origin;
            return 0;
        }
    /* list the keys of the section for the message */
    char keys[600] = "";
    size_t used = 0;
    for (int i = 0; i < L->n && used + 40 < sizeof keys; i++)
        if (strcmp(L->e[i].section, section) == 0)
            used += (size_t)snprintf(keys + used, sizeof keys - used, "%s%s", used ? ", " : "", L->e[i].key);
    char w[DRAM_WHERE_MAX];
    if (origin)
        snprintf(w, sizeof w, "%s", origin);
    else
        snprintf(w, sizeof w, "--set %s", set);
    fail(L, "%s: unknown key '%s.%s' (keys of [%s] in %s: %s)", w, section, key, section, L->path,
         used ? keys : "none: sections are organization, timing, constraints, controller");
    return -1;
}

int dram_spec_param(const dram_spec *spec, const char *name)
{
    for (int i = 0; i < spec->nparams; i++)
        if (strcmp(spec->param_name[i], name) == 0)
            return spec->param_value[i];
    return -1;
}

/* Reads the file's entries into L and applies the overrides. */
static int read_entries(loader *L, const char *path, const char *const *sets, const char *const *origins, int nsets,
                        char *err, size_t errlen)
{
    memset(L, 0, sizeof *L);
    L->path = path;
    L->err = err;
    L->errlen = errlen;
    err[0] = 0;
    static const ini_file_opts opts = {.what = "a DRAM parameter", .example = "organization"};
    if (ini_file_read(path, &opts, handler, L, err, errlen))
        return -1;
    for (int i = 0; i < nsets; i++)
        if (apply_set(L, sets[i], origins ? origins[i] : NULL))
            return -1;
    return 0;
}

int dram_spec_entries(const char *path, const char *const *sets, int nsets, dram_entry_fn fn, void *user, char *err,
                      size_t errlen)
{
    static loader L; /* large; not reentrant across threads (loading is single-threaded) */
    if (read_entries(&L, path, sets, NULL, nsets, err, errlen))
        return -1;
    for (int i = 0; i < L.n; i++)
        fn(user, L.e[i].section, L.e[i].key, L.e[i].value);
    return 0;
}

int dram_spec_load(dram_spec *spec, const char *path, const char *const *sets, int nsets, char *err, size_t errlen)
{
    return dram_spec_load_from(spec, path, sets, NULL, nsets, err, errlen);
}

int dram_spec_load_from(dram_spec *spec, const char *path, const char *const *sets, const char *const *origins,
                        int nsets, char *err, size_t errlen)
{
    static loader L; /* large; not reentrant across threads (loading is single-threaded) */
    memset(spec, 0, sizeof *spec);
    if (read_entries(&L, path, sets, origins, nsets, err, errlen))
        return -1;
    snprintf(spec->source, sizeof spec->source, "%s", path);

    char w[DRAM_WHERE_MAX];
    /* pass 1: [timing] in file order (expressions see earlier names) */
    for (int i = 0; i < L.n; i++) {
        entry *e = &L.e[i];
        if (strcmp(e->section, "timing") != 0)
            continue;
        if (spec->nparams == DRAM_MAX_PARAMS) {
            fail(&L, "%s: too many [timing] parameters (at most %d)", where(&L, e, w, sizeof w), DRAM_MAX_PARAMS);
            return -1;
        }
        const char *k = e->key;
        int ok = (isalpha((unsigned char)k[0]) || k[0] == '_') && strlen(k) < DRAM_NAME_LEN;
        for (const char *p = k; ok && *p; p++)
            ok = isalnum((unsigned char)*p) || *p == '_';
        if (!ok) {
            fail(&L, "%s: [timing] name '%s' must be an identifier", where(&L, e, w, sizeof w), k);
            return -1;
        }
        long v;
        if (eval(&L, spec, spec->nparams, e, is_jedec_latency(k) ? 1 : 0, 10000000, &v))
            return -1;
        /* the precision states the length checked above (gcc -O0 cannot see it: -Wformat-truncation) */
        snprintf(spec->param_name[spec->nparams], DRAM_NAME_LEN, "%.*s", DRAM_NAME_LEN - 1, k);
        spec->param_value[spec->nparams++] = (int)v;
    }
    /* pass 2: everything else */
    int seen[NKNOWN] = {0};
    int have_mapping = 0;
    for (int i = 0; i < L.n; i++) {
        entry *e = &L.e[i];
        if (strcmp(e->section, "timing") == 0)
            continue;
        if (strcmp(e->section, "constraints") == 0) {
            dram_constraint c;
            char why[160];
            if (parse_constraint_key(e->key, &c, why, sizeof why)) {
                fail(&L, "%s: [constraints] '%s': %s", where(&L, e, w, sizeof w), e->key, why);
                return -1;
            }
            if (spec->nconstraints == DRAM_MAX_CONSTRAINTS) {
                fail(&L, "%s: too many constraints (at most %d)", where(&L, e, w, sizeof w), DRAM_MAX_CONSTRAINTS);
                return -1;
            }
            long v;
            if (eval(&L, spec, spec->nparams, e, 0, 1000000, &v))
                return -1;
            c.cycles = (int32_t)v;
            spec->constraint[spec->nconstraints++] = c;
            continue;
        }
        if (strcmp(e->section, "controller") == 0 && strcmp(e->key, "mapping") == 0) {
            /* a longer value cannot be valid (dram_addrmap wants 10 characters): cut it, the
             * mapping check rejects it (explicit precision: -Wformat-truncation at -O0) */
            snprintf(spec->mapping, sizeof spec->mapping, "%.*s", (int)sizeof spec->mapping - 1, e->value);
            have_mapping = 1;
            continue;
        }
        int k = -1;
        for (int j = 0; j < NKNOWN; j++)
            if (strcmp(known_keys[j].section, e->section) == 0 && strcmp(known_keys[j].key, e->key) == 0)
                k = j;
        if (k < 0) {
            fail(&L, "%s: unknown key [%s] %s", where(&L, e, w, sizeof w), e->section, e->key);
            return -1;
        }
        long v;
        if (eval(&L, spec, spec->nparams, e, known_keys[k].lo, known_keys[k].hi, &v))
            return -1;
        *(int *)((char *)spec + known_keys[k].offset) = (int)v;
        seen[k] = 1;
    }
    for (int j = 0; j < NKNOWN; j++)
        if (!seen[j]) {
            snprintf(err, errlen, "%s: missing key [%s] %s (allowed %ld..%ld)", path, known_keys[j].section,
                     known_keys[j].key, known_keys[j].lo, known_keys[j].hi);
            return -1;
        }
    if (!have_mapping) {
        snprintf(err, errlen, "%s: missing key [controller] mapping (e.g. RoBaRaCoCh)", path);
        return -1;
    }
    if (!is_pow2(spec->channels) || !is_pow2(spec->ranks) || !is_pow2(spec->banks) || !is_pow2(spec->rows) ||
        !is_pow2(spec->columns) || !is_pow2(spec->prefetch) || spec->columns < spec->prefetch) {
        snprintf(err, errlen, "%s: [organization] channels, ranks, banks, rows, columns, prefetch must be powers of two"
                 " and columns >= prefetch", path);
        return -1;
    }
    if ((spec->dq_bits * spec->prefetch) % 8 || !is_pow2(spec->dq_bits * spec->prefetch / 8)) {
        snprintf(err, errlen, "%s: [organization] dq_bits*prefetch/8 (burst bytes) must be a power of two", path);
        return -1;
    }
    spec->tx_bytes = spec->dq_bits * spec->prefetch / 8;
    if (spec->write_low_pct > spec->write_high_pct) {
        snprintf(err, errlen, "%s: [controller] write_low_pct %d must be <= write_high_pct %d", path,
                 spec->write_low_pct, spec->write_high_pct);
        return -1;
    }
    dram_addrmap map;
    if (dram_addrmap_init(&map, spec, err, errlen))
        return -1;
    return 0;
}
