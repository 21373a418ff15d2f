/* config.c — rtcfg: INI files through inih, overrides, schema validation.
 * See config.h for the contract. */
#include "config/config.h"

#include "config/ini_file.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifndef RTSIM_DATA_DIR
#define RTSIM_DATA_DIR "model/data"
#endif

#define KEY_MAX 96

enum { LEVEL_DEFAULT = 0, LEVEL_FILE = 1, LEVEL_SET = 2 };

typedef struct slot {
    const rtcfg_schema *schema;
    const rtcfg_param *p;
    char key[KEY_MAX];
    char *text;          /* current value as text */
    int64_t i;
    double r;
    bool b;
    int e;
    int level;
    char source[RTCFG_WHERE_MAX];
} slot;

/* An entry from a file or --set not yet claimed by a registered key. */
typedef struct pending {
    char key[KEY_MAX];
    char *value;
    char where[RTCFG_WHERE_MAX];     /* "FILE:LINE" or "--set ASSIGNMENT" */
    int level;
    bool claimed;
} pending;

typedef struct deferred {
    rtcfg_deferred_fn fn;
    void *user;
} deferred;

struct rtcfg {
    const rtcfg_schema **schemas;
    int nschemas, capschemas;
    slot *slots;
    int nslots, capslots;
    pending *pend;
    int npend, cappend;
    deferred *defer;
    int ndefer;
    bool deferred_done;
    void **owned;
    int nowned;
};

int rtcfg_errorf(char *err, size_t errlen, const char *fmt, ...)
{
    if (err && errlen) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err, errlen, fmt, ap);
        va_end(ap);
    }
    return -1;
}

static void *xrealloc(void *p, size_t n)
{
    void *q = realloc(p, n ? n : 1);
    if (!q) {
        fprintf(stderr, "rtcfg: out of memory\n");
        abort();
    }
    return q;
}

static char *xstrdup(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = xrealloc(NULL, n);
    memcpy(d, s, n);
    return d;
}

/* ---------------------------------------------------------------- values */

static const char *type_name(rtcfg_type t)
{
    switch (t) {
    case RTCFG_INT: return "integer";
    case RTCFG_REAL: return "number";
    case RTCFG_BOOL: return "boolean";
    case RTCFG_ENUM: return "choice";
    case RTCFG_STRING: return "string";
    }
    return "?";
}

void rtcfg_describe_range(const rtcfg_param *p, char *buf, size_t len)
{
    switch (p->type) {
    case RTCFG_INT:
        snprintf(buf, len, "%.0f..%.0f%s", p->min, p->max, (p->flags & RTCFG_POW2) ? ", power of two" : "");
        break;
    case RTCFG_REAL:
        snprintf(buf, len, "%g..%g", p->min, p->max);
        break;
    case RTCFG_BOOL:
        snprintf(buf, len, "true|false");
        break;
    case RTCFG_ENUM:
        snprintf(buf, len, "%s", p->choices ? p->choices : "");
        break;
    case RTCFG_STRING:
        /* choices, when given, describes the text the owner accepts (checked by its schema check) */
        snprintf(buf, len, "%s", p->choices ? p->choices : "any text");
        break;
    }
}

/* 0, -1 not an integer, -2 an integer too large for 64 bits (strtoull's
 * ERANGE, or the K/M/G multiple): told apart so the message does not call a
 * well-formed number "not an integer". */
static int parse_int(const char *s, int64_t *out)
{
    while (isspace((unsigned char)*s))
        s++;
    const char *q = s;
    bool neg = false;
    if (*q == '-' || *q == '+')
        neg = *q++ == '-';
    int base = 10;
    if (q[0] == '0' && (q[1] == 'x' || q[1] == 'X')) {
        base = 16;
        q += 2;
    }
    if (!isxdigit((unsigned char)*q))
        return -1;
    errno = 0;
    char *end;
    unsigned long long v = strtoull(q, &end, base);
    if (end == q)
        return -1;
    const bool too_large = errno == ERANGE;
    unsigned long long mul = 1;
    if (*end == 'K' || *end == 'k')
        mul = 1ull << 10;
    else if (*end == 'M')
        mul = 1ull << 20;
    else if (*end == 'G')
        mul = 1ull << 30;
    if (mul != 1) {
        end++;
        if (end[0] == 'i' && end[1] == 'B')
            end += 2;
        else if (end[0] == 'B')
            end++;
    }
    while (isspace((unsigned char)*end))
        end++;
    if (*end)
        return -1;
    if (too_large || v > (unsigned long long)INT64_MAX / mul)
        return -2;
    v *= mul;
    *out = neg ? -(int64_t)v : (int64_t)v;
    return 0;
}

