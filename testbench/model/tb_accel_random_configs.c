/* tb_accel_random_configs.c — property test of the machine validator and
 * the model: "every configuration the validator accepts runs".
 *
 * A deterministic generator (splitmix64, seed RTSIM_CONFIG_SEED, default 1)
 * draws machine configurations with every registered configuration key
 * within its declared range (the schema tables of model/accel_config.c and
 * model/mem/memsys_config.c, so keys added to a schema join the draw by
 * themselves; keys validated outside rtcfg plug in through extra_keys[]).
 * Each configuration runs twice, once with primary and once with diffuse
 * rays, each on a scene drawn from the four built-in scenes and small random
 * triangle soups, at a few pixels. A run must either
 *   - be refused at start-up (rtcfg_finish or accel_top_create) with a
 *     message naming a configuration key, or
 *   - finish, with every ray's hit bit-identical to the reference traversal
 *     (tracer/trace/traverse.h, the same comparison as tb_accel_system.c) and a
 *     stack overflow exactly where the reference overflows too.
 * A deadlock, a livelock, a run that ran dry or a crash is a failure of the
 * validator or of the model; its FAIL line gives the rtsim command that
 * reproduces it.
 *
 * Draw ranges narrower than the declared ones, each for a stated reason:
 *   sched.watchdog_cycles        1..2,000,000 instead of 0..1e12: 0 turns the
 *                                livelock watchdog off and 1e12 never fires,
 *                                so a livelock would hang the test instead of
 *                                failing it; small values are the harsh case.
 *   memory.fixed_bandwidth_gbs   0 or 0.5..10000 instead of 0..10000: below
 *                                that one line takes more than 128 cycles and
 *                                a frame hours of host time (a valid, slow run).
 *   memory.fixed_latency         1..20,000 instead of 1..100,000, and
 *   sched.shade_latency          0..200,000 instead of 0..1,000,000: host time
 *                                only (idle skipping does not skip looping rays).
 * and a configuration whose host memory estimate (ray stacks, cache tags,
 * FIFO storage) exceeds a budget is drawn again (counted as "redrawn").
 *
 * Counts: RTSIM_RANDOM_CONFIGS (default 100; 16 in a sanitizer build) — `make
 * soak` runs thousands. Summary line: INFO configurations, runs, refused
 * (with the keys named), finished, rays compared. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "frame/frame.h"
#include "model/accel_config.h"
#include "model/accel_top.h"
#include "model/mem/cache_core.h"
#include "model/mem/memsys_config.h"
#include "testbench/tb.h"
#include "tracer/io/builtin.h"
#include "tracer/trace/traverse.h"

/* ------------------------------------------------------------ generator */

static uint64_t rng_state;

