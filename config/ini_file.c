/* ini_file.c — the INI reader of ini_file.h: inih with a line-counting reader
 * (Debian's inih does not pass line numbers to handlers), over-long line and
 * duplicate-key checks, and one wording of file errors. */
#include "config/ini_file.h"

#include <errno.h>
#include <ini.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* A key read so far, for "given twice". */
typedef struct seen_key {
    char *section, *key;
    int line;
} seen_key;

struct ini_file {
    const ini_file_opts *opts;
    const char *path;
    FILE *f;
    int line;             /* lines read so far (inih calls the reader once per line) */
    int long_line;        /* first line longer than the buffer, 0: none */
    size_t bytes;         /* bytes read so far */
    int too_big;          /* line at which INI_FILE_MAX_BYTES was passed, 0: not */
    int nul_line;         /* line with a NUL byte (not text), 0: none */
    int fail_line;        /* line of the first reported error, 0: none (inih reads on) */
    ini_file_fn fn;
    void *user;
    seen_key *seen;
    int nseen, capseen;
    char *err;
    size_t errlen;
};

static void *xrealloc(void *p, size_t n)
{
    void *q = realloc(p, n);
    if (!q) {
        fprintf(stderr, "ini_file: out of memory\n");
        exit(1);
    }
    return q;
}

static char *xstrdup(const char *s)
{
    size_t n = strlen(s) + 1;
    return memcpy(xrealloc(NULL, n), s, n);
}

const char *ini_file_path(const ini_file *f) { return f->path; }
int ini_file_line(const ini_file *f) { return f->line; }

int ini_file_error(ini_file *f, const char *fmt, ...)
{
    if (f->fail_line)
        return -1;
    f->fail_line = f->line;
    int n = snprintf(f->err, f->errlen, "%s:%d: ", f->path, f->line);
    if (n >= 0 && (size_t)n < f->errlen) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(f->err + n, f->errlen - (size_t)n, fmt, ap);
        va_end(ap);
    }
    return -1;
}

int ini_file_key_index(ini_file *f, const char *section, const char *key, const char *const *keys, int n)
{
    for (int i = 0; i < n; i++)
        if (strcmp(keys[i], key) == 0)
            return i;
    char allowed[512] = "";
    size_t used = 0;
    for (int i = 0; i < n && used < sizeof allowed; i++)
        used += (size_t)snprintf(allowed + used, sizeof allowed - used, "%s%s", i ? ", " : "", keys[i]);
    return ini_file_error(f, "unknown key '%s' in [%s] (allowed %s)", key, section, allowed);
}