static int parse_bool(const char *s, bool *out)
{
    static const char *t[] = {"true", "yes", "on", "1"}, *f[] = {"false", "no", "off", "0"};
    for (int i = 0; i < 4; i++) {
        if (strcasecmp(s, t[i]) == 0)
            return *out = true, 0;
        if (strcasecmp(s, f[i]) == 0)
            return *out = false, 0;
    }
    return -1;
}

static int enum_index(const char *choices, const char *s)
{
    size_t n = strlen(s);
    int idx = 0;
    for (const char *c = choices; c && *c; idx++) {
        const char *bar = strchr(c, '|');
        size_t len = bar ? (size_t)(bar - c) : strlen(c);
        if (len == n && strncmp(c, s, n) == 0)
            return idx;
        if (!bar)
            break;
        c = bar + 1;
    }
    return -1;
}

/* Parses and validates text for slot s; on success stores it. `where` is the
 * origin for messages ("FILE:LINE", "--set a.b=c", "default"). */
static int assign(slot *s, const char *text, const char *where, int level, char *err, size_t errlen)
{
    const rtcfg_param *p = s->p;
    char range[160];
    rtcfg_describe_range(p, range, sizeof range);
    int64_t iv = 0;
    double rv = 0;
    bool bv = false;
    int ev = 0;
    switch (p->type) {
    case RTCFG_INT:
        int pi = parse_int(text, &iv);
        if (pi == -2)
            return rtcfg_errorf(err, errlen, "%s: %s = '%s' does not fit in 64 bits (allowed %s)", where, s->key,
                                text, range);
        if (pi)
            return rtcfg_errorf(err, errlen, "%s: %s = '%s' is not an integer (allowed %s)", where, s->key, text, range);
        if ((double)iv < p->min || (double)iv > p->max)
            return rtcfg_errorf(err, errlen, "%s: %s = %s is out of range (allowed %s)", where, s->key, text, range);
        if ((p->flags & RTCFG_POW2) && (iv <= 0 || (iv & (iv - 1))))
            return rtcfg_errorf(err, errlen, "%s: %s = %s is not a power of two (allowed %s)", where, s->key, text, range);
        rv = (double)iv;
        break;
    case RTCFG_REAL: {
        char *end;
        errno = 0;
        rv = strtod(text, &end);
        while (isspace((unsigned char)*end))
            end++;
        if (end == text || *end || errno || !isfinite(rv))
            return rtcfg_errorf(err, errlen, "%s: %s = '%s' is not a number (allowed %s)", where, s->key, text, range);
        if (rv < p->min || rv > p->max)
            return rtcfg_errorf(err, errlen, "%s: %s = %s is out of range (allowed %s)", where, s->key, text, range);
        break;
    }
    case RTCFG_BOOL:
        if (parse_bool(text, &bv))
            return rtcfg_errorf(err, errlen, "%s: %s = '%s' is not a boolean (allowed true|false, yes|no, on|off, 1|0)",
                                where, s->key, text);
        break;
    case RTCFG_ENUM:
        ev = enum_index(p->choices, text);
        if (ev < 0)
            return rtcfg_errorf(err, errlen, "%s: %s = '%s' is not one of %s", where, s->key, text, range);
        break;
    case RTCFG_STRING:
        break;
    }
    free(s->text);
    s->text = xstrdup(text);
    s->i = iv;
    s->r = rv;
    s->b = bv;
    s->e = ev;
    s->level = level;
    snprintf(s->source, sizeof s->source, "%s", where);
    return 0;
}

