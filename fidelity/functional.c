/* functional.c — the functional level (see functional.h). */
#include "fidelity/functional.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "frame/frame.h"
#include "fidelity/fidelity_params.h"
#include "model/dram/dram_addrmap.h"
#include "model/mem/memsys_config.h"
#include "model/accel_config.h"
#include "tracer/trace/traverse.h"

/* One memory access of a ray: a node (L1 of its TRV) or a triangle (prim). */
typedef struct fn_access {
    uint64_t addr;
    uint8_t is_tri;
} fn_access;

typedef struct fn_slot {
    bool busy;
    fn_access *acc;
    uint32_t n, cap, next;
    rt_ray ray;
    rt_hit hit;
    uint32_t path;                /* index of its pixel in the run's pixel list */
    bool bounce;                  /* the ray is a bounce of that pixel's path */
} fn_slot;

typedef struct fn_state {
    const fid_job *job;
    const rt_bvh_image *img;
    rt_trv_params tp;
    rtsim_frame frame;
    cache_core *l1[FID_MAX_TRV], *l2, *prim;
    dram_spec spec;
    dram_addrmap map;
    uint32_t *open_row;           /* per (channel, rank, bank); UINT32_MAX = closed */
    uint32_t nbanks;
    uint32_t l2_line;
    fid_func *out;
    fn_slot *cur;                 /* slot being traced (event callback) */
    fid_func_attr *attr;          /* per pixel of the list (NULL: not asked) */
    fid_func_attr *owner;         /* the path the access being served is charged to */
    bool oom;
} fn_state;

static void record(fn_slot *s, uint64_t addr, uint8_t is_tri, fn_state *st)
{
    if (s->n == s->cap) {
        uint32_t cap = s->cap ? 2 * s->cap : 64;
        fn_access *a = realloc(s->acc, cap * sizeof *a);
        if (!a) {
            st->oom = true;
            return;
        }
        s->acc = a, s->cap = cap;
    }
    s->acc[s->n].addr = addr;
    s->acc[s->n].is_tri = is_tri;
    s->n++;
}

static void on_event(void *user, const rt_trv_event *ev)
{
    fn_state *st = user;
    if (ev->kind == RT_EV_VISIT)
        record(st->cur, st->img->node_base + (uint64_t)ev->a * st->img->node_bytes, 0, st);
    else if (ev->kind == RT_EV_TRI)
        record(st->cur, st->img->tri_base + (uint64_t)ev->a * RT_TRI_BYTES, 1, st);
}

/* Traces the slot's ray at once (its accesses are replayed later). */
static void trace_slot(fn_state *st, fn_slot *s, uint32_t trv)
{
    rt_trv_counts c = {0};
    s->n = s->next = 0;
    st->cur = s;
    if (!rt_trace_ray(st->img, &st->tp, &s->ray, &s->hit, &c, on_event, st))
        st->out->failed++;
    fid_func *o = st->out;
    o->rays++;
    o->visits += c.visits, o->box_tests += c.box_tests, o->leaves += c.leaves, o->tri_tests += c.tri_tests;
    o->pushes += c.pushes, o->pops += c.pops, o->culls += c.culls;
    o->trv_visits[trv] += c.visits;
    o->trv_leaves[trv] += c.leaves;
    if (st->attr) {
        float *a = st->attr[s->path];
        a[FID_ATTR_VISITS] += (float)c.visits;
        a[FID_ATTR_TRI_TESTS] += (float)c.tri_tests;
        if (s->bounce)
            a[FID_ATTR_BOUNCE_WORK] += (float)(c.visits + c.tri_tests);
        st->attr[s->path][FID_ATTR_RAYS] += 1.0f;
    }
    s->busy = true;
}

/* A line from main memory: bytes and row locality. */
static void dram_read(fn_state *st, uint64_t addr, uint32_t bytes)
{
    st->out->dram_bytes += bytes;
    st->out->dram_lines++;
    if (st->owner)
        (*st->owner)[FID_ATTR_DRAM_LINES] += 1.0f;
    dram_addr a;
    dram_addrmap_decode(&st->map, addr, &a);
    uint32_t b = (a.channel * (uint32_t)st->spec.ranks + a.rank) * (uint32_t)st->spec.banks + a.bank;
    if (b < st->nbanks) {
        if (st->open_row[b] == a.row)
            st->out->row_hits++;
        st->open_row[b] = a.row;
    }
}

