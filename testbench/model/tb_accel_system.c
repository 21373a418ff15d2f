/* tb_accel_system.c — system testbench of the accelerator model: on every
 * built-in scene at reduced resolution, primary and diffuse rays, BVH2 and
 * MBVH4 machines, every ray's hit from the cycle-level model must equal the
 * reference traversal's (tracer/trace/traverse.h) bit for bit, and every ray's
 * event sequence (node visits, pushes, pops, culls, leaves, triangle tests,
 * done) must equal the reference log. Also: the diffuse ray count equals the
 * tracer's own diffuse ray set, the run is deterministic (same cycles and
 * statistics twice), and the undersized-FIFO deadlock is reported. Occlusion rays (AO of the primary
 * hits) are compared the same way on both machines, with no sort pass, and
 * their sort bypass is measured in cycles on a warm single-pass ray. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "frame/frame.h"
#include "model/accel_config.h"
#include "model/accel_top.h"
#include "model/mem/memsys_config.h"
#include "model/ray/sort_net.h"
#include "testbench/tb.h"
#include "tracer/io/builtin.h"
#include "tracer/trace/occlusion.h"
#include "tracer/trace/ray_set.h"
#include "tracer/trace/traverse.h"

typedef struct ev {
    uint8_t kind;
    uint32_t a, b;
    float t;
} ev;

typedef struct ev_list {
    ev *e;
    uint32_t n, cap;
} ev_list;

typedef struct ray_rec {
    rt_ray ray;
    rt_hit hit;
    uint64_t admit, done_cycle;
    bool done, failed;
} ray_rec;

typedef struct run_log {
    ev_list *lists;        /* per uid */
    ray_rec *recs;         /* per uid */
    uint32_t cap;
    uint64_t completed;
    bool oom;
} run_log;

static bool grow(run_log *l, uint32_t uid)
{
    if (uid < l->cap)
        return true;
    uint32_t nc = l->cap ? l->cap : 1024;
    while (nc <= uid)
        nc *= 2;
    ev_list *nl = realloc(l->lists, nc * sizeof *nl);
    if (nl)
        l->lists = nl;
    ray_rec *nr = realloc(l->recs, nc * sizeof *nr);
    if (nr)
        l->recs = nr;
    if (!nl || !nr) {
        l->oom = true;
        return false;
    }
    memset(l->lists + l->cap, 0, (nc - l->cap) * sizeof *nl);
    memset(l->recs + l->cap, 0, (nc - l->cap) * sizeof *nr);
    l->cap = nc;
    return true;
}

static void push_ev(ev_list *l, int kind, uint32_t a, uint32_t b, float t)
{
    if (l->n == l->cap) {
        uint32_t nc = l->cap ? l->cap * 2 : 64;
        ev *ne = realloc(l->e, nc * sizeof *ne);
        if (!ne)
            return;
        l->e = ne;
        l->cap = nc;
    }
    l->e[l->n++] = (ev){(uint8_t)kind, a, b, t};
}

static void model_event(void *user, uint32_t uid, int kind, uint32_t a, uint32_t b, float t)
{
    run_log *l = user;
    if (grow(l, uid))
        push_ev(&l->lists[uid], kind, a, b, t);
}

static void model_complete(void *user, uint32_t uid, const rt_ray *ray, const rt_hit *hit, uint64_t admit,
                           uint64_t done, bool failed)
{
    run_log *l = user;
    if (!grow(l, uid))
        return;
    l->recs[uid] = (ray_rec){*ray, *hit, admit, done, true, failed};
    l->completed++;
}

static void ref_event(void *user, const rt_trv_event *e) { push_ev(user, e->kind, e->a, e->b, e->t); }

static void log_free(run_log *l)
{
    for (uint32_t i = 0; i < l->cap; i++)
        free(l->lists[i].e);
    free(l->lists);
    free(l->recs);
    memset(l, 0, sizeof *l);
}