/* ------------------------------------------------------------- registry */

static slot *find_slot(const rtcfg *cfg, const char *key)
{
    for (int i = 0; i < cfg->nslots; i++)
        if (strcmp(cfg->slots[i].key, key) == 0)
            return &cfg->slots[i];
    return NULL;
}

static const rtcfg_param machine_params[] = {
    {"name", RTCFG_STRING, "mbvh4", 0, 0, 0, NULL, "", "machine name (reported in outputs)"},
    {"clock_mhz", RTCFG_REAL, "500", 1, 10000, 0, NULL, "MHz", "accelerator clock (paper sec. 3.2: 500 MHz)"},
    {"branching", RTCFG_INT, "4", 2, 8, 0, NULL, "children",
     "BVH width N: node = N x 32 B (paper sec. 3.1: 2 = BVH, 4 = MBVH4)"},
};
static const rtcfg_schema machine_schema = {
    "machine", "the machine as a whole", machine_params, 3, NULL,
};

rtcfg *rtcfg_create(void)
{
    rtcfg *cfg = calloc(1, sizeof *cfg);
    if (!cfg)
        return NULL;
    char err[256];
    if (rtcfg_add_schema(cfg, &machine_schema, err, sizeof err)) {
        fprintf(stderr, "rtcfg: %s\n", err);
        abort();
    }
    return cfg;
}

void rtcfg_destroy(rtcfg *cfg)
{
    if (!cfg)
        return;
    for (int i = 0; i < cfg->nslots; i++)
        free(cfg->slots[i].text);
    for (int i = 0; i < cfg->npend; i++)
        free(cfg->pend[i].value);
    free(cfg->slots);
    free(cfg->pend);
    free(cfg->schemas);
    free(cfg->defer);
    for (int i = 0; i < cfg->nowned; i++)
        free(cfg->owned[i]);
    free(cfg->owned);
    free(cfg);
}

void rtcfg_add_deferred(rtcfg *cfg, rtcfg_deferred_fn fn, void *user)
{
    for (int i = 0; i < cfg->ndefer; i++)
        if (cfg->defer[i].fn == fn && cfg->defer[i].user == user)
            return; /* registering the same callback twice is harmless, like schemas */
    cfg->defer = xrealloc(cfg->defer, (size_t)(cfg->ndefer + 1) * sizeof *cfg->defer);
    cfg->defer[cfg->ndefer++] = (deferred){fn, user};
}

void rtcfg_own(rtcfg *cfg, void *block)
{
    cfg->owned = xrealloc(cfg->owned, (size_t)(cfg->nowned + 1) * sizeof *cfg->owned);
    cfg->owned[cfg->nowned++] = block;
}

int rtcfg_add_schema(rtcfg *cfg, const rtcfg_schema *schema, char *err, size_t errlen)
{
    for (int i = 0; i < cfg->nschemas; i++)
        if (cfg->schemas[i] == schema)
            return 0; /* registering the same table twice is harmless */
    for (int k = 0; k < schema->nparams; k++) {
        char key[KEY_MAX];
        if (snprintf(key, sizeof key, "%s.%s", schema->section, schema->params[k].name) >= (int)sizeof key)
            return rtcfg_errorf(err, errlen, "schema [%s]: key '%s' too long", schema->section, schema->params[k].name);
        if (find_slot(cfg, key))
            return rtcfg_errorf(err, errlen, "schema [%s]: key %s declared twice", schema->section, key);
    }
    if (cfg->nschemas == cfg->capschemas) {
        cfg->capschemas = cfg->capschemas ? 2 * cfg->capschemas : 16;
        cfg->schemas = xrealloc(cfg->schemas, (size_t)cfg->capschemas * sizeof *cfg->schemas);
    }
    cfg->schemas[cfg->nschemas++] = schema;
    for (int k = 0; k < schema->nparams; k++) {
        if (cfg->nslots == cfg->capslots) {
            cfg->capslots = cfg->capslots ? 2 * cfg->capslots : 64;
            cfg->slots = xrealloc(cfg->slots, (size_t)cfg->capslots * sizeof *cfg->slots);
        }
        slot *s = &cfg->slots[cfg->nslots++];
        memset(s, 0, sizeof *s);
        s->schema = schema;
        s->p = &schema->params[k];
        snprintf(s->key, sizeof s->key, "%s.%s", schema->section, s->p->name);
        char where[KEY_MAX + 40];
        snprintf(where, sizeof where, "default of %s", s->key);
        if (assign(s, s->p->def ? s->p->def : "", where, LEVEL_DEFAULT, err, errlen))
            return -1;
        snprintf(s->source, sizeof s->source, "default");
    }
    /* entries that arrived before this schema: apply in arrival order */
    for (int i = 0; i < cfg->npend; i++) {
        pending *e = &cfg->pend[i];
        if (e->claimed)
            continue;
        slot *s = find_slot(cfg, e->key);
        if (!s || s->schema != schema)
            continue;
        e->claimed = true;
        if (e->level >= s->level && assign(s, e->value, e->where, e->level, err, errlen))
            return -1;
    }
    return 0;
}