/* An access through cache c (cache_core_touch: its misses filled at once),
 * each missing line read from next (NULL: DRAM). */
static void touch(fn_state *st, cache_core *c, uint64_t addr, uint32_t bytes, cache_core *next)
{
    uint64_t missed[CACHE_MAX_LINES_PER_ACCESS];
    const int n = cache_core_touch(c, addr, bytes, missed);
    const uint32_t line = cache_core_get_params(c)->line_bytes;
    for (int i = 0; i < n; i++) {
        if (next)
            touch(st, next, missed[i], line, NULL);
        else
            dram_read(st, missed[i], line);
    }
}

/* One access of a ray through its caches. */
static void do_access(fn_state *st, const fn_access *a, uint32_t trv)
{
    if (a->is_tri)
        touch(st, st->prim, a->addr, RT_TRI_BYTES, NULL);
    else
        touch(st, st->l1[trv], a->addr, st->img->node_bytes, st->l2);
}

static int make_cache(const rtcfg *cfg, const char *section, cache_core **out, char *err, size_t errlen)
{
    cache_params p;
    memsys_cache_params(cfg, section, &p);
    /* misses are filled at once: one MSHR in use at a time per access line */
    *out = cache_core_create(&p, err, errlen);
    return *out ? 0 : -1;
}

static double max2(double a, double b) { return a > b ? a : b; }

/* The busiest issue unit's work since start[] (updated to now): a TRV's
 * visits + leaves, the IST's tests (start[ntrv]). */
static double end_phase(const fid_func *o, double start[FID_MAX_TRV + 1])
{
    double busiest = (double)o->tri_tests - start[o->ntrv];
    start[o->ntrv] = (double)o->tri_tests;
    for (uint32_t i = 0; i < o->ntrv; i++) {
        double w = (double)(o->trv_visits[i] + o->trv_leaves[i]);
        busiest = max2(busiest, w - start[i]);
        start[i] = w;
    }
    return busiest;
}

