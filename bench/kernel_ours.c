/* kernel_ours — the four kernel benchmark workloads on the rtsim kernel
 * (docs/kernel.md "Benchmarks"; the SystemC twin is kernel_systemc.cpp).
 *   kernel_ours a|b|c|d N [VCD_PATH]
 * a: ping-pong of N tokens through a depth-2 FIFO between two methods;
 * b: 500 MHz ring of 8 clocked stages, each moving a 32-byte item through a
 *    depth-4, 1-cycle FIFO every cycle, for N cycles;
 * c: 1000 methods re-triggering themselves after pseudo-random delays
 *    (1..1000 ns), N events in all;
 * d: b with VCD tracing of every stage (item id) and FIFO occupancy.
 * Prints "<seconds> <checksum>" (wall time of the simulation only). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/process.h"
#include "kernel/sim.h"
#include "kernel/vcd.h"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- a: ping-pong ---- */
typedef struct pp {
    ks_fifo *f;
    uint64_t n, sent, received, sum;
} pp;

static void pp_producer(void *u)
{
    pp *p = u;
    while (p->sent < p->n && ks_fifo_can_write(p->f)) {
        uint64_t v = p->sent++;
        KS_FIFO_WRITE(p->f, &v);
    }
}

static void pp_consumer(void *u)
{
    pp *p = u;
    uint64_t v;
    while (KS_FIFO_READ(p->f, &v)) {
        p->sum += v;
        p->received++;
    }
}

static uint64_t run_a(uint64_t n)
{
    ks_sim *sim = ks_sim_create();
    pp p = {0};
    p.n = n;
    p.f = ks_fifo_create(sim, "pp.fifo", sizeof(uint64_t), 2, 0, NULL);
    ks_method *prod = ks_method_create(sim, "pp.producer", pp_producer, &p);
    ks_method *cons = ks_method_create(sim, "pp.consumer", pp_consumer, &p);
    ks_method_sensitive(prod, ks_fifo_ev_freed(p.f));
    ks_method_sensitive(cons, ks_fifo_ev_written(p.f));
    ks_sim_run(sim, KS_TIME_MAX);
    if (p.received != n)
        fprintf(stderr, "ping-pong: received %llu of %llu\n", (unsigned long long)p.received,
                (unsigned long long)n);
    ks_sim_destroy(sim);
    return p.sum;
}

/* ---- b/d: pipeline ring ---- */
typedef struct item {
    uint32_t id, hops;
    uint64_t payload[3];
} item;

typedef struct stage {
    ks_fifo *in, *out;
    ks_vcd_var *id_var;
    uint64_t moved;
} stage;

/* Like the SystemC twin's sc_fifo nb_read / nb_write: the item is copied
 * out of the input FIFO and into the output FIFO. */
static int stage_step(void *u, uint64_t cycle)
{
    (void)cycle;
    stage *s = u;
    if (!ks_fifo_can_read(s->in) || !ks_fifo_can_write(s->out))
        return 0;
    item it;
    KS_FIFO_READ(s->in, &it);
    it.hops++;
    it.payload[0] += it.hops;
    KS_FIFO_WRITE(s->out, &it);
    ks_vcd_set(s->id_var, it.id);
    s->moved++;
    return 1;
}