/* Applies one entry: to its slot when registered, else kept for later. */
static int apply_entry(rtcfg *cfg, const char *key, const char *value, const char *where, int level, char *err,
                       size_t errlen)
{
    slot *s = find_slot(cfg, key);
    if (s) {
        if (level < s->level)
            return 0;
        return assign(s, value, where, level, err, errlen);
    }
    if (cfg->npend == cfg->cappend) {
        cfg->cappend = cfg->cappend ? 2 * cfg->cappend : 32;
        cfg->pend = xrealloc(cfg->pend, (size_t)cfg->cappend * sizeof *cfg->pend);
    }
    pending *e = &cfg->pend[cfg->npend++];
    memset(e, 0, sizeof *e);
    snprintf(e->key, sizeof e->key, "%s", key);
    e->value = xstrdup(value);
    snprintf(e->where, sizeof e->where, "%s", where);
    e->level = level;
    return 0;
}

/* ---------------------------------------------------------------- files */

typedef struct file_entry {
    char key[KEY_MAX];
    char *value;
    int line;
} file_entry;

typedef struct file_loader {
    file_entry *e;
    int n, cap;
} file_loader;

/* Keeps the file's entries: they are applied once the whole file has read
 * without error (a bad file changes nothing). */
static int handler(ini_file *f, void *user, const char *section, const char *name, const char *value)
{
    file_loader *L = user;
    char key[KEY_MAX];
    if (snprintf(key, sizeof key, "%s.%s", section, name) >= (int)sizeof key)
        return ini_file_error(f, "key '%s.%s' too long", section, name);
    if (L->n == L->cap) {
        L->cap = L->cap ? 2 * L->cap : 64;
        L->e = xrealloc(L->e, (size_t)L->cap * sizeof *L->e);
    }
    file_entry *e = &L->e[L->n++];
    snprintf(e->key, sizeof e->key, "%s", key);
    e->value = xstrdup(value);
    e->line = ini_file_line(f);
    return 0;
}

const char *rtcfg_data_dir(void)
{
    const char *d = getenv("RTSIM_DATA_DIR");
    return d && *d ? d : RTSIM_DATA_DIR;
}

int rtcfg_preset_path(const char *name, char *buf, size_t len)
{
    if (snprintf(buf, len, "%s/machines/%s.ini", rtcfg_data_dir(), name) >= (int)len)
        return -1;
    return 0;
}

static bool is_preset_name(const char *s)
{
    if (!*s || strchr(s, '/'))
        return false;
    size_t n = strlen(s);
    if (n >= 4 && strcmp(s + n - 4, ".ini") == 0)
        return false;
    for (const char *p = s; *p; p++)
        if (!isalnum((unsigned char)*p) && *p != '_' && *p != '-')
            return false;
    return true;
}

