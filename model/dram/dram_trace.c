/* dram_trace.c — trace reader and Ramulator-style injection loop (dram_trace.h). */
#include "model/dram/dram_trace.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


int dram_trace_parse_line(const char *s, uint64_t *addr, int *is_write)
{
    while (*s == ' ' || *s == '\t')
        s++;
    if (*s == 0 || *s == '\n' || *s == '\r' || *s == '#')
        return 0;
    if (s[0] != '0' || (s[1] != 'x' && s[1] != 'X'))
        return -1;
    s += 2;
    uint64_t v = 0;
    int nd = 0;
    for (;; s++, nd++) {
        int d;
        if (*s >= '0' && *s <= '9')
            d = *s - '0';
        else if (*s >= 'a' && *s <= 'f')
            d = *s - 'a' + 10;
        else if (*s >= 'A' && *s <= 'F')
            d = *s - 'A' + 10;
        else
            break;
        if (nd >= 16)
            return -1;
        v = v << 4 | (uint64_t)d;
    }
    if (nd == 0 || (*s != ' ' && *s != '\t'))
        return -1;
    while (*s == ' ' || *s == '\t')
        s++;
    if (*s != 'R' && *s != 'W')
        return -1;
    int w = *s++ == 'W';
    while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n')
        s++;
    if (*s)
        return -1;
    *addr = v;
    *is_write = w;
    return 1;
}

uint64_t dram_spec_capacity_bytes(const dram_spec *spec)
{
    /* columns count DQ-wide words (docs/dram.md, [organization]) */
    return (uint64_t)spec->channels * (uint64_t)spec->ranks * (uint64_t)spec->banks * (uint64_t)spec->rows *
           (uint64_t)spec->columns * (uint64_t)spec->dq_bits / 8;
}

int dram_trace_next(dram_trace_reader *r, uint64_t *addr, int *w, char *err, size_t errlen)
{
    if (!r->buf) {
        r->cap = DRAM_TRACE_MAX_LINE + 2;   /* a line, its '\n' and a NUL */
        r->buf = malloc(r->cap);
        if (!r->buf) {
            snprintf(err, errlen, "%s: out of memory", r->name);
            return -1;
        }
    }
    for (;;) {
        errno = 0;
        /* A bounded line: getline() would grow its buffer for as long as no
         * newline comes, without end on /dev/zero or an endless stream. */
        size_t len = 0;
        int c = 0;
        while (len < r->cap - 2 && (c = getc_unlocked(r->f)) != EOF) {
            r->buf[len++] = (char)c;
            if (c == '\n')
                break;
        }
        r->buf[len] = 0;
        if (len == r->cap - 2 && c != '\n' && (c = getc_unlocked(r->f)) != EOF && c != '\n') {
            snprintf(err, errlen, "%s:%ld: line longer than %d characters (not a trace of '0x<hex address> R|W' lines)",
                     r->name, r->line + 1, DRAM_TRACE_MAX_LINE);
            return -1;
        }
        ssize_t n = len ? (ssize_t)len : -1;
        if (n < 0) {
            if (ferror(r->f)) {
                /* a folder opens like a file and fails here (EISDIR): it was
                 * taken for an empty trace */
                snprintf(err, errlen, "%s: cannot read: %s", r->name,
                         errno == EISDIR ? "is a folder, not a trace file" : strerror(errno ? errno : EIO));
                return -1;
            }
            if (r->requests == 0) {
                snprintf(err, errlen, "%s: no requests (expected lines '0x<hex address> R|W')", r->name);
                return -1;
            }
            return 0;
        }
        r->line++;
        int k = (size_t)n == strlen(r->buf) ? dram_trace_parse_line(r->buf, addr, w) : -2;
        if (k == 1 && r->capacity && *addr >= r->capacity) {
            snprintf(err, errlen,
                     "%s:%ld: address 0x%llx beyond the device's capacity of %llu bytes (allowed 0x0..0x%llx; "
                     "[organization] channels x ranks x banks x rows x columns x dq_bits/8)",
                     r->name, r->line, (unsigned long long)*addr, (unsigned long long)r->capacity,
                     (unsigned long long)(r->capacity - 1));
            return -1;
        }
        if (k == 1) {
            r->requests++;
            return 1;
        }
        if (k == -2) {
            snprintf(err, errlen, "%s:%ld: NUL byte in the line (not a text trace)", r->name, r->line);
            return -1;
        }
        if (k < 0) {
            size_t l = strcspn(r->buf, "\r\n");
            snprintf(err, errlen, "%s:%ld: expected '0x<hex address> R|W', got '%.*s'", r->name, r->line,
                     (int)(l > 60 ? 60 : l), r->buf);
            return -1;
        }
    }
}

static int (*stop_check)(void);

void dram_trace_set_stop_check(int (*stop)(void)) { stop_check = stop; }

int dram_trace_run(dram_ctrl *c, FILE *f, const char *name, dram_trace_result *res, char *err, size_t errlen)
{
    memset(res, 0, sizeof *res);
    dram_trace_reader r = {.f = f, .name = name, .capacity = dram_spec_capacity_bytes(dram_ctrl_spec(c))};
    int stall = 0, end = 0, is_write = 0;
    uint64_t addr = 0;
    while (!end || dram_pending(c)) {
        if (!end && !stall) {
            int k = dram_trace_next(&r, &addr, &is_write, err, errlen);
            if (k < 0) {
                free(r.buf);
                return 2;
            }
            end = k == 0;
        }
        if (stop_check && !end && stop_check()) {
            /* e.g. Ctrl-C/SIGTERM in rtdram: stop injecting, leave the
             * statistics of what ran */
            free(r.buf);
            return 3;
        }
        if (!end) {
            stall = !dram_add(c, addr, is_write, (uint64_t)r.line);
            if (!stall) {
                res->requests++;
                if (is_write)
                    res->writes++;
                else
                    res->reads++;
            }
        } else {
            dram_set_write_high_pct(c, 0);
        }
        dram_tick(c);
        /* idle until the controller's next event, unless that tick freed room for the
         * stalled request (a command can free a queue entry without the next cycle
         * being an event) */
        if ((end || (stall && !dram_will_accept(c, addr, is_write))) && dram_pending(c))
            dram_skip(c);
    }
    free(r.buf);
    return 0;
}
