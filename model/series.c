/* series.c — interval statistics of a run (contract in series.h). */
#include "model/series.h"

#include <stdlib.h>
#include <string.h>

struct accel_series {
    FILE *out;
    uint64_t interval, next;       /* cycles per row; where the next row ends */
    bool header;                   /* write the header at the start */
    uint32_t piece;
    char phase[16];
    uint32_t ntrv;
    double clock_mhz;
    energy_model *em;
    accel_series_point prev;       /* where the current row began */
    uint64_t *prev_busy;           /* its TRV busy cycles (prev.trv_busy points here) */
    energy_activity prev_act;
};

accel_series *accel_series_create(FILE *out, uint64_t interval, bool header)
{
    accel_series *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->out = out;
    s->interval = interval ? interval : 1;
    s->header = header;
    accel_series_label(s, 0, "frame");
    return s;
}

void accel_series_destroy(accel_series *s)
{
    if (!s)
        return;
    free(s->prev_busy);
    free(s);
}

void accel_series_label(accel_series *s, uint32_t piece, const char *phase)
{
    s->piece = piece;
    snprintf(s->phase, sizeof s->phase, "%s", phase);
}

void accel_series_write_header(FILE *out, uint32_t ntrv)
{
    fputs("piece,phase,cycle_begin,cycle_end,cycles,rays_admitted,rays_completed,rays_in_flight_mean,"
          "rays_in_flight_end,mrps,trv_utilization",
          out);
    for (uint32_t i = 0; i < ntrv; i++)
        fprintf(out, ",trv%u_utilization", i);
    fputs(",ist_utilization,node_l1_accesses,node_l1_hit_rate,node_l2_accesses,node_l2_hit_rate,prim_accesses,"
          "prim_hit_rate,dram_bytes,dram_bandwidth_gbs,dram_row_hit_rate,dram_queue_mean",
          out);
    for (int u = 0; u < EU_COUNT; u++)
        fprintf(out, ",power_%s_mw", energy_unit_name((energy_unit)u));
    fputs(",power_dynamic_mw\n", out);
}

void accel_series_start(accel_series *s, uint32_t ntrv, double clock_mhz, energy_model *em)
{
    s->ntrv = ntrv;
    s->clock_mhz = clock_mhz;
    s->em = em;
    free(s->prev_busy);
    s->prev_busy = calloc(ntrv ? ntrv : 1, sizeof *s->prev_busy);
    memset(&s->prev, 0, sizeof s->prev);
    s->prev.trv_busy = s->prev_busy;
    memset(&s->prev_act, 0, sizeof s->prev_act);
    s->next = s->interval;
    if (s->header) {
        accel_series_write_header(s->out, ntrv);
        s->header = false;
    }
}

uint64_t accel_series_next(const accel_series *s) { return s->next; }

/* A real as the CSV has it: %.10g, or an empty cell when not applicable. */
static void put_real(FILE *f, double v, bool valid)
{
    if (valid)
        fprintf(f, ",%.10g", v);
    else
        fputc(',', f);
}

static double ratio(uint64_t a, uint64_t b) { return b ? (double)a / (double)b : 0.0; }

void accel_series_sample(accel_series *s, const accel_series_point *p, const energy_activity *act)
{
    const accel_series_point *a = &s->prev;
    while (s->next <= p->cycle)
        s->next += s->interval;
    if (p->cycle <= a->cycle || !s->prev_busy)
        return;
    FILE *f = s->out;
    uint64_t cyc = p->cycle - a->cycle;
    double sec = (double)cyc / (s->clock_mhz * 1e6);
    fprintf(f, "%u,%s,%llu,%llu,%llu,%llu,%llu", s->piece, s->phase, (unsigned long long)a->cycle,
            (unsigned long long)p->cycle, (unsigned long long)cyc, (unsigned long long)(p->admitted - a->admitted),
            (unsigned long long)(p->completed - a->completed));
    put_real(f, ratio(p->in_flight_area - a->in_flight_area, cyc), true);
    fprintf(f, ",%llu", (unsigned long long)p->in_flight);
    put_real(f, sec > 0 ? (double)(p->completed - a->completed) / sec / 1e6 : 0.0, true);
    uint64_t busy = 0;
    for (uint32_t i = 0; i < s->ntrv; i++)
        busy += p->trv_busy[i] - a->trv_busy[i];
    put_real(f, ratio(busy, cyc * (s->ntrv ? s->ntrv : 1)), true);
    for (uint32_t i = 0; i < s->ntrv; i++)
        put_real(f, ratio(p->trv_busy[i] - a->trv_busy[i], cyc), true);
    put_real(f, ratio(p->ist_busy - a->ist_busy, cyc), true);
    for (int c = 0; c < 3; c++) {
        uint64_t acc = p->cache_acc[c] - a->cache_acc[c];
        fprintf(f, ",%llu", (unsigned long long)acc);
        put_real(f, ratio(p->cache_hit[c] - a->cache_hit[c], acc), acc > 0);
    }
    uint64_t bytes = p->dram_bytes - a->dram_bytes;
    fprintf(f, ",%llu", (unsigned long long)bytes);
    put_real(f, sec > 0 ? (double)bytes / sec / 1e9 : 0.0, true);
    uint64_t rows = p->row_accesses - a->row_accesses, dcyc = p->dram_cycles - a->dram_cycles;
    put_real(f, ratio(p->row_hits - a->row_hits, rows), p->dram && rows > 0);
    put_real(f, ratio(p->queue_sum - a->queue_sum, dcyc), p->dram && dcyc > 0);
    if (s->em && act) {
        energy_activity d;
        energy_activity_between(&s->prev_act, act, &d);
        energy_compute(s->em, &d, 0);
        double total = 0;
        for (int u = 0; u < EU_COUNT; u++) {
            put_real(f, s->em->r.dynamic_mj[u] / sec, true);   /* mJ / s = mW */
            total += s->em->r.dynamic_mj[u];
        }
        put_real(f, total / sec, true);
        s->prev_act = *act;
    } else {
        for (int u = 0; u <= EU_COUNT; u++)
            fputc(',', f);
    }
    fputc('\n', f);
    /* the next row begins here */
    memcpy(s->prev_busy, p->trv_busy, s->ntrv * sizeof *s->prev_busy);
    s->prev = *p;
    s->prev.trv_busy = s->prev_busy;
}