static void list_presets(char *buf, size_t len)
{
    /* The presets are a fixed set shipped with the model; listed for messages. */
    static const char *const names[] = {"bvh2", "mbvh4"};
    buf[0] = 0;
    size_t used = 0;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char path[RTCFG_PATH_MAX];
        if (rtcfg_preset_path(names[i], path, sizeof path) == 0 && access(path, R_OK) == 0)
            used += (size_t)snprintf(buf + used, len - used, "%s%s", used ? ", " : "", names[i]);
        if (used >= len)
            break;
    }
    if (!used)
        snprintf(buf, len, "none found in %s/machines", rtcfg_data_dir());
}

int rtcfg_load(rtcfg *cfg, const char *what, char *err, size_t errlen)
{
    char path[RTCFG_PATH_MAX];
    if (is_preset_name(what)) {
        if (rtcfg_preset_path(what, path, sizeof path))
            return rtcfg_errorf(err, errlen, "machine preset '%s': %s/machines/%s.ini is longer than %d characters",
                                what, rtcfg_data_dir(), what, RTCFG_PATH_MAX - 1);
        if (access(path, R_OK) != 0) {
            /* room for "none found in <data folder>/machines" whatever the
             * checkout's path (the data folder is compiled in) */
            char names[RTCFG_PATH_MAX + 32];
            list_presets(names, sizeof names);
            return rtcfg_errorf(err, errlen, "unknown machine preset '%s' (presets: %s; or give a path to an .ini file)",
                                what, names);
        }
    } else if (snprintf(path, sizeof path, "%s", what) >= (int)sizeof path) {
        return rtcfg_errorf(err, errlen, "%s: configuration path longer than %d characters", what, RTCFG_PATH_MAX - 1);
    }
    file_loader L = {0};
    static const ini_file_opts opts = {.what = "a machine configuration", .example = "node_l1"};
    int result = ini_file_read(path, &opts, handler, &L, err, errlen);
    for (int i = 0; i < L.n && result == 0; i++) {
        char where[RTCFG_WHERE_MAX];   /* path (< RTCFG_PATH_MAX) and line: fits */
        snprintf(where, sizeof where, "%s:%d", path, L.e[i].line);
        result = apply_entry(cfg, L.e[i].key, L.e[i].value, where, LEVEL_FILE, err, errlen);
    }
    for (int i = 0; i < L.n; i++)
        free(L.e[i].value);
    free(L.e);
    return result;
}

static void trim(char *s)
{
    size_t n = strlen(s);
    while (n && isspace((unsigned char)s[n - 1]))
        s[--n] = 0;
    size_t k = 0;
    while (isspace((unsigned char)s[k]))
        k++;
    memmove(s, s + k, n - k + 1);
}

int rtcfg_set(rtcfg *cfg, const char *assignment, char *err, size_t errlen)
{
    char where[RTCFG_WHERE_MAX];
    if (snprintf(where, sizeof where, "--set %s", assignment) >= (int)sizeof where)
        return rtcfg_errorf(err, errlen, "--set: assignment longer than %d characters", RTCFG_WHERE_MAX - 7);
    const char *eq = strchr(assignment, '=');
    if (!eq)
        return rtcfg_errorf(err, errlen, "%s: expected KEY=VALUE with KEY = section.name (e.g. trv.count=8)", where);
    char key[KEY_MAX];
    size_t lk = (size_t)(eq - assignment);
    if (lk >= sizeof key)
        return rtcfg_errorf(err, errlen, "%s: key too long", where);
    memcpy(key, assignment, lk);
    key[lk] = 0;
    trim(key);
    const char *dot = strchr(key, '.');
    if (!dot || dot == key || !dot[1])
        return rtcfg_errorf(err, errlen, "%s: key '%s' must be section.name (e.g. trv.count=8)", where, key);
    char *value = xstrdup(eq + 1);
    trim(value);
    int rc = apply_entry(cfg, key, value, where, LEVEL_SET, err, errlen);
    free(value);
    return rc;
}

int rtcfg_set_int(rtcfg *cfg, const char *key, int64_t value, char *err, size_t errlen)
{
    char a[KEY_MAX + 32];
    snprintf(a, sizeof a, "%s=%lld", key, (long long)value);
    if (!find_slot(cfg, key))
        return rtcfg_errorf(err, errlen, "%s: unknown key", key);
    return rtcfg_set(cfg, a, err, errlen);
}

