/* dram_trace.c — trace reader and Ramulator-style injection loop (dram_trace.h). */
#include "model/dram/dram_trace.h"

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

typedef struct reader {
    FILE *f;
    char *buf;
    size_t cap;
    long line;
} reader;

/* 1 request, 0 end of file, -1 malformed */
static int next_request(reader *r, uint64_t *addr, int *w, const char *name, char *err, size_t errlen)
{
    for (;;) {
        ssize_t n = getline(&r->buf, &r->cap, r->f);
        if (n < 0)
            return 0;
        r->line++;
        int k = dram_trace_parse_line(r->buf, addr, w);
        if (k == 1)
            return 1;
        if (k < 0) {
            size_t l = strcspn(r->buf, "\r\n");
            snprintf(err, errlen, "%s:%ld: expected '0x<hex address> R|W', got '%.*s'", name, r->line,
                     (int)(l > 60 ? 60 : l), r->buf);
            return -1;
        }
    }
}

int dram_trace_run(dram_ctrl *c, FILE *f, const char *name, dram_trace_result *res, char *err, size_t errlen)
{
    memset(res, 0, sizeof *res);
    reader r = {.f = f};
    int stall = 0, end = 0, is_write = 0;
    uint64_t addr = 0;
    while (!end || dram_pending(c)) {
        if (!end && !stall) {
            int k = next_request(&r, &addr, &is_write, name, err, errlen);
            if (k < 0) {
                free(r.buf);
                return 2;
            }
            end = k == 0;
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