/* The throughput model (functional.h). */
static void throughput(const fid_job *job, fid_func *o)
{
    const rtcfg *cfg = job->cfg;
    const fid_params *fp = fid_params_get();
    double clock = rtcfg_real(cfg, "machine.clock_mhz");
    double fifo_lat = (double)rtcfg_int(cfg, "fifo.ray_latency");
    double trv_depth = (double)accel_trv_depth_of(cfg);
    double trv_period = trv_depth + fifo_lat;   /* a looping ray's round trip */
    double ist_period = (double)rtcfg_int(cfg, "prim.hit_latency") + (double)rtcfg_int(cfg, "ist.latency") +
                        fp->ist_loop_extra;
    double l2_wait = (double)rtcfg_int(cfg, "node_l2.hit_latency") + fp->mem_side_fifo_cycles;
    double bpc = rtcfg_real(cfg, "memory.fixed_bandwidth_gbs") * 1000.0 / clock;   /* bytes per cycle */
    double slots = (double)rtcfg_int(cfg, "trv.count") * (double)rtcfg_int(cfg, "trv.slots");
    double l1_lines = (double)o->l1.miss_lines, l2_lines = (double)o->l2.miss_lines,
           prim_lines = (double)o->prim.miss_lines;
    double l2_miss_frac = l1_lines > 0 ? l2_lines / l1_lines : 0;
    double mean_line = o->dram_lines ? (double)o->dram_bytes / (double)o->dram_lines : 64.0;
    double service = bpc > 0 ? mean_line / bpc : 0;   /* cycles a line holds the data bus */
    double row_miss = o->dram_lines ? 1.0 - (double)o->row_hits / (double)o->dram_lines : 0;
    o->cyc_dram = bpc > 0 ? (double)o->dram_bytes / bpc : 0;
    double k = o->miss_scale > 0 ? o->miss_scale : 1.0;   /* fid_functional_retime */
    double cycles = 1;
    /* fixed point: cycles -> utilisation -> memory latency -> loops and
     * ray latency -> cycles (converges in a few steps: latency grows with
     * utilisation, cycles with latency, utilisation falls with cycles) */
    for (int it = 0; it < 20; it++) {
        double util = cycles > 0 ? fmin(o->cyc_dram / cycles, fp->max_util) : 0;
        /* queueing grows as u / (1 - u) (M/D/1 shape); its scale is fitted
         * to the LPDDR3 model, whose row misses and bank conflicts make the
         * effective service time far longer than a line's bus transfer */
        double mem = fp->dram_latency + row_miss * fp->row_miss_cycles + service +
                     (util > 0 ? util / (1.0 - util) * fp->queue_cycles : 0);
        double node_wait = (l2_wait + l2_miss_frac * mem) * k, mem_k = mem * k;
        double trv_loops_per_miss = 1.0 + node_wait / trv_period, ist_loops_per_miss = 1.0 + mem_k / ist_period;
        double busiest_trv = 0;
        for (uint32_t i = 0; i < o->ntrv; i++)
            busiest_trv = max2(busiest_trv, (double)o->trv_visits[i] + (double)o->trv_leaves[i] +
                                                (double)o->trv_l1_miss_lines[i] * trv_loops_per_miss);
        o->cyc_trv = busiest_trv;
        o->cyc_ist = (double)o->tri_tests + prim_lines * ist_loops_per_miss;
        /* summed ray latencies: each pass a round trip, each leaf the IST's
         * depth, each miss its wait (Little: cycles >= sum / rays in flight) */
        double lat_sum = ((double)o->visits + (double)o->leaves) * trv_period +
                         (double)o->leaves * (ist_period + 2 * fifo_lat) + (double)o->tri_tests +
                         l1_lines * node_wait * fp->miss_waiters + prim_lines * mem_k * fp->miss_waiters;
        o->cyc_lat = lat_sum / slots;
        double next = max2(max2(o->cyc_trv, o->cyc_ist), max2(o->cyc_dram, o->cyc_lat));
        o->mem_latency = mem;
        o->dram_util = util;
        if (fabs(next - cycles) < 0.5)
            break;
        cycles = next;
    }
    double b[4] = {o->cyc_trv, o->cyc_ist, o->cyc_dram, o->cyc_lat};
    static const char *const names[4] = {"trv", "ist", "dram", "latency"};
    int top = 0;
    for (int i = 1; i < 4; i++)
        if (b[i] > b[top])
            top = i;
    double second = 0;
    for (int i = 0; i < 4; i++)
        if (i != top && b[i] > second)
            second = b[i];
    o->bound = names[top];
    /* fill and drain: the last rays admitted (and their bounces) finish one
     * path latency after the bound; each ray's latency is Little's
     * slots x cycles / rays, at least its unloaded latency */
    double rays = (double)o->rays, prim = o->primaries ? (double)o->primaries : 1;
    double ray_lat = rays > 0 ? fmax(slots * b[top] / rays, o->cyc_lat * slots / rays) : 0;
    o->cyc_tail = ray_lat * (rays / prim);
    o->cyc_bound = b[top];
    o->cycles = ceil(b[top] + o->cyc_tail);
    o->runner_up = b[top] > 0 ? second / b[top] : 0;
    o->clock_mhz = clock;
    o->mrps = o->cycles > 0 ? (double)o->rays / (o->cycles / (clock * 1e6)) / 1e6 : 0;
}

void fid_functional_retime(const fid_job *job, fid_func *f, double miss_scale)
{
    f->miss_scale = miss_scale;
    throughput(job, f);
}

static void add_cache(cache_stats *s, const cache_stats *f)
{
    s->accesses += f->accesses, s->hits += f->hits, s->misses += f->misses, s->miss_lines += f->miss_lines;
    s->fills += f->fills, s->evictions += f->evictions, s->bytes_filled += f->bytes_filled;
}

void fid_functional_add(fid_func *sum, const fid_func *f)
{
    sum->ntrv = f->ntrv;
    sum->rays += f->rays, sum->primaries += f->primaries, sum->bounces += f->bounces, sum->failed += f->failed;
    sum->visits += f->visits, sum->box_tests += f->box_tests, sum->leaves += f->leaves, sum->tri_tests += f->tri_tests;
    sum->pushes += f->pushes, sum->pops += f->pops, sum->culls += f->culls;
    for (uint32_t i = 0; i < f->ntrv && i < FID_MAX_TRV; i++) {
        sum->trv_visits[i] += f->trv_visits[i], sum->trv_leaves[i] += f->trv_leaves[i];
        sum->trv_l1_miss_lines[i] += f->trv_l1_miss_lines[i];
    }
    add_cache(&sum->l1, &f->l1);
    add_cache(&sum->l2, &f->l2);
    add_cache(&sum->prim, &f->prim);
    sum->dram_bytes += f->dram_bytes, sum->dram_lines += f->dram_lines, sum->row_hits += f->row_hits;
    sum->phase_excess = 0;
}