/* "keys of [sec]: a, b, c" or the list of sections. A key with two dots
 * ("dram.timing.nFOO") first gets the keys under its prefix ("dram.timing."),
 * so the list names the keys the user most likely meant. */
static void suggest(const rtcfg *cfg, const char *key, char *buf, size_t len)
{
    const char *last = strrchr(key, '.'), *dot = strchr(key, '.');
    if (last && last != dot) {
        size_t lp = (size_t)(last - key) + 1, used = 0, head;
        used = head = (size_t)snprintf(buf, len, "keys %.*s*: ", (int)lp, key);
        for (int i = 0; i < cfg->nslots && used + 2 < len; i++)
            if (strncmp(cfg->slots[i].key, key, lp) == 0)
                used += (size_t)snprintf(buf + used, len - used, "%s%s", used > head ? ", " : "",
                                         cfg->slots[i].key + lp);
        if (used > head)
            return;
    }
    size_t ls = dot ? (size_t)(dot - key) : strlen(key);
    size_t used = (size_t)snprintf(buf, len, "keys of [%.*s]: ", (int)ls, key), head = used;
    for (int i = 0; i < cfg->nslots && used + 2 < len; i++)
        if (strlen(cfg->slots[i].schema->section) == ls && strncmp(cfg->slots[i].schema->section, key, ls) == 0)
            used += (size_t)snprintf(buf + used, len - used, "%s%s", used > head ? ", " : "", cfg->slots[i].p->name);
    if (used > head)
        return;
    used = (size_t)snprintf(buf, len, "no section [%.*s]; sections: ", (int)ls, key);
    for (int i = 0; i < cfg->nschemas && used + 2 < len; i++) {
        bool seen = false;
        for (int j = 0; j < i; j++)
            seen |= strcmp(cfg->schemas[j]->section, cfg->schemas[i]->section) == 0;
        if (!seen)
            used += (size_t)snprintf(buf + used, len - used, "%s%s", i ? ", " : "", cfg->schemas[i]->section);
    }
}

int rtcfg_finish(rtcfg *cfg, char *err, size_t errlen)
{
    if (!cfg->deferred_done) {
        cfg->deferred_done = true;
        for (int i = 0; i < cfg->ndefer; i++)
            if (cfg->defer[i].fn(cfg, cfg->defer[i].user, err, errlen))
                return -1;
    }
    for (int i = 0; i < cfg->npend; i++) {
        pending *e = &cfg->pend[i];
        if (e->claimed)
            continue;
        char hint[700];
        suggest(cfg, e->key, hint, sizeof hint);
        return rtcfg_errorf(err, errlen, "%s: unknown key %s (%s)", e->where, e->key, hint);
    }
    for (int i = 0; i < cfg->nschemas; i++)
        if (cfg->schemas[i]->check && cfg->schemas[i]->check(cfg, err, errlen))
            return -1;
    return 0;
}

/* -------------------------------------------------------------- getters */

static const slot *get(const rtcfg *cfg, const char *key, int type)
{
    const slot *s = find_slot(cfg, key);
    if (!s) {
        fprintf(stderr, "rtcfg: internal error: key %s is not registered\n", key);
        abort();
    }
    if (type >= 0 && (int)s->p->type != type) {
        fprintf(stderr, "rtcfg: internal error: key %s is a %s, read as a %s\n", key, type_name(s->p->type),
                type_name((rtcfg_type)type));
        abort();
    }
    return s;
}

bool rtcfg_has(const rtcfg *cfg, const char *key) { return find_slot(cfg, key) != NULL; }
int64_t rtcfg_int(const rtcfg *cfg, const char *key) { return get(cfg, key, RTCFG_INT)->i; }
bool rtcfg_bool(const rtcfg *cfg, const char *key) { return get(cfg, key, RTCFG_BOOL)->b; }
int rtcfg_enum(const rtcfg *cfg, const char *key) { return get(cfg, key, RTCFG_ENUM)->e; }
const char *rtcfg_str(const rtcfg *cfg, const char *key) { return get(cfg, key, -1)->text; }
const char *rtcfg_source(const rtcfg *cfg, const char *key) { return get(cfg, key, -1)->source; }