static uint64_t rng_next(void)
{
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double rng_unit(void) { return (double)(rng_next() >> 11) / 9007199254740992.0; }
static uint64_t rng_below(uint64_t n) { return n ? rng_next() % n : 0; }

/* Log-uniform integer in [lo, hi] (small values as likely per octave as big
 * ones), with the ends themselves drawn often: edges are where bugs live. */
static int64_t draw_int(int64_t lo, int64_t hi)
{
    double u = rng_unit();
    if (u < 0.12 || lo == hi)
        return lo;
    if (u < 0.18)
        return hi;
    double a = log((double)(lo > 0 ? lo : 1)), b = log((double)hi + 1.0);
    int64_t v = (int64_t)floor(exp(a + (b - a) * rng_unit()));
    if (lo <= 0 && rng_unit() < 0.1)
        v = lo;
    return v < lo ? lo : v > hi ? hi : v;
}

static int64_t draw_pow2(int64_t lo, int64_t hi)
{
    int a = 0, b = 0;
    while ((1ll << a) < lo)
        a++;
    while ((1ll << (b + 1)) <= hi)
        b++;
    return 1ll << (a + (int)rng_below((uint64_t)(b - a + 1)));
}

/* Keys whose draw is narrower than their declared range (see the header). */
typedef struct narrow_key {
    const char *key;
    double lo, hi;
} narrow_key;
static const narrow_key narrowed[] = {
    {"sched.watchdog_cycles", 1, 2000000},
    {"memory.fixed_latency", 1, 20000},
    {"sched.shade_latency", 0, 200000},
};

/* Keys that rtsim accepts but no rtcfg schema declares (validated by their
 * own loader, e.g. DRAM spec overrides): key, inclusive range. Each entry
 * joins the draw only when rtcfg_set accepts it on this build, so entries
 * may be added before the keys exist. Empty while rtsim takes its DRAM
 * parameters from memory.dram_config only. */
typedef struct extra_key {
    const char *key;
    int64_t lo, hi;
} extra_key;
static const extra_key extra_keys[] = {{NULL, 0, 0}};

#define MAX_SETS 160

typedef struct drawn_config {
    char sets[MAX_SETS][192];
    int n;
} drawn_config;

static void add_set(drawn_config *c, const char *key, const char *value)
{
    if (c->n < MAX_SETS)
        snprintf(c->sets[c->n++], sizeof c->sets[0], "%s=%s", key, value);
}

static const char *find_set(const drawn_config *c, const char *key)
{
    size_t n = strlen(key);
    for (int i = 0; i < c->n; i++)
        if (!strncmp(c->sets[i], key, n) && c->sets[i][n] == '=')
            return c->sets[i] + n + 1;
    return NULL;
}

static double set_num(const drawn_config *c, const char *key, double def)
{
    const char *v = find_set(c, key);
    return v ? strtod(v, NULL) : def;
}

/* Draws every key of every schema registered in proto. */
static void draw_config(const rtcfg *proto, drawn_config *c)
{
    c->n = 0;
    for (int i = 0; i < rtcfg_schema_count(proto); i++) {
        const rtcfg_schema *s = rtcfg_schema_at(proto, i);
        for (int k = 0; k < s->nparams; k++) {
            const rtcfg_param *p = &s->params[k];
            char key[96], val[64];
            snprintf(key, sizeof key, "%s.%s", s->section, p->name);
            double lo = p->min, hi = p->max;
            for (size_t j = 0; j < sizeof narrowed / sizeof narrowed[0]; j++)
                if (!strcmp(narrowed[j].key, key))
                    lo = narrowed[j].lo, hi = narrowed[j].hi;
            switch (p->type) {
            case RTCFG_INT:
                snprintf(val, sizeof val, "%lld",
                         (long long)((p->flags & RTCFG_POW2) ? draw_pow2((int64_t)lo, (int64_t)hi)
                                                             : draw_int((int64_t)lo, (int64_t)hi)));
                break;
            case RTCFG_REAL:
                if (!strcmp(key, "memory.fixed_bandwidth_gbs"))
                    snprintf(val, sizeof val, "%.4g", rng_unit() < 0.15 ? 0.0 : 0.5 * pow(2e4, rng_unit()));
                else if (lo > 0)
                    snprintf(val, sizeof val, "%.6g", lo * pow(hi / lo, rng_unit()));
                else
                    snprintf(val, sizeof val, "%.6g", lo + (hi - lo) * rng_unit());
                break;
            case RTCFG_BOOL:
                snprintf(val, sizeof val, "%s", rng_below(2) ? "true" : "false");
                break;
            case RTCFG_ENUM: {
                int n = 1;
                for (const char *q = p->choices; q && *q; q++)
                    n += *q == '|';
                int pick = (int)rng_below((uint64_t)n);
                const char *q = p->choices;
                for (int j = 0; j < pick; j++)
                    q = strchr(q, '|') + 1;
                size_t len = strcspn(q, "|");
                snprintf(val, sizeof val, "%.*s", (int)len, q);
                break;
            }
            case RTCFG_STRING:
                continue;   /* names and file paths keep their defaults */
            }
            add_set(c, key, val);
        }
    }
    for (size_t j = 0; j < sizeof extra_keys / sizeof extra_keys[0] && extra_keys[j].key; j++) {
        char val[32];
        snprintf(val, sizeof val, "%lld", (long long)draw_int(extra_keys[j].lo, extra_keys[j].hi));
        add_set(c, extra_keys[j].key, val);
    }
}

static void replace_set_str(drawn_config *c, const char *key, const char *value)
{
    size_t n = strlen(key);
    for (int i = 0; i < c->n; i++)
        if (!strncmp(c->sets[i], key, n) && c->sets[i][n] == '=') {
            snprintf(c->sets[i], sizeof c->sets[0], "%s=%s", key, value);
            return;
        }
    add_set(c, key, value);
}

static void replace_set(drawn_config *c, const char *key, long long value)
{
    char v[32];
    snprintf(v, sizeof v, "%lld", value);
    replace_set_str(c, key, v);
}

static rtcfg *new_cfg(char *err, size_t errlen);

/* Lines an object touches, worst case, in the image's layout (the same
 * arithmetic as memsys_config.c, written again so a mistake in one shows). */
static long long lines_of(long long bytes, long long line)
{
    long long a = bytes, b = line;
    while (b) {
        long long r = a % b;
        a = b, b = r;
    }
    return (line - a + bytes - 1) / line + 1;
}

/* Most draws are steered into the validator's structural rules, so that
 * most runs exercise the model rather than the refusals: every cache holds
 * at least one set per bank and the lines of one node or triangle, an L1
 * line fits an L2 line, and the ray FIFOs are at their deadlock-free
 * minima (accel_config.h) or above. The values stay in their ranges and
 * keep their drawn distribution otherwise. */
static void steer_config(drawn_config *c)
{
    static const char *const secs[] = {"node_l1", "node_l2", "prim"};
    char k[64];
    /* one addressing for the node hierarchy (memsys_config.c); index: the
     * line is the node, whatever node_l*.line says */
    const char *addressing = find_set(c, "node_l1.addressing");
    bool index = addressing && !strcmp(addressing, "index");
    replace_set_str(c, "node_l2.addressing", index ? "index" : "byte");
    const long long node_bytes = 32 * (long long)set_num(c, "machine.branching", 4);
    /* node and triangle reads of at most 8 lines (cache.h) */
    for (int i = 0; i < 3; i += 2) {
        snprintf(k, sizeof k, "%s.line", secs[i]);
        long long line = (long long)set_num(c, k, 64), bytes = i == 0 ? 32 * (long long)set_num(c, "machine.branching", 4) : 48;
        while (lines_of(bytes, line) > CACHE_MAX_LINES_PER_ACCESS)
            line *= 2;
        replace_set(c, k, line);
    }
    double l1_line = set_num(c, "node_l1.line", 128);
    if (set_num(c, "node_l2.line", 128) < l1_line)
        replace_set(c, "node_l2.line", (long long)l1_line);
    for (int i = 0; i < 3; i++) {
        snprintf(k, sizeof k, "%s.line", secs[i]);
        long long line = index && i < 2 ? node_bytes : (long long)set_num(c, k, 64);
        snprintf(k, sizeof k, "%s.ways", secs[i]);
        double ways = set_num(c, k, 4);
        snprintf(k, sizeof k, "%s.banks", secs[i]);
        double banks = set_num(c, k, 1);
        long long bytes = i == 0 ? 32 * (long long)set_num(c, "machine.branching", 4) : 48;
        /* the lines of one node or triangle per ray that may wait on the cache_core */
        double waiting = i == 0 ? set_num(c, "trv.slots", 32)
                       : i == 2 ? set_num(c, "ist.latency", 16) + set_num(c, "prim.hit_latency", 2) + 2
                                : 1;
        double min = 64, fit = waiting * (double)(lines_of(bytes, line) * line);
        while (min < (double)line * ways * banks) /* sizes are powers of two, node words need not be */
            min *= 2;
        while (min < fit)
            min *= 2;
        snprintf(k, sizeof k, "%s.size", secs[i]);
        if (set_num(c, k, 0) < min && min <= 1073741824.0)
            replace_set(c, k, (long long)min);
        snprintf(k, sizeof k, "%s.ways", secs[i]);
        if (i != 1 && ways < 2 && lines_of(bytes, line) > 1)
            replace_set(c, k, 2), min *= 2;
        snprintf(k, sizeof k, "%s.size", secs[i]);
        if (set_num(c, k, 0) < min && min <= 1073741824.0)
            replace_set(c, k, (long long)min);
        snprintf(k, sizeof k, "%s.mshrs", secs[i]);
        if (i == 0 && set_num(c, k, 8) < (double)lines_of(bytes, line))
            replace_set(c, k, lines_of(bytes, line));
    }
    char err[TB_ERR_MAX];
    rtcfg *cfg = new_cfg(err, sizeof err);
    if (!cfg)
        return;
    for (int i = 0; i < c->n; i++)
        rtcfg_set(cfg, c->sets[i], err, sizeof err);
    uint32_t loop = accel_fifo_min(cfg, ACCEL_FIFO_TRV_LOOP), lr = accel_leaf_return_min(cfg);
    if (set_num(c, "fifo.ray_trv_loop", 32) < loop)
        replace_set(c, "fifo.ray_trv_loop", loop + (long long)rng_below(3));
    double leaf = set_num(c, "fifo.ray_leaf", 32), ret = set_num(c, "fifo.ray_return", 32);
    if (leaf + ret < lr) {
        long long l = 1 + (long long)rng_below(lr);
        if (l > leaf)
            replace_set(c, "fifo.ray_leaf", l);
        else
            l = (long long)leaf;
        if (ret < lr - l)
            replace_set(c, "fifo.ray_return", lr - l);
    }
    rtcfg_destroy(cfg);
}

/* Host memory of a drawn machine, roughly: ray records and stacks, cache
 * tag arrays, FIFO storage. */
static double host_bytes(const drawn_config *c)
{
    double ntrv = set_num(c, "trv.count", 4), slots = set_num(c, "trv.slots", 32);
    double bytes = ntrv * slots * (set_num(c, "trv.stack_depth", 64) * 16 + 512);
    double l1 = set_num(c, "node_l1.size", 16384) / set_num(c, "node_l1.line", 128);
    double l2 = set_num(c, "node_l2.size", 131072) / set_num(c, "node_l2.line", 128);
    double pr = set_num(c, "prim.size", 131072) / set_num(c, "prim.line", 64);
    bytes += 64 * (ntrv * l1 + l2 + pr);
    double fifos = 0;
    for (int i = 0; i < c->n; i++)
        if (!strncmp(c->sets[i], "fifo.ray_", 9) || !strncmp(c->sets[i], "fifo.mem_l1", 11))
            fifos += ntrv * strtod(strchr(c->sets[i], '=') + 1, NULL);
        else if (!strncmp(c->sets[i], "fifo.", 5))
            fifos += strtod(strchr(c->sets[i], '=') + 1, NULL);
    bytes += 32 * fifos;
    return bytes;
}

/* ------------------------------------------------------------- scenes */

#define N_RANDOM_SCENES 6

typedef struct scene_slot {
    char name[TB_PATH_MAX]; /* built-in name or file path (under RTSIM_TMP) */
    rt_scene sc;
    bool loaded, failed;
    rt_bvh_image img[RT_WIDTH_MAX + 1];   /* per width, built on first use */
    bool built[RT_WIDTH_MAX + 1];
} scene_slot;

/* A soup of n random triangles in the unit cube (some tiny, some
 * duplicated) as an OBJ file under dir. */
static bool write_random_scene(const char *path, unsigned n)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return false;
    for (unsigned i = 0; i < n; i++) {
        double c[3], s = rng_unit() < 0.2 ? 1e-3 : 0.05 + 0.4 * rng_unit();
        for (int k = 0; k < 3; k++)
            c[k] = rng_unit();
        for (int v = 0; v < 3; v++)
            fprintf(f, "v %.6f %.6f %.6f\n", c[0] + s * (rng_unit() - 0.5), c[1] + s * (rng_unit() - 0.5),
                    c[2] + s * (rng_unit() - 0.5));
    }
    for (unsigned i = 0; i < n; i++) {
        unsigned t = rng_unit() < 0.1 && i ? (unsigned)rng_below(i) : i;   /* a duplicate face */
        fprintf(f, "f %u %u %u\n", 3 * t + 1, 3 * t + 2, 3 * t + 3);
    }
    return fclose(f) == 0;
}