int fid_functional_run(const fid_job *job, const uint32_t *pixels, uint32_t npix, fid_func *out, char *err,
                       size_t errlen)
{
    return fid_functional_run_attributed(job, pixels, npix, out, NULL, err, errlen);
}

int fid_functional_run_attributed(const fid_job *job, const uint32_t *pixels, uint32_t npix, fid_func *out,
                                  fid_func_attr *attr, char *err, size_t errlen)
{
    return fid_functional_run_snap(job, pixels, npix, out, attr, NULL, 0, err, errlen);
}

void fid_functional_snap_free(fid_func_snap *s)
{
    for (uint32_t i = 0; i < s->ntrv && i < FID_MAX_TRV; i++)
        cache_core_destroy(s->l1[i]);
    cache_core_destroy(s->l2);
    cache_core_destroy(s->prim);
    memset(s->l1, 0, sizeof s->l1);
    s->l2 = s->prim = NULL;
}

/* A copy of c's contents in a new core, or NULL. */
static cache_core *clone_core(const cache_core *c)
{
    char err[160];
    cache_core *d = cache_core_create(cache_core_get_params(c), err, sizeof err);
    if (d && cache_core_copy_contents(d, c)) {
        cache_core_destroy(d);
        d = NULL;
    }
    return d;
}

static int take_snap(fn_state *st, uint32_t ntrv, fid_func_snap *s)
{
    s->ntrv = ntrv;
    bool ok = true;
    for (uint32_t i = 0; i < ntrv; i++)
        ok = (s->l1[i] = clone_core(st->l1[i])) != NULL && ok;
    ok = (s->l2 = clone_core(st->l2)) != NULL && ok;
    ok = (s->prim = clone_core(st->prim)) != NULL && ok;
    return ok ? 0 : -1;
}

