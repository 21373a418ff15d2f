/* tb_kernel_vcd_bulk — many changes in one time stamp: thousands of
 * variables (64-bit integers with values of every length, bits, and
 * enumerations with long names in between) change together, more than the
 * writer formats into one reserved stretch of its buffer and more bytes
 * than the buffer holds. The body is checked line by line against text the
 * test formats itself (binary without leading zeros, identifiers in
 * declaration order: '!' + index in base 94), including unchanged and
 * glitched variables that must not appear. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "kernel/process.h"
#include "kernel/sim.h"
#include "kernel/vcd.h"
#include "testbench/tb.h"

enum { NV = 6000 };

static char long_names[2][3000];
static const char *enum_names[3] = {"short", long_names[0], long_names[1]};

typedef enum { K_INT, K_BIT, K_ENUM } kind;

static kind kind_of(unsigned i) { return i % 97 == 5 ? K_ENUM : i % 7 == 3 ? K_BIT : K_INT; }

static void id_of(unsigned n, char *id)
{
    int len = 0;
    do {
        id[len++] = (char)('!' + n % 94);
        n /= 94;
    } while (n);
    id[len] = 0;
}

/* The value variable i gets at time t (1 or 2); t = 0 is the initial one. */
static uint64_t value_at(unsigned i, int t)
{
    uint64_t x = (uint64_t)i * 0x9E3779B97F4A7C15ull + (uint64_t)t * 0xD1B54A32D192ED03ull;
    x ^= x >> 29;
    switch (kind_of(i)) {
    case K_BIT: return (x >> 7) & 1;
    case K_ENUM: return x % 3;
    default: return x >> (x % 64); /* every length of binary */
    }
}

static void put_line(char **p, unsigned i, uint64_t v)
{
    char id[8];
    id_of(i, id);
    switch (kind_of(i)) {
    case K_BIT: *p += sprintf(*p, "%u%s\n", (unsigned)v, id); break;
    case K_ENUM: *p += sprintf(*p, "s%s %s\n", enum_names[v], id); break;
    default: {
        char bits[65];
        int n = 0;
        for (int b = 63; b >= 0; b--)
            if ((v >> b) & 1 || n || b == 0)
                bits[n++] = (char)('0' + ((v >> b) & 1));
        bits[n] = 0;
        *p += sprintf(*p, "b%s %s\n", bits, id);
    }
    }
}

/* Keeps time moving: a method re-triggered every picosecond. */
static void ticker(void *u)
{
    ks_next_trigger_time(*(ks_method **)u, 1);
}

int main(void)
{
    for (int k = 0; k < 2; k++) {
        memset(long_names[k], 'a' + k, sizeof long_names[k] - 1);
        long_names[k][sizeof long_names[k] - 1] = 0;
    }
    tb_begin("vcd_bulk_changes_in_one_time_stamp");
    char path[TB_PATH_MAX];
    const char *dir = getenv("RTSIM_TMP");
    tb_pathf(path, sizeof path, "%s/kernel_vcd_bulk.vcd", dir && *dir ? dir : "/tmp");
    ks_sim *sim = ks_sim_create();
    ks_vcd *vcd = ks_vcd_open(sim, path, "1ps", 0, KS_TIME_MAX, NULL);
    TB_CHECK(vcd != NULL, "open: %s", ks_sim_error(sim));
    ks_method *tick = NULL;
    tick = ks_method_create(sim, "ticker", ticker, &tick);
    ks_vcd_var **v = calloc(NV, sizeof *v);
    uint64_t *cur = calloc(NV, sizeof *cur); /* each variable's value */
    char name[64];
    for (unsigned i = 0; i < NV; i++) {
        snprintf(name, sizeof name, "top.v%u", i);
        uint64_t init = cur[i] = value_at(i, 0);
        v[i] = kind_of(i) == K_BIT    ? ks_vcd_var_bit(vcd, name, (int)init)
               : kind_of(i) == K_ENUM ? ks_vcd_var_enum(vcd, name, enum_names, 3, (unsigned)init)
                                      : ks_vcd_var_int(vcd, name, 64, init);
        TB_CHECK(v[i] != NULL, "declaration %u refused", i);
    }
    /* expected body after "$dumpvars ... $end": times 1 and 2 */
    size_t cap = (size_t)NV * 3100 * 2 + 4096;
    char *expect = malloc(cap), *e = expect;
    for (int t = 1; t <= 2; t++) {
        ks_sim_run(sim, t);
        TB_EQ_INT(ks_sim_now(sim), t);
        e += sprintf(e, "#%d\n", t);
        for (unsigned i = 0; i < NV; i++) {
            /* visit in a scrambled order: the output follows the order of
             * the first change */
            unsigned j = (unsigned)(((uint64_t)i * 2654435761u + (unsigned)t) % NV);
            uint64_t nv = value_at(j, t), old = cur[j];
            if (j % 11 == 0) { /* glitch: away and back within the time stamp */
                ks_vcd_set(v[j], old ^ 1);
                ks_vcd_set(v[j], old);
                continue;
            }
            ks_vcd_set(v[j], nv);
            cur[j] = nv;
            if (nv != old)
                put_line(&e, j, nv);
        }
    }
    ks_sim_run(sim, 3);
    e += sprintf(e, "#3\n");
    TB_EQ_INT(ks_vcd_close(vcd), 0);
    size_t len = 0;
    char *txt = tb_read_file(path, &len);
    TB_CHECK(txt != NULL, "no file");
    const char *body = txt ? strstr(txt, "$dumpvars\n") : NULL;
    body = body ? strstr(body, "$end\n") : NULL;
    TB_CHECK(body != NULL, "no $dumpvars section");
    if (body) {
        body += 5;
        size_t elen = (size_t)(e - expect);
        TB_CHECK(len > 300000, "file of %zu bytes: smaller than intended", len);
        TB_EQ_INT(strlen(body), elen);
        size_t k = 0;
        while (body[k] && body[k] == expect[k])
            k++;
        TB_CHECK(k == elen && !body[k], "body differs at byte %zu: got '%.60s' expected '%.60s'", k,
                 body + k, expect + k);
    }
    free(txt);
    free(v);
    free(cur);
    remove(path);
    free(expect);
    ks_sim_destroy(sim);
    tb_end();
    return tb_finish();
}