static const rt_bvh_image *scene_image(scene_slot *s, int width, char *err, size_t errlen)
{
    if (!s->loaded && !s->failed) {
        s->failed = !rt_scene_load(s->name, &s->sc, err, errlen);
        s->loaded = !s->failed;
    }
    if (!s->loaded)
        return NULL;
    if (!s->built[width]) {
        rt_bvh_params bp;
        rt_bvh_params_default(&bp);
        bp.width = width;
        if (!rt_bvh_build(&s->sc.mesh, &bp, &s->img[width], NULL, err, errlen))
            return NULL;
        s->built[width] = true;
    }
    return &s->img[width];
}

/* ---------------------------------------------------------------- runs */

typedef struct ray_rec {
    rt_ray ray;
    rt_hit hit;
    bool failed;
} ray_rec;

typedef struct run_log {
    ray_rec *recs;
    uint64_t n, cap;
    bool oom;
} run_log;

static void on_complete(void *user, uint32_t uid, const rt_ray *ray, const rt_hit *hit, uint64_t admit, uint64_t done,
                        bool failed)
{
    (void)uid, (void)admit, (void)done;
    run_log *l = user;
    if (l->n == l->cap) {
        uint64_t nc = l->cap ? 2 * l->cap : 256;
        ray_rec *r = realloc(l->recs, nc * sizeof *r);
        if (!r) {
            l->oom = true;
            return;
        }
        l->recs = r, l->cap = nc;
    }
    l->recs[l->n++] = (ray_rec){*ray, *hit, failed};
}