double rtcfg_real(const rtcfg *cfg, const char *key)
{
    const slot *s = get(cfg, key, -1);
    if (s->p->type != RTCFG_REAL && s->p->type != RTCFG_INT) {
        fprintf(stderr, "rtcfg: internal error: key %s is a %s, read as a number\n", key, type_name(s->p->type));
        abort();
    }
    return s->r;
}

int rtcfg_schema_count(const rtcfg *cfg) { return cfg->nschemas; }
const rtcfg_schema *rtcfg_schema_at(const rtcfg *cfg, int i)
{
    return i >= 0 && i < cfg->nschemas ? cfg->schemas[i] : NULL;
}

/* --------------------------------------------------------------- output */

void rtcfg_write_ini_file(const rtcfg *cfg, FILE *f)
{
    fprintf(f, "; rtsim machine configuration written by rtcfg_write_ini (every key, current values)\n");
    for (int i = 0; i < cfg->nschemas; i++) {
        bool seen = false;
        for (int j = 0; j < i; j++)
            seen |= strcmp(cfg->schemas[j]->section, cfg->schemas[i]->section) == 0;
        if (seen)
            continue;
        fprintf(f, "\n[%s]\n", cfg->schemas[i]->section);
        for (int j = i; j < cfg->nschemas; j++) {
            if (strcmp(cfg->schemas[j]->section, cfg->schemas[i]->section) != 0)
                continue;
            for (int k = 0; k < cfg->nslots; k++) {
                const slot *s = &cfg->slots[k];
                if (s->schema != cfg->schemas[j])
                    continue;
                char range[160];
                rtcfg_describe_range(s->p, range, sizeof range);
                /* keep every line under inih's line limit */
                fprintf(f, "; %.120s [%.20s; %.40s]\n", s->p->desc, s->p->unit && *s->p->unit ? s->p->unit : "-", range);
                fprintf(f, "%s = %s\n", s->p->name, s->text);
            }
        }
    }
}

int rtcfg_write_ini(const rtcfg *cfg, const char *path, char *err, size_t errlen)
{
    char tmp[RTCFG_PATH_MAX + 8];
    if (snprintf(tmp, sizeof tmp, "%s.tmp", path) >= (int)sizeof tmp)
        return rtcfg_errorf(err, errlen, "%s: path too long", path);
    FILE *f = fopen(tmp, "w");
    if (!f)
        return rtcfg_errorf(err, errlen, "%s: cannot write: %s", tmp, strerror(errno));
    rtcfg_write_ini_file(cfg, f);
    bool bad = ferror(f) != 0;
    if (fclose(f) != 0 || bad) {
        remove(tmp);
        return rtcfg_errorf(err, errlen, "%s: write failed", tmp);
    }
    if (rename(tmp, path) != 0) {
        remove(tmp);
        return rtcfg_errorf(err, errlen, "%s: cannot rename to %s: %s", tmp, path, strerror(errno));
    }
    return 0;
}

void rtcfg_print_schema(FILE *out, const rtcfg_schema *schema, const rtcfg *cfg)
{
    fprintf(out, "[%s] %s\n", schema->section, schema->title ? schema->title : "");
    for (int k = 0; k < schema->nparams; k++) {
        const rtcfg_param *p = &schema->params[k];
        char key[KEY_MAX], range[160];
        snprintf(key, sizeof key, "%s.%s", schema->section, p->name);
        rtcfg_describe_range(p, range, sizeof range);
        const slot *s = cfg ? find_slot(cfg, key) : NULL;
        fprintf(out, "  %-28s %-8s %-10s %-10s %-28s %s\n", key, type_name(p->type), s ? s->text : (p->def ? p->def : ""),
                p->unit && *p->unit ? p->unit : "-", range, p->desc);
    }
}