static bool same_float(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* When set, machine_cfg skips rtcfg_finish's cross-key checks: the one way
 * to build a machine the validator refuses, to test the run-time failure
 * reports that such a machine still gets. */
static bool skip_validation;

static rtcfg *machine_cfg(const char *preset, const char *const *sets, char *err, size_t errlen)
{
    rtcfg *cfg = rtcfg_create();
    if (!cfg || memsys_add_schemas(cfg, err, errlen) || accel_add_schemas(cfg, err, errlen) ||
        rtcfg_load(cfg, preset, err, errlen)) {
        rtcfg_destroy(cfg);
        return NULL;
    }
    for (int i = 0; sets && sets[i]; i++)
        if (rtcfg_set(cfg, sets[i], err, errlen)) {
            rtcfg_destroy(cfg);
            return NULL;
        }
    if (!skip_validation && rtcfg_finish(cfg, err, errlen)) {
        rtcfg_destroy(cfg);
        return NULL;
    }
    return cfg;
}

typedef struct totals {
    uint64_t rays, hit_mismatch, event_mismatch, events;
} totals;

/* Per-ray completion cycles of a run, by uid (for the idle-skipping check). */
typedef struct ray_times {
    uint64_t *admit, *done;
    uint64_t n, cycles;
} ray_times;

/* One run of the model with every ray compared against the reference:
 * scene x machine x ray type, plus extra --set overrides (stress), seed and
 * the kernel's exhaustive (no idle skipping) mode. times: when non-NULL,
 * receives every ray's admit/completion cycle. */
typedef struct case_spec {
    const char *preset, *memory;
    int width;                  /* 0: the preset's branching factor */
    bool diffuse, exhaustive;
    bool occlusion;             /* AO rays of the primary hits (rtsim_frame_occlusion) */
    uint32_t w, h;
    uint64_t seed;
    const char *const *extra;   /* NULL-terminated overrides, or NULL */
    const char *tag;            /* appended to the test name, or NULL */
} case_spec;

static void check_spec(const rt_scene *sc, const case_spec *cs, totals *tot, ray_times *times)
{
    char name[400], err[4096], memset_[64], widthset[64];
    const char *preset = cs->preset, *memory = cs->memory;
    int width = cs->width;
    bool diffuse = cs->diffuse;
    uint32_t w = cs->w, h = cs->h;
    snprintf(name, sizeof name, "system_%s_%s%s%.0d_%s_%ux%u_%s%s%s", sc->name, preset, width ? "_width" : "", width,
             diffuse ? "diffuse" : cs->occlusion ? "occlusion" : "primary", w, h, memory, cs->tag ? "_" : "",
             cs->tag ? cs->tag : "");
    tb_begin(name);
    snprintf(memset_, sizeof memset_, "memory.model=%s", memory);
    snprintf(widthset, sizeof widthset, "machine.branching=%d", width);
    /* odd widths: unaligned nodes, served by a two-bank node L1 (paper 3.1) */
    const char *sets[32] = {memset_, "node_l1.banks=2"};
    int ns = 2;
    if (width)
        sets[ns++] = widthset;
    for (int i = 0; cs->extra && cs->extra[i] && ns < 31; i++)
        sets[ns++] = cs->extra[i];
    sets[ns] = NULL;
    rtcfg *cfg = machine_cfg(preset, sets, err, sizeof err);
    if (!TB_CHECK(cfg != NULL, "config: %s", err)) {
        tb_end();
        return;
    }
    rt_bvh_params bp;
    rtsim_bvh_params(cfg, &bp);
    rt_bvh_image img;
    memset(&img, 0, sizeof img);
    run_log log = {0};
    rtsim_frame fr;
    memset(&fr, 0, sizeof fr);
    accel_top *top = NULL;
    if (!TB_CHECK(rt_bvh_build(&sc->mesh, &bp, &img, NULL, err, sizeof err), "bvh: %s", err))
        goto out;
    accel_source src;
    if (!TB_CHECK(rtsim_frame_init(&fr, cfg, &sc->mesh, &sc->views.v[0], w, h, diffuse, 4, cs->seed ? cs->seed : 1, false,
                                   &src, err, sizeof err),
                  "%s", err))
        goto out;
    if (cs->occlusion && !TB_CHECK(rtsim_frame_occlusion(&fr, &img, RT_AO_SAMPLES_DEFAULT, &src, err, sizeof err), "%s", err))
        goto out;
    fr.hook = model_complete;
    fr.hook_user = &log;
    accel_image aimg = rtsim_image(&img);
    accel_top_opts o = {0};
    o.events = model_event;
    o.events_user = &log;
    o.exhaustive = cs->exhaustive;
    top = accel_top_create(cfg, &aimg, &src, &o, err, sizeof err);
    if (!TB_CHECK(top != NULL, "create: %s", err))
        goto out;
    int rc = accel_top_run(top, NULL, NULL, err, sizeof err);
    if (!TB_CHECK(rc == 0, "run failed: %s", err))
        goto out;
    TB_CHECK(!log.oom, "out of memory in the log");
    TB_EQ_INT(log.completed, accel_top_rays(top));
    TB_CHECK(accel_top_cycles(top) > 0, "cycles counted");

    /* every ray against the reference traversal */
    rt_trv_params tp;
    rt_trv_params_default(&tp, bp.width);
    tp.stack_depth = (int)rtcfg_int(cfg, "trv.stack_depth");
    tp.distance_cull = accel_top_params(top)->trv.core.distance_cull;
    uint64_t hit_bad = 0, ev_bad = 0, nev = 0;
    ev_list ref = {0};
    for (uint32_t uid = 0; uid < log.completed && uid < log.cap; uid++) {
        const ray_rec *r = &log.recs[uid];
        if (!r->done) {
            hit_bad++;
            continue;
        }
        rt_hit rh;
        ref.n = 0;
        bool ok = rt_trace_ray(&img, &tp, &r->ray, &rh, NULL, ref_event, &ref);
        if (!ok || r->failed || rh.prim != r->hit.prim || !same_float(rh.t, r->hit.t) || !same_float(rh.u, r->hit.u) ||
            !same_float(rh.v, r->hit.v)) {
            if (hit_bad++ == 0)
                TB_CHECK(0, "ray %u (pixel %u bounce %u): model prim %u t %.9g, reference prim %u t %.9g", uid,
                         r->ray.pixel, r->ray.bounce, r->hit.prim, r->hit.t, rh.prim, rh.t);
        }
        const ev_list *m = &log.lists[uid];
        nev += m->n;
        bool same = m->n == ref.n;
        uint32_t first = 0;
        for (uint32_t i = 0; same && i < m->n; i++) {
            const ev *a = &m->e[i], *b = &ref.e[i];
            if (a->kind != b->kind || a->a != b->a || a->b != b->b || !same_float(a->t, b->t)) {
                same = false;
                first = i;
            }
        }
        if (!same && ev_bad++ == 0)
            TB_CHECK(0, "ray %u: event sequences differ (model %u events, reference %u; first difference at %u)", uid,
                     m->n, ref.n, first);
    }
    free(ref.e);
    TB_EQ_INT(hit_bad, 0);
    TB_EQ_INT(ev_bad, 0);
    tot->rays += log.completed;
    tot->hit_mismatch += hit_bad;
    tot->event_mismatch += ev_bad;
    tot->events += nev;

    /* ray count: the tracer's own primary + diffuse set, or its occlusion set */
    rt_ray_set prim_set = {0}, dif_set = {0};
    if (TB_CHECK(rt_ray_set_primary(&sc->views.v[0], w, h, &prim_set, err, sizeof err), "%s", err)) {
        uint64_t want = prim_set.n;
        if (cs->occlusion) {
            rt_ray_set occ_set = {0};
            if (TB_CHECK(rt_ray_set_occlusion(&sc->mesh, &img, &tp, &prim_set, cs->seed ? cs->seed : 1,
                                              RT_AO_SAMPLES_DEFAULT, rt_ao_distance(&sc->mesh), &occ_set, err,
                                              sizeof err),
                         "%s", err)) {
                want = occ_set.n;
                /* the same rays: the set holds each hit pixel's samples
                 * consecutively, pixels in scanline order; the model admits
                 * them in the frame's pixel order (uid = admission order), so
                 * the uid-th ray is sample uid % S of its pixel in the set */
                const uint32_t S = RT_AO_SAMPLES_DEFAULT;
                uint32_t *first = malloc((size_t)w * h * sizeof *first);
                uint64_t differ = first ? 0 : 1;
                for (uint32_t i = 0; first && i < w * h; i++)
                    first[i] = UINT32_MAX;
                for (uint32_t i = 0; first && i < occ_set.n; i += S)
                    if (occ_set.rays[i].pixel < w * h)
                        first[occ_set.rays[i].pixel] = i;
                for (uint32_t i = 0; first && i < occ_set.n && i < log.cap && i < log.completed; i++) {
                    const rt_ray *b = &log.recs[i].ray;
                    const uint32_t j = b->pixel < w * h ? first[b->pixel] : UINT32_MAX;
                    if (j == UINT32_MAX || j + i % S >= occ_set.n) {
                        differ++;
                        continue;
                    }
                    const rt_ray *a = &occ_set.rays[j + i % S];
                    differ += memcmp(&a->org, &b->org, sizeof a->org) || memcmp(&a->dir, &b->dir, sizeof a->dir) ||
                              !same_float(a->tmax, b->tmax) || a->pixel != b->pixel || !b->occlusion;
                }
                free(first);
                TB_EQ_INT(differ, 0);
            }
            rt_ray_set_free(&occ_set);
            /* the sort bypass: no pass of an occlusion ray goes through the sorting network */
            double sorts = 0, visits = 0, v;
            char k[64];
            for (uint32_t i = 0; i < accel_top_params(top)->trv_count; i++) {
                snprintf(k, sizeof k, "trv%u.sort_passes", i);
                sorts += ks_stats_value(accel_top_stats(top), k, &v) == 0 ? v : 0;
                snprintf(k, sizeof k, "trv%u.visits", i);
                visits += ks_stats_value(accel_top_stats(top), k, &v) == 0 ? v : 0;
            }
            TB_CHECK(sorts == 0 && visits > 0, "occlusion rays: %g sort passes (want 0) in %g visits", sorts, visits);
            double occl = -1, occd = -1;
            ks_stats_value(accel_top_stats(top), "sched.occlusion_rays", &occl);
            ks_stats_value(accel_top_stats(top), "sched.occluded", &occd);
            TB_CHECK(occl == (double)log.completed && occd > 0 && occd < occl, "statistics: %g occlusion rays, %g occluded",
                     occl, occd);
        }
        if (diffuse && TB_CHECK(rt_ray_set_diffuse(&sc->mesh, &img, &tp, &prim_set, cs->seed ? cs->seed : 1, 4, &dif_set,
                                                   err, sizeof err),
                                "%s", err))
            want += dif_set.n;
        TB_EQ_INT(log.completed, want);
    }
    rt_ray_set_free(&prim_set);
    rt_ray_set_free(&dif_set);
    if (times && !log.oom) {
        times->n = log.completed < log.cap ? log.completed : log.cap;
        times->cycles = accel_top_cycles(top);
        times->admit = calloc(times->n ? times->n : 1, sizeof *times->admit);
        times->done = calloc(times->n ? times->n : 1, sizeof *times->done);
        for (uint64_t i = 0; times->admit && times->done && i < times->n; i++) {
            times->admit[i] = log.recs[i].admit;
            times->done[i] = log.recs[i].done_cycle;
        }
    }
    printf("INFO %s: %llu rays, %llu events, %llu cycles, %.2f MRPS, hit mismatches %llu, event mismatches %llu\n", name,
           (unsigned long long)log.completed, (unsigned long long)nev, (unsigned long long)accel_top_cycles(top),
           accel_top_mrps(top), (unsigned long long)hit_bad, (unsigned long long)ev_bad);
out:
    accel_top_destroy(top);
    rtsim_frame_free(&fr);
    log_free(&log);
    rt_bvh_image_free(&img);
    rtcfg_destroy(cfg);
    tb_end();
}

static void check_case_width(const rt_scene *sc, const char *preset, int width, const char *memory, bool diffuse,
                             uint32_t w, uint32_t h, totals *tot)
{
    case_spec cs = {.preset = preset, .memory = memory, .width = width, .diffuse = diffuse, .w = w, .h = h};
    check_spec(sc, &cs, tot, NULL);
}

static void check_case(const rt_scene *sc, const char *preset, const char *memory, bool diffuse, uint32_t w, uint32_t h,
                       totals *tot)
{
    check_case_width(sc, preset, 0, memory, diffuse, w, h, tot);
}

/* Builds the scene's BVH for the machine, runs one frame from its first view
 * with options o (NULL: defaults) and hands the finished top level to done
 * (with accel_top_run's result) before destroying it. Returns cycles, 0 on a
 * set-up failure (message in err). */
typedef void (*frame_done_fn)(accel_top *top, int rc, void *user);
static uint64_t run_frame_with(const rt_scene *sc, const char *preset, const char *const *sets, uint32_t w, uint32_t h,
                               bool diffuse, const accel_top_opts *o, frame_done_fn done, void *user, char *err,
                               size_t errlen, int *rc_out)
{
    rtcfg *cfg = machine_cfg(preset, sets, err, errlen);
    if (!cfg)
        return 0;
    rt_bvh_params bp;
    rtsim_bvh_params(cfg, &bp);
    rt_bvh_image img;
    uint64_t cycles = 0;
    rtsim_frame fr;
    memset(&fr, 0, sizeof fr);
    if (rt_bvh_build(&sc->mesh, &bp, &img, NULL, err, errlen)) {
        accel_source src;
        if (rtsim_frame_init(&fr, cfg, &sc->mesh, &sc->views.v[0], w, h, diffuse, 4, 1, false, &src, err, errlen)) {
            accel_image aimg = rtsim_image(&img);
            accel_top *top = accel_top_create(cfg, &aimg, &src, o, err, errlen);
            if (top) {
                int rc = accel_top_run(top, NULL, NULL, err, errlen);
                if (rc_out)
                    *rc_out = rc;
                cycles = accel_top_cycles(top);
                if (done)
                    done(top, rc, user);
                accel_top_destroy(top);
            }
        }
        rt_bvh_image_free(&img);
    }
    rtsim_frame_free(&fr);
    rtcfg_destroy(cfg);
    return cycles;
}

typedef struct json_out {
    char *buf;
    size_t len;
} json_out;

static void frame_json(accel_top *top, int rc, void *user)
{
    (void)rc;
    json_out *j = user;
    FILE *f = fmemopen(j->buf, j->len, "w");
    if (f) {
        ks_stats_write_json(accel_top_stats(top), f);
        fclose(f);
    }
}

/* Runs a frame with a 20,000-cycle deadlock limit and returns cycles (0 on
 * failure, message in err); json (when non-NULL) receives the statistics. */
static uint64_t run_frame(const rt_scene *sc, const char *preset, const char *const *sets, uint32_t w, uint32_t h,
                          bool diffuse, char *json, size_t jsonlen, char *err, size_t errlen, int *rc_out)
{
    accel_top_opts o = {0};
    o.deadlock_cycles = 20000;
    json_out j = {json, jsonlen};
    return run_frame_with(sc, preset, sets, w, h, diffuse, &o, json ? frame_json : NULL, &j, err, errlen, rc_out);
}

typedef struct stat_sums {
    const char *const *names;
    double *vals;
    int n;
} stat_sums;

/* Each name's value; summed over the TRVs when it starts with "trv.". */
static void frame_stat_sums(accel_top *top, int rc, void *user)
{
    if (rc != 0)
        return;
    stat_sums *q = user;
    for (int i = 0; i < q->n; i++) {
        const char *name = q->names[i];
        for (int k = 0; k < 64; k++) {
            char nm[128];
            double v;
            if (strncmp(name, "trv.", 4))
                snprintf(nm, sizeof nm, "%s", name);
            else
                snprintf(nm, sizeof nm, "trv%d.%s", k, name + 4);
            if (ks_stats_value(accel_top_stats(top), nm, &v))
                break;
            q->vals[i] += v;
            if (strncmp(name, "trv.", 4))
                break;
        }
    }
}

/* Runs an MBVH4 64x36 primary frame; returns cycles (0 when it failed) and
 * the named statistics (0 when absent). */
static uint64_t run_stats(const rt_scene *sc, const char *const *sets, const char *const *names, double *vals, int n,
                          char *err, size_t errlen)
{
    for (int i = 0; i < n; i++)
        vals[i] = 0;
    stat_sums q = {names, vals, n};
    int rc = 1;
    uint64_t cycles = run_frame_with(sc, "mbvh4", sets, 64, 36, false, NULL, frame_stat_sums, &q, err, errlen, &rc);
    return rc == 0 ? cycles : 0;
}

static void test_banks_and_looping(const rt_scene *sc)
{
    char err[4096];
    static const char *const names[] = {"trv.stack_conflict_cycles", "trv.loops_miss", "trv.visits", "ist.loops_miss"};
    double base[4] = {0}, one[4] = {0};
    tb_begin("system_stack_bank_conflicts");
    static const char *const fixed[] = {"memory.model=fixed", NULL};
    static const char *const onebank[] = {"memory.model=fixed", "trv.stack_banks=1", NULL};
    uint64_t c_base = run_stats(sc, fixed, names, base, 4, err, sizeof err);
    uint64_t c_one = run_stats(sc, onebank, names, one, 4, err, sizeof err);
    TB_CHECK(c_base > 0 && c_one > 0, "runs: %s", err);
    /* with N-1 = 3 banks only pops that cull several entries conflict */
    TB_CHECK(one[0] > 4 * base[0], "1 bank: many more conflict cycles (%g vs %g)", one[0], base[0]);
    TB_CHECK(c_one > c_base, "conflicts cost cycles (%llu vs %llu)", (unsigned long long)c_one, (unsigned long long)c_base);
    TB_CHECK(one[2] == base[2], "same visits (%g vs %g)", one[2], base[2]);
    tb_end();

    tb_begin("system_looping_for_next_chance");
    /* cold caches and a slow memory: rays miss and loop; each loop costs a
     * pass but the committed work (visits) is unchanged */
    static const char *const slow[] = {"memory.model=fixed", "memory.fixed_latency=400", NULL};
    double sl[4] = {0};
    uint64_t c_slow = run_stats(sc, slow, names, sl, 4, err, sizeof err);
    TB_CHECK(c_slow > c_base, "slower memory, more cycles (%llu vs %llu): %s", (unsigned long long)c_slow,
             (unsigned long long)c_base, err);
    TB_CHECK(base[1] > 0 && base[3] > 0, "TRV and IST loop on misses (%g, %g)", base[1], base[3]);
    TB_CHECK(sl[1] > base[1], "more TRV loops with a slower memory (%g vs %g)", sl[1], base[1]);
    TB_CHECK(sl[2] == base[2], "same committed visits (%g vs %g)", sl[2], base[2]);
    tb_end();
}

static void test_determinism_and_deadlock(const rt_scene *sc)
{
    char err[8192];
    static char j1[1 << 16], j2[1 << 16];
    tb_begin("system_deterministic_repeat");
    int rc1 = -1, rc2 = -1;
    uint64_t c1 = run_frame(sc, "mbvh4", NULL, 24, 16, true, j1, sizeof j1, err, sizeof err, &rc1);
    uint64_t c2 = run_frame(sc, "mbvh4", NULL, 24, 16, true, j2, sizeof j2, err, sizeof err, &rc2);
    TB_CHECK(rc1 == 0 && rc2 == 0, "runs succeed: %s", err);
    TB_CHECK(c1 > 0 && c1 == c2, "same cycles twice (%llu, %llu)", (unsigned long long)c1, (unsigned long long)c2);
    TB_CHECK(strcmp(j1, j2) == 0, "identical statistics JSON");
    TB_CHECK(strstr(j1, "\"cycles\"") && strstr(j1, "\"rays\"") && strstr(j1, "\"mrps\"") && strstr(j1, "\"dram_bytes\""),
             "JSON has cycles, rays, mrps, dram_bytes");
    tb_end();

    tb_begin("system_deadlock_report_on_undersized_fifo");
    /* a one-entry loop FIFO: the TRV's exit stage waits for the loop FIFO,
     * which only its own (blocked) issue stage drains. The validator
     * refuses it (below the deadlock-free minimum, accel_config.h) ... */
    static const char *const sets[] = {"fifo.ray_trv_loop=1", NULL};
    int rc = -1;
    err[0] = 0;
    rtcfg *refused = machine_cfg("mbvh4", sets, err, sizeof err);
    TB_CHECK(refused == NULL && strstr(err, "fifo.ray_trv_loop") && strstr(err, "must be >= trv.slots - stages + 1 = 24"),
             "validator refuses the machine naming the key and its minimum: %.300s", err);
    rtcfg_destroy(refused);
    /* ... and when it is bypassed, the kernel's detector reports who waits
     * on whom instead of hanging */
    skip_validation = true;
    err[0] = 0;
    run_frame(sc, "mbvh4", sets, 32, 32, false, NULL, 0, err, sizeof err, &rc);
    skip_validation = false;
    TB_EQ_INT(rc, 1);
    TB_CHECK(strstr(err, "deadlock") != NULL, "report says deadlock: %.200s", err);
    TB_CHECK(strstr(err, "trv0") != NULL, "report names the TRV: %.300s", err);
    TB_CHECK(strstr(err, "loop 1/1") != NULL, "report shows the full loop FIFO: %.400s", err);
    tb_end();
}

/* The sort bypass in cycles: one ray that misses the root's children (a
 * single TRV pass), traced twice in a row (the second time as the "bounce"
 * of the first, so the node L1 is warm and the pass never loops). Its
 * latency with the occlusion flag is exactly the sort layers shorter: 1
 * cycle for BVH2, 3 for MBVH4 (sort_net.h, paper sec. 3.1). */
typedef struct one_ray_src {
    accel_ray_in ray;
    uint64_t latency[2];
    uint64_t passes;
} one_ray_src;

static void one_ray_primary(void *user, uint64_t i, accel_ray_in *out)
{
    (void)i;
    *out = ((one_ray_src *)user)->ray;
}

static bool one_ray_again(void *user, const accel_ray_in *in, const accel_hit *hit, accel_ray_in *out)
{
    (void)hit;
    if (in->bounce)
        return false;
    *out = ((one_ray_src *)user)->ray;
    out->bounce = 1;
    return true;
}

static void one_ray_done(void *user, uint32_t uid, const accel_ray_in *in, const accel_hit *hit, uint64_t admit,
                         uint64_t done, uint32_t visits, uint32_t tri_tests, bool failed)
{
    (void)uid, (void)hit, (void)visits, (void)tri_tests, (void)failed;
    ((one_ray_src *)user)->latency[in->bounce ? 1 : 0] = done - admit;
}

static void test_sort_bypass_latency(const rt_scene *sc)
{
    static const char *const presets[] = {"bvh2", "mbvh4"};
    /* one TRV: the second trace meets the node L1 the first one filled */
    static const char *const fixed[] = {"memory.model=fixed", "trv.count=1", NULL};
    for (int m = 0; m < 2; m++) {
        char name[64], err[4096];
        snprintf(name, sizeof name, "system_sort_bypass_latency_%s", presets[m]);
        tb_begin(name);
        rtcfg *cfg = machine_cfg(presets[m], fixed, err, sizeof err);
        rt_bvh_params bp;
        rt_bvh_params_default(&bp);
        rt_bvh_image img;
        memset(&img, 0, sizeof img);
        if (!TB_CHECK(cfg != NULL, "%s", err) ||
            !TB_CHECK((bp.width = (int)rtcfg_int(cfg, "machine.branching"),
                       rt_bvh_build(&sc->mesh, &bp, &img, NULL, err, sizeof err)),
                      "%s", err)) {
            rtcfg_destroy(cfg);
            tb_end();
            continue;
        }
        rt_vec3 lo, hi;
        rt_mesh_bounds(&sc->mesh, &lo, &hi);
        uint64_t lat[2] = {0, 0}, passes[2] = {0, 0};
        for (int occ = 0; occ < 2; occ++) {
            /* from beyond the scene's upper corner, away from it: every root slot misses */
            one_ray_src o = {.ray = {{hi.x + 1, hi.y + 1, hi.z + 1}, {0.577f, 0.577f, 0.577f}, 0.0f, 1e30f, 0, 0,
                                     (uint8_t)occ}};
            accel_source src = {&o, 1, occ == 1, one_ray_primary, one_ray_again, one_ray_done};
            accel_image aimg = rtsim_image(&img);
            accel_top_opts opts = {0};
            accel_top *top = accel_top_create(cfg, &aimg, &src, &opts, err, sizeof err);
            if (!TB_CHECK(top != NULL, "%s", err))
                break;
            TB_CHECK(accel_top_run(top, NULL, NULL, err, sizeof err) == 0, "%s", err);
            /* committed passes: all passes but those invalidated by a node L1 miss or block */
            double v = 0, x;
            static const char *const keys[] = {"trv0.passes", "trv0.loops_miss", "trv0.loops_blocked"};
            for (int i = 0; i < 3; i++)
                v += (i ? -1 : 1) * (ks_stats_value(accel_top_stats(top), keys[i], &x) == 0 ? x : 0);
            passes[occ] = (uint64_t)v;
            lat[occ] = o.latency[1];
            accel_top_destroy(top);
        }
        const int layers = sort_net_get(bp.width)->layers;
        TB_CHECK(passes[0] == 2 && passes[1] == 2, "one committed pass per trace (%llu, %llu passes in all)",
                 (unsigned long long)passes[0], (unsigned long long)passes[1]);
        TB_CHECK(lat[0] > 0 && lat[1] + (uint64_t)layers == lat[0],
                 "warm single-pass latency: closest-hit %llu cycles, occlusion %llu, want %d fewer",
                 (unsigned long long)lat[0], (unsigned long long)lat[1], layers);
        printf("INFO %s: warm single-pass ray latency %llu cycles closest-hit, %llu occlusion (sort layers %d)\n", name,
               (unsigned long long)lat[0], (unsigned long long)lat[1], layers);
        rt_bvh_image_free(&img);
        rtcfg_destroy(cfg);
        tb_end();
    }
}

/* LPDDR3 stress configurations: tiny MSHR counts, one-entry memory-side FIFOs,
 * one request in flight at the memory; a lost or refused-then-forgotten line
 * shows up as a watchdog (livelock) or deadlock failure. (Not in them, as they
 * fail with any memory: one MSHR per cache livelocks the looping rays, and
 * one-entry leaf/return FIFOs deadlock the TRV-IST loop, like ray_trv_loop=1.) */
static const char *const stress_tiny[] = {
    "node_l1.mshrs=2", "node_l1.mshr_merge=1", "node_l2.mshrs=2", "node_l2.mshr_merge=1", "prim.mshrs=2",
    "prim.mshr_merge=1", "fifo.mem_l1_miss=1", "fifo.mem_l1_fill=1", "fifo.mem_l2_req=1", "fifo.mem_l2_resp=1",
    "fifo.mem_l2_miss=1", "fifo.mem_l2_fill=1", "fifo.mem_prim_miss=1", "fifo.mem_prim_fill=1", "fifo.mem_req=1",
    "fifo.mem_resp=1", "fifo.mem_dram_req=1", "fifo.mem_dram_resp=1", "memory.max_outstanding=1", NULL};
/* One MSHR in every cache: a triangle over two missing lines used to loop
 * forever in the primitive cache (all-or-nothing probes; model/mem/cache_core.h) */
static const char *const stress_one_mshr[] = {"node_l1.mshrs=1", "node_l2.mshrs=1", "prim.mshrs=1", NULL};
static const char *const stress_small[] = {
    "node_l1.mshrs=2", "node_l2.mshrs=2", "prim.mshrs=2", "prim.mshr_merge=2", "fifo.mem_req=2", "fifo.mem_resp=2",
    "fifo.mem_dram_req=2", "fifo.mem_dram_resp=1", "fifo.mem_prim_fill=1", "fifo.mem_l2_fill=1",
    "memory.max_outstanding=3", "fifo.mem_latency=3", "fifo.ray_new=1", "fifo.ray_done=1", NULL};

/* Idle skipping must not change anything: every ray's admit and completion
 * cycle with LPDDR3 equals the exhaustive (every unit, every cycle, both
 * clocks) run's. */
static void check_idle_skip_equivalence(const rt_scene *sc, case_spec cs, totals *tot)
{
    ray_times a = {0}, b = {0};
    cs.exhaustive = false;
    check_spec(sc, &cs, tot, &a);
    cs.exhaustive = true;
    const char *tag = cs.tag;
    char t2[64];
    snprintf(t2, sizeof t2, "%s%sexhaustive", tag ? tag : "", tag ? "_" : "");
    cs.tag = t2;
    check_spec(sc, &cs, tot, &b);
    char name[512];
    snprintf(name, sizeof name, "system_%s_%s_%s_idle_skip_equals_exhaustive%s%s", sc->name, cs.preset,
             cs.diffuse ? "diffuse" : cs.occlusion ? "occlusion" : "primary", tag ? "_" : "", tag ? tag : "");
    tb_begin(name);
    TB_CHECK(a.n > 0 && a.admit && b.admit, "both runs recorded rays");
    TB_EQ_INT(a.n, b.n);
    TB_EQ_INT(a.cycles, b.cycles);
    uint64_t bad = 0;
    for (uint64_t i = 0; a.admit && b.admit && i < a.n && i < b.n; i++)
        if (a.admit[i] != b.admit[i] || a.done[i] != b.done[i]) {
            if (bad++ == 0)
                TB_CHECK(0, "ray %llu: admit/done %llu/%llu with idle skipping, %llu/%llu exhaustive",
                         (unsigned long long)i, (unsigned long long)a.admit[i], (unsigned long long)a.done[i],
                         (unsigned long long)b.admit[i], (unsigned long long)b.done[i]);
        }
    TB_EQ_INT(bad, 0);
    tb_end();
    free(a.admit), free(a.done), free(b.admit), free(b.done);
}

/* LPDDR3 with every machine and ray type, stressed memory sides, several
 * seeds, and idle skipping against the exhaustive mode. full (env
 * RTSIM_LPDDR3_SWEEP=1): every scene, resolutions 24x14, 40x22, 64x36, seeds
 * 1..5, both stress configurations; otherwise a small subset. */
static void lpddr3_sweep(const rt_scene *sc, unsigned scene_index, bool full, bool small, totals *tot)
{
    static const char *const presets[] = {"bvh2", "mbvh4"};
    static const uint32_t res[][2] = {{24, 14}, {40, 22}, {64, 36}};
    if (!full) {
        if (scene_index != 1)   /* hairball: the scene of the reported hang */
            return;
        for (int m = 0; m < 2; m++)
            for (int d = 0; d < 2; d++) {
                case_spec cs = {.preset = presets[m], .memory = "lpddr3", .diffuse = d, .w = small ? 8 : 24,
                                .h = small ? 5 : 14, .seed = 2, .extra = stress_tiny, .tag = "tiny"};
                check_spec(sc, &cs, tot, NULL);
            }
        /* Idle skipping against the exhaustive mode, fixed memory and
         * LPDDR3: before the kernel fix of the lost wake-up when a clock's
         * scheduled tick moves earlier (kernel/clock.c wake_cycle), hairball
         * BVH2 diffuse 24x14 took 90,828 cycles with idle skipping and
         * 90,789 without, and stress_small livelocked on MBVH4. */
        case_spec eq = {.preset = "bvh2", .memory = "fixed", .diffuse = true, .w = small ? 8 : 24, .h = small ? 5 : 14,
                        .seed = 1};
        check_idle_skip_equivalence(sc, eq, tot);
        eq.memory = "lpddr3";
        eq.tag = "lpddr3";
        check_idle_skip_equivalence(sc, eq, tot);
        for (int m = 0; m < 2; m++) {
            case_spec one = {.preset = presets[m], .memory = "lpddr3", .diffuse = true, .w = small ? 8 : 24,
                             .h = small ? 5 : 14, .seed = 1, .extra = stress_one_mshr, .tag = "one_mshr"};
            check_spec(sc, &one, tot, NULL);
        }
        /* stress_small has a 1-entry DRAM response FIFO: the accelerator's
         * read frees it at edges shared with the DRAM clock, where the DRAM
         * port must see the slot at once (kernel/clock.h, coincident edges);
         * before that kernel fix these runs differed by a DRAM cycle */
        for (int m = 0; m < 2; m++) {
            case_spec st = {.preset = presets[m], .memory = "lpddr3", .diffuse = true, .w = small ? 8 : 24,
                            .h = small ? 5 : 14, .seed = 1, .extra = stress_small, .tag = "small"};
            check_idle_skip_equivalence(sc, st, tot);
        }
        return;
    }
    for (int m = 0; m < 2; m++)
        for (int d = 0; d < 2; d++)
            for (int r = 0; r < 3; r++)
                for (uint64_t seed = 1; seed <= (d ? 5u : 1u); seed++) {
                    case_spec cs = {.preset = presets[m], .memory = "lpddr3", .diffuse = d, .w = res[r][0],
                                    .h = res[r][1], .seed = seed};
                    char tag[32];
                    snprintf(tag, sizeof tag, "seed%llu", (unsigned long long)seed);
                    cs.tag = tag;
                    if (r == 0)
                        check_idle_skip_equivalence(sc, cs, tot);
                    else
                        check_spec(sc, &cs, tot, NULL);
                    snprintf(tag, sizeof tag, "seed%llu_tiny", (unsigned long long)seed);
                    cs.extra = stress_tiny;
                    check_spec(sc, &cs, tot, NULL);
                    snprintf(tag, sizeof tag, "seed%llu_small", (unsigned long long)seed);
                    cs.extra = stress_small;
                    if (r == 0)
                        check_idle_skip_equivalence(sc, cs, tot);
                    else
                        check_spec(sc, &cs, tot, NULL);
                }
}

int main(void)
{
    bool small = tb_is_sanitized();
    const char *sw = getenv("RTSIM_LPDDR3_SWEEP");
    bool full_sweep = sw && *sw && strcmp(sw, "0") != 0;
    totals tot = {0};
    for (unsigned i = 0; i < rt_builtin_count(); i++) {
        rt_scene sc;
        char err[512];
        char lname[96];
        snprintf(lname, sizeof lname, "system_load_scene_%s", rt_builtin_name(i));
        tb_begin(lname);
        bool ok = rt_scene_load(rt_builtin_name(i), &sc, err, sizeof err);
        TB_CHECK(ok, "%s: %s", rt_builtin_name(i), err);
        tb_end();
        if (!ok)
            continue;
        static const char *const presets[] = {"bvh2", "mbvh4"};
        for (int m = 0; m < 2; m++) {
            /* fixed-latency memory: the comparison does not depend on the
             * memory's timing, and it keeps the suite fast */
            check_case(&sc, presets[m], "fixed", false, small ? 16 : 48, small ? 9 : 27, &tot);
            check_case(&sc, presets[m], "fixed", true, small ? 8 : 24, small ? 5 : 14, &tot);
        }
        /* occlusion rays (AO of the primary hits): sort bypass, any-hit */
        for (int m = 0; m < 2; m++) {
            case_spec oc = {.preset = presets[m], .memory = "fixed", .occlusion = true, .w = small ? 12 : 32,
                            .h = small ? 7 : 18};
            check_spec(&sc, &oc, &tot, NULL);
        }
        /* and the default LPDDR3 memory on one case per scene */
        check_case(&sc, "mbvh4", "lpddr3", true, small ? 8 : 48, small ? 5 : 27, &tot);
        lpddr3_sweep(&sc, i, full_sweep, small, &tot);
        if (i == 0) {
            /* other widths (paper 3.1: MBVH3, MBVH5, MBVH6 were tried) */
            for (int wd = 3; wd <= 8; wd += (wd == 3 ? 2 : 1))
                if (wd != 4)
                    check_case_width(&sc, "mbvh4", wd, "fixed", wd == 5, small ? 12 : 32, small ? 7 : 18, &tot);
            /* the other organisation for such nodes (paper 3.1): an
             * index-addressed node hierarchy, one 96 B / 192 B node per line */
            static const char *const index_sets[] = {"node_l1.addressing=index", "node_l2.addressing=index",
                                                     "node_l1.banks=1", NULL};
            case_spec ix3 = {.preset = "mbvh4", .memory = "lpddr3", .width = 3, .diffuse = true, .w = small ? 12 : 32,
                             .h = small ? 7 : 18, .extra = index_sets, .tag = "index"};
            check_spec(&sc, &ix3, &tot, NULL);
            case_spec ix6 = {.preset = "mbvh4", .memory = "fixed", .width = 6, .w = small ? 12 : 32,
                             .h = small ? 7 : 18, .extra = index_sets, .tag = "index"};
            check_spec(&sc, &ix6, &tot, NULL);
            test_determinism_and_deadlock(&sc);
            test_sort_bypass_latency(&sc);
            case_spec ol = {.preset = "mbvh4", .memory = "lpddr3", .occlusion = true, .w = small ? 8 : 24,
                            .h = small ? 5 : 14, .seed = 3};
            check_idle_skip_equivalence(&sc, ol, &tot);
            test_banks_and_looping(&sc);
        }
        rt_scene_free(&sc);
    }
    printf("INFO total: %llu rays compared, %llu events, %llu hit mismatches, %llu event-sequence mismatches\n",
           (unsigned long long)tot.rays, (unsigned long long)tot.events, (unsigned long long)tot.hit_mismatch,
           (unsigned long long)tot.event_mismatch);
    return tb_finish();
}