static uint64_t run_ring(uint64_t cycles, const char *vcd_path)
{
    enum { STAGES = 8 };
    ks_sim *sim = ks_sim_create();
    ks_clock *clk = ks_clock_create(sim, "clk", 0);
    ks_vcd *vcd = NULL;
    if (vcd_path) {
        vcd = ks_vcd_open(sim, vcd_path, "1ps", 0, KS_TIME_MAX, NULL);
        if (!vcd) {
            fprintf(stderr, "%s\n", ks_sim_error(sim));
            exit(2);
        }
    }
    ks_fifo *f[STAGES];
    stage st[STAGES];
    char name[64];
    for (int i = 0; i < STAGES; i++) {
        snprintf(name, sizeof name, "ring.stage%d.in", i);
        f[i] = ks_fifo_create(sim, name, sizeof(item), 4, 1, clk);
    }
    for (int i = 0; i < STAGES; i++) {
        st[i].in = f[i];
        st[i].out = f[(i + 1) % STAGES];
        st[i].moved = 0;
        snprintf(name, sizeof name, "ring.stage%d.id", i);
        st[i].id_var = vcd ? ks_vcd_var_int(vcd, name, 32, 0) : NULL;
        snprintf(name, sizeof name, "ring.stage%d", i);
        ks_clocked *p = ks_clocked_create(clk, name, stage_step, &st[i]);
        ks_clocked_wake_on(p, ks_fifo_ev_written(st[i].in));
        ks_clocked_wake_on(p, ks_fifo_ev_freed(st[i].out));
    }
    for (int i = 0; i < STAGES; i++)
        for (int k = 0; k < 2; k++) {
            item it = {(uint32_t)(i * 2 + k), 0, {0, 0, 0}};
            ks_fifo_write(f[i], &it);
        }
    /* items preloaded at time 0 are ready at cycle 1: cycles 1..N move items, as
     * in the SystemC twin (whose stages preload at cycle 0) */
    ks_sim_run(sim, (ks_time)(cycles + 1) * ks_clock_period(clk) - 1);
    uint64_t sum = 0;
    for (int i = 0; i < STAGES; i++)
        sum += st[i].moved;
    if (vcd && ks_vcd_close(vcd)) {
        fprintf(stderr, "%s\n", ks_sim_error(sim));
        exit(1);
    }
    ks_sim_destroy(sim);
    return sum;
}

/* ---- c: timed re-triggering ---- */
typedef struct tproc {
    ks_method *m;
    uint64_t rng;
    uint64_t *count, limit;
} tproc;

static void tproc_fn(void *u)
{
    tproc *t = u;
    if (++*t->count >= t->limit)
        return;
    t->rng = t->rng * 6364136223846793005ull + 1442695040888963407ull;
    ks_time d = (ks_time)(1 + (t->rng >> 33) % 1000) * 1000; /* 1..1000 ns */
    ks_next_trigger_time(t->m, d);
}

static uint64_t run_c(uint64_t n)
{
    enum { PROCS = 1000 };
    ks_sim *sim = ks_sim_create();
    tproc *t = calloc(PROCS, sizeof *t);
    uint64_t count = 0;
    char name[32];
    for (int i = 0; i < PROCS; i++) {
        snprintf(name, sizeof name, "p%d", i);
        t[i].rng = (uint64_t)i * 0x9E3779B97F4A7C15ull + 1;
        t[i].count = &count;
        t[i].limit = n;
        t[i].m = ks_method_create(sim, name, tproc_fn, &t[i]);
    }
    ks_sim_run(sim, KS_TIME_MAX);
    uint64_t r = count ^ (uint64_t)ks_sim_now(sim);
    ks_sim_destroy(sim);
    free(t);
    return r;
}

int main(int argc, char **argv)
{
    if (argc < 3 || strlen(argv[1]) != 1 || !strchr("abcd", argv[1][0])) {
        fprintf(stderr, "usage: kernel_ours a|b|c|d N [VCD_PATH]\n");
        return 2;
    }
    char *end;
    uint64_t n = strtoull(argv[2], &end, 10);
    if (*end || n == 0) {
        fprintf(stderr, "kernel_ours: N must be a positive integer, got '%s'\n", argv[2]);
        return 2;
    }
    double t0 = now_s();
    uint64_t check = 0;
    switch (argv[1][0]) {
    case 'a': check = run_a(n); break;
    case 'b': check = run_ring(n, NULL); break;
    case 'c': check = run_c(n); break;
    case 'd': check = run_ring(n, argc > 3 ? argv[3] : "/dev/null"); break;
    }
    printf("%.6f %llu\n", now_s() - t0, (unsigned long long)check);
    return 0;
}