static bool same_float(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

typedef struct totals {
    uint64_t configs, runs, refused_finish, refused_create, finished, overflow_runs, guarded, rays, redrawn;
} totals;

/* Does msg name a registered key ("section.name")? */
static bool names_a_key(const rtcfg *cfg, const char *msg)
{
    for (int i = 0; i < rtcfg_schema_count(cfg); i++) {
        const rtcfg_schema *s = rtcfg_schema_at(cfg, i);
        for (int k = 0; k < s->nparams; k++) {
            char key[96];
            snprintf(key, sizeof key, "%s.%s", s->section, s->params[k].name);
            if (strstr(msg, key))
                return true;
        }
    }
    return false;
}

static rtcfg *new_cfg(char *err, size_t errlen)
{
    rtcfg *cfg = rtcfg_create();
    if (!cfg || memsys_add_schemas(cfg, err, errlen) || accel_add_schemas(cfg, err, errlen)) {
        rtcfg_destroy(cfg);
        return NULL;
    }
    return cfg;
}

static void print_repro(const drawn_config *c, unsigned index, const char *scene, bool diffuse, uint32_t w,
                        uint32_t h)
{
    printf("INFO reproduce %s: rtsim %s --rays %s --res %ux%u --bounces 2 --seed %u", tb_case_name, scene,
            diffuse ? "diffuse" : "primary", w, h, index + 1);
    for (int i = 0; i < c->n; i++)
        printf(" --set %s", c->sets[i]);
    printf("\n");
}

/* One run of configuration c on scene s; a FAIL when the property breaks. */
static void run_one(const drawn_config *c, unsigned index, scene_slot *s, bool diffuse, uint32_t w, uint32_t h,
                    totals *tot)
{
    char name[160], err[8192];
    snprintf(name, sizeof name, "random_config_%04u_%s", index, diffuse ? "diffuse" : "primary");
    tb_begin(name);
    tot->runs++;
    rtcfg *cfg = new_cfg(err, sizeof err);
    if (!TB_CHECK(cfg != NULL, "schemas: %s", err)) {
        tb_end();
        return;
    }
    for (int i = 0; i < c->n; i++)
        if (!TB_CHECK(rtcfg_set(cfg, c->sets[i], err, sizeof err) == 0, "a drawn value is out of its range: %s", err)) {
            rtcfg_destroy(cfg);
            tb_end();
            return;
        }
    run_log log = {0};
    rtsim_frame fr;
    memset(&fr, 0, sizeof fr);
    accel_top *top = NULL;
    if (rtcfg_finish(cfg, err, sizeof err)) {
        /* refused by the validator: fine, when it says which key */
        TB_CHECK(names_a_key(cfg, err), "refusal names no key: %s", err);
        if (getenv("RTSIM_RANDOM_VERBOSE"))
            printf("INFO %s refused: %s\n", name, err);
        tot->refused_finish++;
        goto out;
    }
    int width = (int)rtcfg_int(cfg, "machine.branching");
    const rt_bvh_image *img = scene_image(s, width, err, sizeof err);
    if (!TB_CHECK(img != NULL, "scene %s: %s", s->name, err))
        goto out;
    accel_source src;
    if (!TB_CHECK(rtsim_frame_init(&fr, cfg, &s->sc.mesh, &s->sc.views.v[0], w, h, diffuse, 2, index + 1, false, &src, err,
                                   sizeof err),
                  "%s", err))
        goto out;
    fr.hook = on_complete;
    fr.hook_user = &log;
    accel_image aimg = rtsim_image(img);
    top = accel_top_create(cfg, &aimg, &src, NULL, err, sizeof err);
    if (!top) {
        TB_CHECK(names_a_key(cfg, err), "start-up refusal names no key: %s", err);
        tot->refused_create++;
        goto out;
    }
    int rc = accel_top_run(top, NULL, NULL, err, sizeof err);
    bool overflow = rc != 0 && strstr(err, "trv.stack_depth") != NULL && !strstr(err, "deadlock") &&
                    !strstr(err, "livelock") && !strstr(err, "ran dry");
    if (!TB_CHECK(rc == 0 || overflow, "run-time failure: %.600s", err)) {
        print_repro(c, index, s->name, diffuse, w, h);
        goto out;
    }
    tot->finished++;
    tot->overflow_runs += overflow;
    tot->guarded += accel_top_guard_cycle(top) != 0;
    TB_CHECK(!log.oom, "out of memory in the log");
    TB_EQ_INT(log.n, accel_top_rays(top));
    /* every ray against the reference traversal with the same stack */
    rt_trv_params tp;
    rt_trv_params_default(&tp, width);
    tp.stack_depth = (int)rtcfg_int(cfg, "trv.stack_depth");
    tp.distance_cull = accel_top_params(top)->trv.core.distance_cull;
    uint64_t bad = 0, primaries = 0;
    for (uint64_t i = 0; i < log.n; i++) {
        const ray_rec *r = &log.recs[i];
        rt_hit rh;
        bool ok = rt_trace_ray(img, &tp, &r->ray, &rh, NULL, NULL, NULL);
        primaries += r->ray.bounce == 0;
        bool same = ok ? !r->failed && rh.prim == r->hit.prim && same_float(rh.t, r->hit.t) &&
                             same_float(rh.u, r->hit.u) && same_float(rh.v, r->hit.v)
                       : r->failed;
        if (!same && bad++ == 0) {
            TB_CHECK(0, "ray (pixel %u bounce %u): model prim %u t %.9g%s, reference prim %u t %.9g%s", r->ray.pixel,
                     r->ray.bounce, r->hit.prim, r->hit.t, r->failed ? " (overflow)" : "", rh.prim, rh.t,
                     ok ? "" : " (overflow)");
            print_repro(c, index, s->name, diffuse, w, h);
        }
    }
    TB_EQ_INT(bad, 0);
    TB_EQ_INT(primaries, (uint64_t)w * h);
    tot->rays += log.n;
out:
    accel_top_destroy(top);
    rtsim_frame_free(&fr);
    free(log.recs);
    rtcfg_destroy(cfg);
    tb_end();
}

int main(void)
{
    const char *e = getenv("RTSIM_RANDOM_CONFIGS");
    unsigned count = e && *e ? (unsigned)strtoul(e, NULL, 10) : (tb_is_sanitized() ? 16u : 100u);
    e = getenv("RTSIM_CONFIG_SEED");
    rng_state = e && *e ? strtoull(e, NULL, 10) : 1;
    double budget = tb_is_sanitized() ? 48e6 : 160e6;
    const char *tmp = getenv("RTSIM_TMP");
    if (!tmp || !*tmp)
        tmp = "/tmp";

    /* the scenes: built-ins and random soups of 1..200 triangles */
    unsigned nb = rt_builtin_count();
    unsigned nscenes = nb + N_RANDOM_SCENES;
    scene_slot *scenes = calloc(nscenes, sizeof *scenes);
    if (!scenes)
        return 1;
    for (unsigned i = 0; i < nb; i++)
        snprintf(scenes[i].name, sizeof scenes[i].name, "%s", rt_builtin_name(i));
    tb_begin("random_config_scenes_written");
    for (unsigned i = 0; i < N_RANDOM_SCENES; i++) {
        scene_slot *s = &scenes[nb + i];
        tb_pathf(s->name, sizeof s->name, "%s/random_%u.obj", tmp, i);
        unsigned ntri = i == 0 ? 1 : (unsigned)draw_int(2, 200);
        TB_CHECK(write_random_scene(s->name, ntri), "cannot write %s", s->name);
    }
    tb_end();

    rtcfg *proto = new_cfg((char[256]){0}, 256);
    if (!proto)
        return 1;
    totals tot = {0};
    for (unsigned n = 0; n < count; n++) {
        drawn_config c;
        do {
            draw_config(proto, &c);
            if (rng_unit() < 0.8)
                steer_config(&c);
            tot.redrawn += host_bytes(&c) > budget;
        } while (host_bytes(&c) > budget);
        tot.configs++;
        for (int d = 0; d < 2; d++) {
            scene_slot *s = &scenes[rng_below(nscenes)];
            uint32_t w = 1 + (uint32_t)rng_below(d ? 5 : 8), h = 1 + (uint32_t)rng_below(d ? 4 : 6);
            run_one(&c, n, s, d == 1, w, h, &tot);
        }
    }
    rtcfg_destroy(proto);
    for (unsigned i = 0; i < nscenes; i++) {
        for (int wd = 0; wd <= RT_WIDTH_MAX; wd++)
            if (scenes[i].built[wd])
                rt_bvh_image_free(&scenes[i].img[wd]);
        if (scenes[i].loaded)
            rt_scene_free(&scenes[i].sc);
    }
    free(scenes);
    printf("INFO random configurations: %llu drawn (%llu redrawn over the host memory budget), %llu runs: %llu refused "
           "by the validator, %llu refused at start-up, %llu finished (%llu with stack overflows matching the "
           "reference, %llu with the livelock guard engaged), %llu rays compared\n",
           (unsigned long long)tot.configs, (unsigned long long)tot.redrawn, (unsigned long long)tot.runs,
           (unsigned long long)tot.refused_finish, (unsigned long long)tot.refused_create,
           (unsigned long long)tot.finished, (unsigned long long)tot.overflow_runs, (unsigned long long)tot.guarded,
           (unsigned long long)tot.rays);
    return tb_finish();
}
