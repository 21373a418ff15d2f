/* tb_kernel_vcd_fifo — a FIFO's automatically traced occupancy (sampled by
 * the VCD writer when a time stamp is written out, not recorded per change)
 * against a mirror: a plain integer variable the test sets with
 * ks_vcd_set after every FIFO operation, i.e. recorded per change. A random
 * workload (three FIFOs with latency 0 and 1, several operations per
 * process and cycle including write-then-read glitches, idle gaps, a method
 * doing FIFO operations in delta cycles at the same time stamp) runs with
 * the full window and with windows starting and ending mid-run. In every
 * file each FIFO line must be followed at once by its mirror's line with
 * the same value (both are listed at the same operation), every mirror line
 * must follow its FIFO's, and the $dumpvars values must agree. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/process.h"
#include "kernel/sim.h"
#include "kernel/vcd.h"
#include "testbench/tb.h"

enum { NF = 3 };

typedef struct world {
    ks_fifo *f[NF];
    ks_vcd_var *mirror[NF];
    ks_method *meth;
    ks_event kick;
    uint64_t rng;
    uint64_t cycles;
} world;

static uint32_t rnd(world *w, uint32_t n)
{
    w->rng = w->rng * 6364136223846793005ull + 1442695040888963407ull;
    return (uint32_t)((w->rng >> 33) % n);
}

static void mirror(world *w, int k) { ks_vcd_set(w->mirror[k], ks_fifo_occupancy(w->f[k])); }

/* A random mix of writes and reads on random FIFOs; returns the number done. */
static int random_ops(world *w, int n)
{
    int done = 0;
    for (int i = 0; i < n; i++) {
        int k = (int)rnd(w, NF);
        uint32_t item = rnd(w, 1000);
        if (rnd(w, 2)) {
            if (ks_fifo_write(w->f[k], &item)) {
                mirror(w, k);
                done++;
                if (rnd(w, 4) == 0 && ks_fifo_read(w->f[k], &item)) { /* glitch */
                    mirror(w, k);
                    done++;
                }
            }
        } else if (ks_fifo_read(w->f[k], &item)) {
            mirror(w, k);
            done++;
        }
    }
    return done;
}

typedef struct proc {
    world *w;
    ks_clocked *self;
} proc;

static int proc_step(void *u, uint64_t cycle)
{
    proc *p = u;
    world *w = p->w;
    if (cycle >= w->cycles)
        return 0;
    int r = random_ops(w, (int)rnd(w, 4));
    if (rnd(w, 5) == 0) /* more operations in a delta cycle of this time */
        ks_event_notify_delta(&w->kick);
    if (rnd(w, 6) == 0) /* idle gap: time stamps without any change */
        ks_clocked_sleep_until_cycle(p->self, cycle + 2 + rnd(w, 5));
    return 1 + r;
}

static void meth_fn(void *u)
{
    world *w = u;
    random_ops(w, 1 + (int)rnd(w, 3));
}

/* Runs the workload with a writer over [wb, we); 0 on success. */
static int run_world(const char *path, ks_time wb, ks_time we, uint64_t seed, uint64_t cycles)
{
    ks_sim *sim = ks_sim_create();
    ks_vcd *vcd = ks_vcd_open(sim, path, "1ps", wb, we, NULL);
    TB_CHECK(vcd != NULL, "open: %s", ks_sim_error(sim));
    if (!vcd) {
        ks_sim_destroy(sim);
        return -1;
    }
    ks_clock *clk = ks_clock_create(sim, "clk", 0);
    world w;
    memset(&w, 0, sizeof w);
    w.rng = seed;
    w.cycles = cycles;
    char name[64];
    for (int k = 0; k < NF; k++) {
        snprintf(name, sizeof name, "t.f%d", k);
        w.f[k] = ks_fifo_create(sim, name, sizeof(uint32_t), 3 + (uint32_t)k, k == 1 ? 0 : 1, clk);
        snprintf(name, sizeof name, "t.m%d", k);
        w.mirror[k] = ks_vcd_var_int(vcd, name, 32, 0);
    }
    ks_event_init(&w.kick, sim, "t.kick");
    w.meth = ks_method_create(sim, "t.meth", meth_fn, &w);
    ks_method_sensitive(w.meth, &w.kick);
    ks_method_dont_initialize(w.meth);
    proc procs[3];
    for (int i = 0; i < 3; i++) {
        procs[i].w = &w;
        snprintf(name, sizeof name, "t.p%d", i);
        procs[i].self = ks_clocked_create(clk, name, proc_step, &procs[i]);
    }
    ks_sim_set_deadlock_cycles(sim, 0);
    ks_sim_run(sim, KS_TIME_MAX);
    int rc = ks_vcd_close(vcd);
    ks_event_destroy(&w.kick);
    ks_sim_destroy(sim);
    return rc;
}

/* The identifier declared by "$var reg 32 <id> <leaf> $end" right after
 * `scope_line` (NULL: anywhere), or "" when missing. */
static void find_id(const char *txt, const char *scope_line, const char *leaf, char *id, size_t cap)
{
    id[0] = 0;
    const char *p = scope_line ? strstr(txt, scope_line) : txt;
    if (!p)
        return;
    char pat[64];
    snprintf(pat, sizeof pat, " %s $end\n", leaf);
    const char *e = strstr(p, pat);
    if (!e)
        return;
    const char *b = e;
    while (b > txt && b[-1] != ' ')
        b--;
    size_t n = (size_t)(e - b);
    if (n >= cap)
        n = cap - 1;
    memcpy(id, b, n);
    id[n] = 0;
}