int ini_file_number(const char *value, double *out)
{
    char *end;
    errno = 0;
    const double v = strtod(value, &end);
    if (errno || end == value || *end || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

/* inih reader: counts lines and bytes. It ends the file at an over-long line
 * (noted; inih would take it for several lines) and after INI_FILE_MAX_BYTES
 * (noted): skipping to the end of the line, or reading on, would never end on
 * an input without newlines or without end (/dev/zero, a FIFO fed forever). */
static char *reader(char *buf, int size, void *stream)
{
    ini_file *f = stream;
    if (f->long_line || f->too_big || f->nul_line)
        return NULL;
    /* byte by byte, not fgets: fgets cannot tell a NUL byte from the end of
     * the line, and /dev/zero would read as empty lines without end */
    int n = 0, c = EOF;
    while (n < size - 1 && (c = getc_unlocked(f->f)) != EOF) {
        if (c == 0) {
            f->nul_line = f->line + 1;
            return NULL;
        }
        buf[n++] = (char)c;
        if (c == '\n')
            break;
    }
    if (n == 0)
        return NULL;
    buf[n] = 0;
    f->line++;
    f->bytes += (size_t)n;
    if (n == size - 1 && buf[n - 1] != '\n' && (c = getc_unlocked(f->f)) != EOF) {
        f->long_line = f->line;
        return NULL;
    }
    if (f->bytes > INI_FILE_MAX_BYTES) {
        f->too_big = f->line;
        return NULL;
    }
    return buf;
}

/* The checks every file gets, then the caller's handler. inih goes on after a
 * handler error; nothing is handled after the first. */
static int handler(void *user, const char *section, const char *name, const char *value)
{
    ini_file *f = user;
    if (f->fail_line)
        return 0;
    const ini_file_opts *o = f->opts;
    if (!section[0])
        return !ini_file_error(f, "key '%s' outside a [section] (write e.g. [%s] above it)", name,
                               o->example ? o->example : o->section);
    if (o->section && strcmp(section, o->section) != 0)
        return !ini_file_error(f, "unknown section [%s] (expected [%s])", section, o->section);
    for (int i = 0; i < f->nseen; i++)
        if (strcmp(f->seen[i].key, name) == 0 && strcmp(f->seen[i].section, section) == 0)
            return !ini_file_error(f, "%s.%s given twice (first at line %d)", section, name, f->seen[i].line);
    if (f->nseen == f->capseen) {
        f->capseen = f->capseen ? 2 * f->capseen : 64;
        f->seen = xrealloc(f->seen, (size_t)f->capseen * sizeof *f->seen);
    }
    f->seen[f->nseen++] = (seen_key){xstrdup(section), xstrdup(name), f->line};
    return f->fn(f, f->user, section, name, value) == 0;
}

int ini_file_read(const char *path, const ini_file_opts *opts, ini_file_fn fn, void *user, char *err, size_t errlen)
{
    char none[1];
    if (!err || !errlen) {
        err = none;
        errlen = sizeof none;
    }
    ini_file f = {.opts = opts, .path = path, .fn = fn, .user = user, .err = err, .errlen = errlen};
    err[0] = 0;
    f.f = fopen(path, "r");
    if (!f.f) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    /* a folder opens like a file on Linux and reads as empty, which passed for
     * an empty file */
    struct stat st;
    if (fstat(fileno(f.f), &st) == 0 && S_ISDIR(st.st_mode)) {
        fclose(f.f);
        snprintf(err, errlen, "%s: is a folder, not %s (.ini) file", path, opts->what);
        return -1;
    }
    const int rc = ini_parse_stream(reader, &f, handler, &f);
    fclose(f.f);
    for (int i = 0; i < f.nseen; i++) {
        free(f.seen[i].section);
        free(f.seen[i].key);
    }
    free(f.seen);
    /* inih's rc is the line of its first error, a handler's included: a lower
     * line than the handler's is a syntax error. An over-long line comes first
     * at its own line (its truncated text may look like a syntax error). */
    const int syntax_line = rc > 0 && (!f.fail_line || rc < f.fail_line) ? rc : rc < 0 ? (f.line > 0 ? f.line : 1) : 0;
    int first = f.fail_line;
    if (syntax_line && (!first || syntax_line < first))
        first = syntax_line;
    if (f.nul_line && (!first || f.nul_line <= first)) {
        snprintf(err, errlen, "%s:%d: NUL byte (not a text file)", path, f.nul_line);
        return -1;
    }
    if (f.too_big && (!first || f.too_big <= first)) {
        snprintf(err, errlen, "%s: more than %d MiB, the most an INI file may hold (an endless stream?)", path,
                 INI_FILE_MAX_BYTES >> 20);
        return -1;
    }
    if (f.long_line && (!first || f.long_line <= first)) {
        snprintf(err, errlen, "%s:%d: line too long (at most %d characters)", path, f.long_line, INI_MAX_LINE - 2);
        return -1;
    }
    if (syntax_line && first == syntax_line) {
        snprintf(err, errlen, "%s:%d: syntax error (expected [section], key = value or ; comment)", path,
                 syntax_line);
        return -1;
    }
    return f.fail_line ? -1 : 0;
}
