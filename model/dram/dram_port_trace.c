/* dram_port_trace.c — a trace through producer -> dram_port -> consumer (dram_port_trace.h). */
#include "model/dram/dram_port_trace.h"

#include <stdlib.h>
#include <string.h>

#include "kernel/clock.h"
#include "kernel/fifo.h"
#include "kernel/interrupt.h"
#include "kernel/sim.h"
#include "model/dram/dram_port.h"
#include "model/dram/dram_trace.h"

typedef struct trace_run {
    ks_sim *sim;
    ks_fifo *req, *resp;
    dram_port *port;
    ks_clocked *prod;
    dram_trace_reader rd;
    int ended, failed, interrupted;
    uint32_t size;
    dram_trace_result *res;
    char *err;
    size_t errlen;
} trace_run;

/* Producer: fills the request FIFO from the trace, in order. */
static int produce(void *user, uint64_t cycle)
{
    (void)cycle;
    trace_run *t = user;
    int made = 0;
    while (!t->ended && ks_fifo_can_write(t->req)) {
        if (ks_interrupted()) {
            /* Ctrl-C/SIGTERM (kernel/interrupt.h): stop where the run is */
            t->interrupted = 1;
            t->ended = 1;
            ks_sim_stop(t->sim);
            break;
        }
        uint64_t addr;
        int w;
        const int k = dram_trace_next(&t->rd, &addr, &w, t->err, t->errlen);
        if (k == 0) {
            t->ended = 1;
            dram_port_input_done(t->port);
            break;
        }
        if (k < 0) {
            t->failed = 1;
            t->ended = 1;
            ks_sim_stop(t->sim);
            break;
        }
        const dram_port_req r = {addr, (uint64_t)t->rd.line, t->size, (uint8_t)w};
        ks_fifo_write(t->req, &r);
        t->res->requests++;
        if (w)
            t->res->writes++;
        else
            t->res->reads++;
        made++;
    }
    return made;
}

static int consume(void *user, uint64_t cycle)
{
    (void)cycle;
    trace_run *t = user;
    int made = 0;
    while (ks_fifo_read(t->resp, NULL))
        made++;
    return made;
}

int dram_port_trace_run(const dram_spec *spec, const dram_power_spec *power, FILE *f, const char *name,
                        dram_cmd_fn sink, void *sink_user, int exhaustive, dram_trace_result *res,
                        dram_summary *sum, char *err, size_t errlen)
{
    memset(res, 0, sizeof *res);
    trace_run t = {.rd = {.f = f, .name = name, .capacity = dram_spec_capacity_bytes(spec)}, .size = (uint32_t)spec->tx_bytes, .res = res, .err = err, .errlen = errlen};
    t.sim = ks_sim_create();
    /* 4 requests keep the port fed (it takes at most one per cycle); 64 responses
     * never fill between two consumer steps. Latency 0: the trace is there at once. */
    t.req = ks_fifo_create(t.sim, "dram.req", sizeof(dram_port_req), 4, 0, NULL);
    t.resp = ks_fifo_create(t.sim, "dram.resp", sizeof(dram_port_resp), 64, 0, NULL);
    t.port = dram_port_create(t.sim, "dram", spec, power, t.req, t.resp, NULL, err, errlen);
    if (!t.port) {
        ks_sim_destroy(t.sim);
        return 2;
    }
    dram_port_set_cmd_sink(t.port, sink, sink_user);
    dram_set_exhaustive(dram_port_ctrl(t.port), exhaustive);
    ks_clock_set_exhaustive(dram_port_clock(t.port), exhaustive);
    /* created after the port: stepped after it at each DRAM clock edge */
    t.prod = ks_clocked_create(dram_port_clock(t.port), "trace_producer", produce, &t);
    ks_clocked_wake_on(t.prod, ks_fifo_ev_freed(t.req));
    ks_clocked *cons = ks_clocked_create(dram_port_clock(t.port), "trace_consumer", consume, &t);
    ks_clocked_wake_on(cons, ks_fifo_ev_written(t.resp));
    produce(&t, 0); /* the trace is available from cycle 0, as in dram_trace_run */
    int rc = 0;
    if (!t.failed) {
        const ks_run_status st = ks_sim_run(t.sim, KS_TIME_MAX);
        if (t.failed) {
            rc = 2;
        } else if (t.interrupted) {
            rc = 3;
        } else if (st != KS_RUN_FINISHED || dram_port_outstanding(t.port) || !t.ended) {
            snprintf(err, errlen, "%s: kernel run ended '%s' with %llu requests outstanding: %.300s", name,
                     ks_run_status_name(st), (unsigned long long)dram_port_outstanding(t.port),
                     ks_sim_deadlock_report(t.sim));
            rc = 1;
        }
    } else {
        rc = 2;
    }
    if (rc == 0 || rc == 3)
        dram_summary_compute(dram_port_ctrl(t.port), power, sum);
    free(t.rd.buf);
    dram_port_destroy(t.port);
    ks_sim_destroy(t.sim);
    return rc;
}