/* Splits "b<bits> <id>" into value text and id; 0 if not such a line. */
static int parse_change(const char *line, char *val, char *id)
{
    if (line[0] != 'b')
        return 0;
    return sscanf(line + 1, "%70s %15s", val, id) == 2;
}

/* The checks described at the top; returns the number of FIFO lines. */
static long check_file(const char *path)
{
    char *txt = tb_read_file(path, NULL);
    TB_CHECK(txt != NULL, "no file %s", path);
    if (!txt)
        return -1;
    char fid[NF][16], mid[NF][16];
    for (int k = 0; k < NF; k++) {
        char scope[64], leaf[16];
        snprintf(scope, sizeof scope, "$scope module f%d $end\n", k);
        find_id(txt, scope, "occupancy", fid[k], sizeof fid[k]);
        snprintf(leaf, sizeof leaf, "m%d", k);
        find_id(txt, NULL, leaf, mid[k], sizeof mid[k]);
        TB_CHECK(fid[k][0] && mid[k][0], "ids of fifo %d not found", k);
    }
    char *body = strstr(txt, "$enddefinitions $end\n");
    TB_CHECK(body != NULL, "no header end");
    long fifo_lines = 0, mirror_lines = 0, mismatches = 0; /* only the first is reported */
    int in_dump = 0;
    char dump_f[NF][72], dump_m[NF][72];
    memset(dump_f, 0, sizeof dump_f);
    memset(dump_m, 0, sizeof dump_m);
    char prev_val[72] = "", prev_id[16] = "";
    for (char *line = body ? strchr(body, '\n') + 1 : NULL; line && *line;) {
        char *nl = strchr(line, '\n');
        if (nl)
            *nl = 0;
        char val[72], id[16];
        int is_change = parse_change(line, val, id);
        if (!strcmp(line, "$dumpvars"))
            in_dump = 1;
        else if (!strcmp(line, "$end"))
            in_dump = 0;
        for (int k = 0; is_change && k < NF; k++) {
            if (in_dump) {
                if (!strcmp(id, fid[k]))
                    snprintf(dump_f[k], sizeof dump_f[k], "%s", val);
                if (!strcmp(id, mid[k]))
                    snprintf(dump_m[k], sizeof dump_m[k], "%s", val);
                continue;
            }
            if (!strcmp(id, fid[k]))
                fifo_lines++;
            if (!strcmp(id, mid[k])) {
                mirror_lines++;
                if (strcmp(prev_id, fid[k]) || strcmp(prev_val, val))
                    mismatches++;
                TB_CHECK(mismatches > 1 || (!strcmp(prev_id, fid[k]) && !strcmp(prev_val, val)),
                         "%s: mirror line 'b%s %s' not preceded by fifo %d's same value (got 'b%s %s')",
                         path, val, id, k, prev_val, prev_id);
            }
        }
        if (is_change && !in_dump) {
            snprintf(prev_val, sizeof prev_val, "%s", val);
            snprintf(prev_id, sizeof prev_id, "%s", id);
        } else {
            prev_val[0] = prev_id[0] = 0;
        }
        line = nl ? nl + 1 : NULL;
    }
    TB_EQ_INT(fifo_lines, mirror_lines);
    TB_EQ_INT(mismatches, 0);
    for (int k = 0; k < NF; k++)
        TB_CHECK(!strcmp(dump_f[k], dump_m[k]), "%s: $dumpvars fifo %d 'b%s' mirror 'b%s'", path, k,
                 dump_f[k], dump_m[k]);
    free(txt);
    return fifo_lines;
}

static void tmp_path(char *buf, size_t cap, const char *name)
{
    const char *dir = getenv("RTSIM_TMP");
    tb_pathf(buf, cap, "%s/%s", dir && *dir ? dir : "/tmp", name);
}

int main(void)
{
    uint64_t cycles = tb_is_sanitized() ? 400 : 3000;
    char path[TB_PATH_MAX];
    const struct {
        const char *name;
        ks_time wb, we;
    } windows[] = {
        {"vcd_fifo_sampled_full_run", 0, KS_TIME_MAX},
        {"vcd_fifo_sampled_window_mid_run", 2000 * 101 + 700, 2000 * 250},
        {"vcd_fifo_sampled_window_on_edges", 2000 * 37, 2000 * 38},
    };
    for (unsigned c = 0; c < sizeof windows / sizeof windows[0]; c++)
        for (uint64_t seed = 1; seed <= 3; seed++) {
            char name[128];
            snprintf(name, sizeof name, "%s_seed%llu", windows[c].name, (unsigned long long)seed);
            tb_begin(name);
            tmp_path(path, sizeof path, "kernel_vcd_fifo.vcd");
            TB_EQ_INT(run_world(path, windows[c].wb, windows[c].we, seed, cycles), 0);
            long n = check_file(path);
            /* the workload must really change the occupancies in the window */
            TB_CHECK(windows[c].we - windows[c].wb > 2000 * 2 ? n > 20 : n >= 0, "only %ld fifo lines", n);
            remove(path);
            tb_end();
        }
    return tb_finish();
}