int fid_functional_run_snap(const fid_job *job, const uint32_t *pixels, uint32_t npix, fid_func *out,
                            fid_func_attr *attr, fid_func_snap *snaps, uint32_t nsnap, char *err, size_t errlen)
{
    uint32_t snap_next = 0;
    fn_state st;
    memset(&st, 0, sizeof st);
    memset(out, 0, sizeof *out);
    if (attr && pixels)
        memset(attr, 0, (size_t)npix * sizeof *attr);
    st.attr = pixels ? attr : NULL;
    st.job = job;
    st.img = job->img;
    st.out = out;
    const rtcfg *cfg = job->cfg;
    uint32_t ntrv = (uint32_t)rtcfg_int(cfg, "trv.count"), per = (uint32_t)rtcfg_int(cfg, "trv.slots");
    if (ntrv > FID_MAX_TRV) {
        snprintf(err, errlen, "trv.count = %u: the functional level supports at most %d TRVs", ntrv, FID_MAX_TRV);
        return -1;
    }
    out->ntrv = ntrv;
    accel_params ap;
    accel_params_get(cfg, &ap);
    rtsim_trv_params(&ap, job->img->width, &st.tp);
    accel_source src;
    int rc = -1;
    uint32_t nslots = ntrv * per;
    fn_slot *slots = calloc(nslots, sizeof *slots);
    if (!slots) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    if (!rtsim_frame_init(&st.frame, job->cfg, job->mesh, job->view, job->width, job->height, job->diffuse, job->bounces,
                          job->seed, false, &src, err, errlen))
        goto done;
    for (uint32_t i = 0; i < ntrv; i++)
        if (make_cache(cfg, "node_l1", &st.l1[i], err, errlen))
            goto done;
    if (make_cache(cfg, "node_l2", &st.l2, err, errlen) || make_cache(cfg, "prim", &st.prim, err, errlen))
        goto done;
    {
        char path[RTCFG_PATH_MAX], why[RTCFG_MSG_MAX];
        const char *file = rtcfg_str(cfg, "memory.dram_config");
        if (memsys_dram_path(cfg, path, sizeof path)) {
            snprintf(err, errlen, "memory.dram_config = %s: path longer than %d characters", file, RTCFG_PATH_MAX - 1);
            goto done;
        }
        if (dram_spec_load(&st.spec, path, NULL, 0, why, sizeof why) || dram_addrmap_init(&st.map, &st.spec, why, sizeof why)) {
            snprintf(err, errlen, "memory.dram_config = %s: %s", file, why);
            goto done;
        }
        st.nbanks = (uint32_t)(st.spec.channels * st.spec.ranks * st.spec.banks);
        st.open_row = malloc(st.nbanks * sizeof *st.open_row);
        if (!st.open_row) {
            snprintf(err, errlen, "out of memory");
            goto done;
        }
        memset(st.open_row, 0xff, st.nbanks * sizeof *st.open_row);
    }
    uint64_t total = pixels ? npix : (uint64_t)job->width * job->height, next_primary = 0;
    uint32_t busy = 0;
    /* phases: each unit's issue work when the last one ended (ntrv: the IST) */
    const uint32_t phases = (uint32_t)fid_params_get()->func_phases;
    double phase_start[FID_MAX_TRV + 1] = {0}, phase_sum = 0;
    uint32_t phase = 0;
    for (;;) {
        while (phase + 1 < phases && next_primary > 0 && next_primary >= (phase + 1) * total / phases) {
            phase_sum += end_phase(out, phase_start);
            phase++;
        }
        /* refill: a finished slot takes its bounce or the next primary */
        for (uint32_t k = 0; k < nslots; k++) {
            fn_slot *s = &slots[k];
            uint32_t trv = k % ntrv;   /* round-robin over the TRVs */
            if (s->busy && s->next < s->n)
                continue;
            if (s->busy) {
                s->busy = false;
                busy--;
                rt_ray nx;
                if (job->diffuse && rt_bounce_ray(job->mesh, &s->ray, &s->hit, job->seed, job->bounces, &nx)) {
                    s->ray = nx;
                    s->bounce = true;
                    out->bounces++;
                    trace_slot(&st, s, trv);
                    busy++;
                    continue;
                }
            }
            while (snap_next < nsnap && next_primary >= snaps[snap_next].at)
                if (take_snap(&st, ntrv, &snaps[snap_next++]))
                    st.oom = true;
            if (next_primary < total) {
                uint64_t p = pixels ? pixels[next_primary] : next_primary;
                s->path = (uint32_t)next_primary, s->bounce = false;
                next_primary++;
                s->ray = rtsim_frame_camera_ray(&st.frame, p);   /* p: a position in the pixel order */
                out->primaries++;
                trace_slot(&st, s, trv);
                busy++;
            }
        }
        if (st.oom) {
            snprintf(err, errlen, "out of memory");
            goto done;
        }
        if (!busy)
            break;
        /* one round: the next access of every busy slot */
        for (uint32_t k = 0; k < nslots; k++) {
            fn_slot *s = &slots[k];
            if (s->busy && s->next < s->n) {
                st.owner = st.attr ? &st.attr[s->path] : NULL;
                do_access(&st, &s->acc[s->next++], k % ntrv);
            }
        }
    }
    for (uint32_t i = 0; i < ntrv; i++) {
        cache_stats cs;
        cache_core_get_stats(st.l1[i], &cs);
        out->trv_l1_miss_lines[i] = cs.miss_lines;
        add_cache(&out->l1, &cs);
    }
    cache_core_get_stats(st.l2, &out->l2);
    cache_core_get_stats(st.prim, &out->prim);
    phase_sum += end_phase(out, phase_start);
    double from_start[FID_MAX_TRV + 1] = {0}, busiest = end_phase(out, from_start);   /* over the whole run */
    out->phase_excess = busiest > 0 ? phase_sum / busiest - 1.0 : 0;
    throughput(job, out);
    rc = 0;
done:
    for (uint32_t k = 0; k < nslots; k++)
        free(slots[k].acc);
    free(slots);
    for (uint32_t i = 0; i < ntrv && i < FID_MAX_TRV; i++)
        cache_core_destroy(st.l1[i]);
    cache_core_destroy(st.l2);
    cache_core_destroy(st.prim);
    free(st.open_row);
    rtsim_frame_free(&st.frame);
    return rc;
}
