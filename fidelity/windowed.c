/* windowed.c — the windowed level (see windowed.h). */
#include "fidelity/windowed.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fidelity/estimator.h"
#include "fidelity/fidelity_params.h"
#include "fidelity/functional.h"
#include "fidelity/subset.h"
#include "kernel/fork_pool.h"
#include "model/mem/memsys_config.h"
#include "model/ray/accel_ray.h"
#include "tracer/trace/bounce.h"
#include "tracer/trace/camera.h"
#include "tracer/trace/traverse.h"

/* ---- the traversal work of a pixel's path ------------------------------- */

typedef struct path_tracer {
    const fid_job *job;
    rt_camera cam;
    const uint32_t *order;   /* the frame's pixel order (frame.h); NULL: scanline */
    uint32_t *own;           /* order, when computed here */
    rt_trv_params tp;
} path_tracer;

/* order: the frame's pixel order when the caller has it (have_order; NULL
 * then means scanline), else computed here (a Morton order of a 1280x720
 * frame took 14% of a windowed run when each of 48 windows made its own) */
static int path_tracer_init(path_tracer *pt, const fid_job *job, bool have_order, const uint32_t *order, char *err,
                            size_t errlen)
{
    memset(pt, 0, sizeof *pt);
    pt->job = job;
    if (!rt_camera_init(&pt->cam, job->view, job->width, job->height, err, errlen) ||
        (!have_order && !rtsim_pixel_order(job->cfg, job->width, job->height, &pt->own, err, errlen)))
        return 2;
    pt->order = have_order ? order : pt->own;
    accel_params ap;
    accel_params_get(job->cfg, &ap);
    rtsim_trv_params(&ap, job->img->width, &pt->tp);
    return 0;
}

static void path_tracer_free(path_tracer *pt)
{
    free(pt->own);
    pt->own = NULL, pt->order = NULL;
}

/* The traversal work of pixel p's path (the rays the model traces for the
 * pixel), as the first three auxiliary figures: its rays' node visits and
 * triangle tests, its bounces' visits + tests (FID_AUX_VISITS,
 * FID_AUX_TRI_TESTS, FID_AUX_BOUNCE_WORK). */
static void path_work(const path_tracer *pt, uint32_t p, double work[FID_AUX_DRAM_LINES])
{
    const fid_job *job = pt->job;
    const uint32_t px = rt_pixel_at(pt->order, p);   /* p: a position in the pixel order */
    rt_ray ray = rt_camera_primary_ray(&pt->cam, px % job->width, px / job->width), next;
    rt_hit hit;
    work[FID_AUX_VISITS] = work[FID_AUX_TRI_TESTS] = work[FID_AUX_BOUNCE_WORK] = 0;
    for (bool bounce = false;; bounce = true) {
        rt_trv_counts c = {0};
        rt_trace_ray(job->img, &pt->tp, &ray, &hit, &c, NULL, NULL);
        work[FID_AUX_VISITS] += (double)c.visits;
        work[FID_AUX_TRI_TESTS] += (double)c.tri_tests;
        if (bounce)
            work[FID_AUX_BOUNCE_WORK] += (double)c.visits + (double)c.tri_tests;
        if (!job->diffuse || !rt_bounce_ray(job->mesh, &ray, &hit, job->seed, job->bounces, &next))
            break;
        ray = next;
    }
}

/* ---- the pieces ----------------------------------------------------------- */

struct win_lattice;
typedef struct win_plan {
    const fid_job *job;
    uint32_t first, count;        /* pieces first..first+count-1 are windows */
    uint32_t warm, len, lattice_period;
    uint64_t npix;
    /* functional warming: each window's caches start from the lattice's at
     * its warm-up's first pixel (win_snapshot); snapshots for windows
     * 0..max_windows-1 are taken while the lattice runs */
    bool snapshot;
    uint32_t max_windows;
    bool have_order;              /* order holds the frame's pixel order (NULL: scanline) */
    const uint32_t *order;
    const struct win_lattice *lat;
} win_plan;

/* What a window hands back (plain data). */
typedef struct win_piece {
    accel_point a, b;             /* after the warm-up; after the window */
    double e_warm, e_win, s_win;  /* energy (mJ) of the warm-up and the window, the window's static part */
    /* per unit over the warm-up and the window: dynamic energy (mJ), DRAM's
     * static at EU_COUNT; the units' leakage (mW) and area (mm2) */
    double u_warm[EU_COUNT + 1], u_win[EU_COUNT + 1], leak_mw[EU_COUNT], area_mm2[EU_COUNT];
    bool has_units;
    double x_warm[FID_AUX_COUNT], x_win[FID_AUX_COUNT]; /* auxiliary figures of their pixels (the
                                   * lattice's DRAM lines filled in by the estimate) */
} win_piece;

/* The lattice: the frame's auxiliary figures, from 1 pixel in win_lattice
 * through the functional level. */
typedef struct win_lattice {
    double n, x[FID_AUX_COUNT], xx[FID_AUX_COUNT][FID_AUX_COUNT], r, r2;
    double gn[FID_LAT_GROUPS], gx[FID_LAT_GROUPS][FID_AUX_COUNT];   /* per interleaved group (windowed.h) */
    double *cum;                  /* cum[p]: DRAM lines of the lattice's pixels before pixel p */
    uint32_t *ncum;               /* ncum[p]: lattice pixels before pixel p */
    fid_func_snap *snaps;         /* nsnap of them, ascending in `at` */
    uint32_t *snap_of;            /* window i's snapshot: snaps[snap_of[i]] (i < nsnap) */
    uint32_t nsnap;
} win_lattice;

/* The radical inverse of i in base 2 (van der Corput): the first 2^k values
 * split [0, 1) into 2^k equal strata, one value in each, and the next ones
 * fall between them, so a set of windows grown later keeps the earlier ones. */
static double radical_inverse(uint32_t i)
{
    double v = 0, f = 0.5;
    for (; i; i >>= 1, f *= 0.5)
        if (i & 1)
            v += f;
    return v;
}

/* Window i: pixels [first, end), its warm-up [first, start). Rows: the
 * radical inverse (shifted off the frame's first row), so any 2^k first
 * windows are stratified down the image; columns spread by the golden
 * ratio: evenly spaced centres fell on the same columns, and the middle of an
 * image is not its average (MRPS 1% and DRAM MB 4% off on interior diffuse). */
static void window_range(const win_plan *pl, uint32_t i, uint64_t *first, uint64_t *start, uint64_t *end)
{
    uint32_t w = pl->job->width, h = pl->job->height;
    uint64_t row = (uint64_t)(fmod(radical_inverse(i) + 1.0 / 32.0, 1.0) * h);
    double col = fmod(((double)i + 0.5) * 0.6180339887498949, 1.0) * w;
    uint64_t centre = row * w + (uint64_t)col;
    if (centre >= pl->npix)
        centre = pl->npix - 1;
    uint64_t s = centre > pl->len / 2 ? centre - pl->len / 2 : 0;
    if (s < pl->warm)
        s = pl->warm < pl->npix ? pl->warm : 0;   /* a whole warm-up, even at the frame's start */
    if (s + pl->len > pl->npix)
        s = pl->npix > pl->len ? pl->npix - pl->len : 0;
    *start = s;
    *first = s > pl->warm ? s - pl->warm : 0;
    const fid_params *fp = fid_params_get();
    uint64_t e = s + pl->len + (uint64_t)fp->win_tail_pixels;
    *end = e < pl->npix ? e : pl->npix;
}

static bool on_lattice(const win_plan *pl, uint64_t p)
{
    /* a diagonal lattice: every row and every column is sampled */
    uint32_t w = pl->job->width;
    return (p % w + 5 * (p / w)) % pl->lattice_period == 0;
}

/* The lattice's pixels in scanline order through the functional level
 * (functional.h: the model's caches, 128 rays in flight), each pixel's work,
 * rays and DRAM lines charged to it. */
static int run_lattice(const win_plan *pl, win_lattice *lat, char *err, size_t errlen)
{
    uint64_t N = pl->npix, n = 0;
    for (uint64_t p = 0; p < N; p++)
        n += on_lattice(pl, p);
    uint32_t *px = malloc((size_t)(n ? n : 1) * sizeof *px);
    fid_func_attr *attr = malloc((size_t)(n ? n : 1) * sizeof *attr);
    lat->cum = malloc((size_t)(N + 1) * sizeof *lat->cum);
    lat->ncum = malloc((size_t)(N + 1) * sizeof *lat->ncum);
    if (!px || !attr || !lat->cum || !lat->ncum) {
        free(px), free(attr);
        snprintf(err, errlen, "out of memory");
        return 2;
    }
    n = 0;
    for (uint64_t p = 0; p < N; p++)
        if (on_lattice(pl, p))
            px[n++] = (uint32_t)p;
    if (pl->snapshot && pl->max_windows) {
        /* each window's warm-up starts from the lattice's caches when the
         * lattice reached the warm-up's first pixel: sorted by position */
        uint32_t W = pl->max_windows;
        lat->snaps = calloc(W, sizeof *lat->snaps);
        lat->snap_of = malloc(W * sizeof *lat->snap_of);
        uint64_t *key = malloc(W * sizeof *key);
        if (!lat->snaps || !lat->snap_of || !key) {
            free(px), free(attr), free(key);
            snprintf(err, errlen, "out of memory");
            return 2;
        }
        for (uint32_t i = 0; i < W; i++) {
            uint64_t first, st, end, lo = 0, hi = n;
            window_range(pl, i, &first, &st, &end);
            while (lo < hi) {   /* lattice pixels before `first` */
                uint64_t mid = (lo + hi) / 2;
                if (px[mid] < first)
                    lo = mid + 1;
                else
                    hi = mid;
            }
            key[i] = lo << 32 | i;
        }
        for (uint32_t i = 1; i < W; i++)   /* insertion sort by (position, window) */
            for (uint32_t j = i; j > 0 && key[j - 1] > key[j]; j--) {
                uint64_t t = key[j];
                key[j] = key[j - 1], key[j - 1] = t;
            }
        for (uint32_t k = 0; k < W; k++) {
            lat->snaps[k].at = (uint32_t)(key[k] >> 32);
            lat->snap_of[(uint32_t)key[k]] = k;
        }
        lat->nsnap = W;
        free(key);
    }
    fid_func f;
    int rc = fid_functional_run_snap(pl->job, px, (uint32_t)n, &f, attr, lat->snaps, lat->nsnap, err, errlen) ? 2 : 0;
    uint64_t k = 0;
    lat->cum[0] = 0, lat->ncum[0] = 0;
    for (uint64_t p = 0; rc == 0 && p < N; p++) {
        lat->cum[p + 1] = lat->cum[p], lat->ncum[p + 1] = lat->ncum[p];
        if (k >= n || px[k] != p)
            continue;
        const float *a = attr[k++];
        double x[FID_AUX_COUNT] = {a[FID_ATTR_VISITS], a[FID_ATTR_TRI_TESTS], a[FID_ATTR_BOUNCE_WORK],
                                   a[FID_ATTR_DRAM_LINES]},
               rays = a[FID_ATTR_RAYS];
        lat->cum[p + 1] += x[FID_AUX_DRAM_LINES], lat->ncum[p + 1] += 1;
        uint32_t g = (uint32_t)((k - 1) % FID_LAT_GROUPS);   /* k: this pixel's index + 1 */
        lat->gn[g] += 1;
        for (int i = 0; i < FID_AUX_COUNT; i++)
            lat->gx[g][i] += x[i];
        lat->n += 1, lat->r += rays, lat->r2 += rays * rays;
        for (int i = 0; i < FID_AUX_COUNT; i++) {
            lat->x[i] += x[i];
            for (int j = 0; j < FID_AUX_COUNT; j++)
                lat->xx[i][j] += x[i] * x[j];
        }
    }
    free(px);
    free(attr);
    return rc;
}

/* Each unit's dynamic energy of an interval, DRAM's static at EU_COUNT. */
static void unit_energy(const energy_result *er, double u_mj[EU_COUNT + 1])
{
    for (int u = 0; u < EU_COUNT; u++)
        u_mj[u] = er->dynamic_mj[u];
    u_mj[EU_COUNT] = er->static_mj[EU_DRAM];
}

/* The lattice's DRAM lines over pixels [lo, hi), scaled to all of them.
 * (Smoothing each pixel's figure over the lattice pixels within 2048 or
 * 8192 pixels of it, so that a window of ~1K pixels has more than its ~130
 * own, made the intervals wider, not narrower: hairball diffuse MBVH4 48
 * windows, DRAM MB 8.9% -> 12.0-12.6%; the lines a pixel's own rays fetch
 * say more than the neighbourhood's.) */
static double lattice_lines(const win_lattice *lat, uint64_t lo, uint64_t hi)
{
    uint32_t c = lat->ncum[hi] - lat->ncum[lo];
    return c ? (lat->cum[hi] - lat->cum[lo]) * (double)(hi - lo) / c : 0.0;
}

static int run_window(const win_plan *pl, uint32_t i, win_piece *r, char *err, size_t errlen)
{
    const fid_job *job = pl->job;
    uint64_t first, start, end;
    window_range(pl, i, &first, &start, &end);
    uint32_t n = (uint32_t)(end - first);
    uint32_t *map = malloc((size_t)n * sizeof *map);
    if (!map) {
        snprintf(err, errlen, "out of memory");
        return 2;
    }
    for (uint32_t k = 0; k < n; k++)
        map[k] = (uint32_t)(first + k);
    fid_subset sub;
    int rc = fid_subset_open_series(&sub, job, job->cfg, map, n, "window", i, "warm-up", err, errlen);
    if (rc) {
        free(map);
        return rc;
    }
    if (pl->snapshot && pl->lat && i < pl->lat->nsnap) {
        const fid_func_snap *sn = &pl->lat->snaps[pl->lat->snap_of[i]];
        if (accel_top_warm_caches(sub.top, (const cache_core *const *)sn->l1, (int)sn->ntrv, sn->l2, sn->prim)) {
            snprintf(err, errlen, "window %u: the lattice's caches do not match the machine's", i);
            fid_subset_close(&sub);
            free(map);
            return 2;
        }
    }
    accel_point zero;
    memset(&zero, 0, sizeof zero);
    uint64_t warm = start - first;
    if (warm == 0)
        r->a = zero;   /* the frame's own start: nothing to warm */
    else if (accel_top_run_until(sub.top, warm, &r->a, err, errlen))
        rc = 1;
    if (sub.series)
        accel_series_label(sub.series, i, "window");   /* the rows of the window proper */
    if (rc == 0 && accel_top_run_until(sub.top, warm + pl->len, &r->b, err, errlen))
        rc = 1;
    if (rc == 0) {
        const energy_result *er = accel_top_interval_energy(sub.top, &zero, &r->a);
        r->has_units = er != NULL;
        if (er) {
            r->e_warm = er->total_energy_mj;
            unit_energy(er, r->u_warm);
            er = accel_top_interval_energy(sub.top, &r->a, &r->b);
            r->e_win = er->total_energy_mj;
            unit_energy(er, r->u_win);
            double sec = (double)(r->b.cycle - r->a.cycle) / (rtcfg_real(job->cfg, "machine.clock_mhz") * 1e6);
            for (int u = 0; u < EU_COUNT; u++) {
                r->s_win += er->static_mj[u];
                r->leak_mw[u] = u == EU_DRAM || sec <= 0 ? 0 : er->static_mj[u] / sec;
                r->area_mm2[u] = er->area_mm2[u];
            }
        }
        path_tracer pt;
        rc = path_tracer_init(&pt, job, pl->have_order, pl->order, err, errlen);
        for (uint64_t k = 0; rc == 0 && k < r->b.primaries && k < n; k++) {
            double work[FID_AUX_DRAM_LINES];
            path_work(&pt, map[k], work);
            double *x = k < r->a.primaries ? r->x_warm : r->x_win;
            for (int a = 0; a < FID_AUX_DRAM_LINES; a++)
                x[a] += work[a];
        }
        path_tracer_free(&pt);
    }
    if (fid_subset_close(&sub) && rc == 0) {
        snprintf(err, errlen, "--series: writing the rows of window %u failed", i);
        rc = 2;
    }
    free(map);
    return rc;
}

static int run_win_piece(void *user, int index, void *result, char *err, size_t errlen)
{
    const win_plan *pl = user;
    win_piece *r = result;
    memset(r, 0, sizeof *r);
    return run_window(pl, pl->first + (uint32_t)index, r, err, errlen);
}

/* ---- the estimate ---------------------------------------------------------- */

static double point_fig(const accel_point *p, int k)
{
    return k == FID_WIN_CYCLES ? (double)p->cycle : k == FID_WIN_DRAM ? p->dram_bytes : 0.0;
}

/* Figure k of window w: over the window, or over its warm-up. */
static double window_fig(const win_piece *w, int k, bool warm)
{
    if (k == FID_WIN_ENERGY)
        return warm ? w->e_warm : w->e_win;
    if (k >= FID_WIN_UNIT0)
        return warm ? w->u_warm[k - FID_WIN_UNIT0] : w->u_win[k - FID_WIN_UNIT0];
    return warm ? point_fig(&w->a, k) : point_fig(&w->b, k) - point_fig(&w->a, k);
}

/* Pieces run so far (the plan is fixed by the first run; more windows can be added). */
struct fid_win_runs {
    win_plan pl;
    uint32_t *order;              /* the frame's pixel order, for every window (pl.order) */
    win_piece *win;               /* windows 0..count-1 */
    uint32_t count, cap;
    win_lattice lat;
    bool has_lat;
};

void fid_windowed_free(fid_windowed *w)
{
    if (w->runs) {
        free(w->runs->order);
        free(w->runs->win);
        free(w->runs->lat.cum);
        free(w->runs->lat.ncum);
        for (uint32_t k = 0; k < w->runs->lat.nsnap; k++)
            fid_functional_snap_free(&w->runs->lat.snaps[k]);
        free(w->runs->lat.snaps);
        free(w->runs->lat.snap_of);
    }
    free(w->resid);
    free(w->lat_resid);
    free(w->start_resid);
    w->resid = w->lat_resid = w->start_resid = NULL;
    free(w->runs);
    w->runs = NULL;
}

/* Sets the plan: `windows` windows of len pixels, each after `warm`, within
 * rate x the frame; fewer windows (down to win_min_count) before shorter
 * ones; a frame that cannot hold the minimum gets it anyway, flagged. */
static int plan(const fid_job *job, double rate, uint32_t windows, fid_windowed *out, win_plan *pl, char *err,
                size_t errlen)
{
    const fid_params *fp = fid_params_get();
    memset(pl, 0, sizeof *pl);
    pl->job = job;
    pl->snapshot = fp->win_snapshot != 0;
    pl->warm = (uint32_t)(pl->snapshot ? fp->win_snap_warm_pixels : fp->win_warm_pixels);
    pl->lattice_period = (uint32_t)fp->win_lattice;
    pl->npix = (uint64_t)job->width * job->height;
    if (rate <= 0)
        rate = fp->win_rate;
    uint32_t M = windows ? windows : (uint32_t)(pl->snapshot ? fp->win_snap_count : fp->win_count);
    double budget = rate * (double)pl->npix;
    while (M > (uint32_t)fp->win_min_count && budget / M - pl->warm < fp->win_min_pixels)
        M--;
    double len = budget / M - pl->warm;
    if (len < fp->win_min_pixels) {
        len = fp->win_min_pixels;
        out->too_small = true;
    }
    if ((double)M * (len + pl->warm) > 0.5 * (double)pl->npix)
        out->too_small = true;
    if (len > (double)pl->npix / M)
        len = (double)pl->npix / M;
    pl->len = (uint32_t)len;
    if (pl->len == 0 || pl->npix <= pl->warm) {
        snprintf(err, errlen,
                 "windowed: the frame has %llu pixels, too few for windows after %u warm-up pixels each (it needs "
                 "well over %u; use --fidelity full or sampled)",
                 (unsigned long long)pl->npix, pl->warm, 8 * pl->warm);
        return 2;
    }
    out->windows = M, out->warm_pixels = pl->warm, out->window_pixels = pl->len;
    pl->max_windows = M;
    return 0;
}

static void estimate(const fid_job *job, const struct fid_win_runs *r, fid_windowed *out);

bool fid_windowed_fits(const fid_job *job, double rate, uint32_t windows, char *why, size_t whylen)
{
    fid_windowed w;
    win_plan pl;
    memset(&w, 0, sizeof w);
    if (plan(job, rate, windows, &w, &pl, why, whylen))
        return false;
    if (w.too_small)
        snprintf(why, whylen, "the frame (%llu pixels) is too small for %u windows after %u warm-up pixels each",
                 (unsigned long long)pl.npix, w.windows, w.warm_pixels);
    return !w.too_small;
}

/* Runs windows r->count..upto-1 (and the lattice when asked and not yet
 * run) as pieces, keeps them, and estimates when the lattice is there. */
static int run_more(const fid_job *job, struct fid_win_runs *r, uint32_t upto, bool lattice, fid_windowed *out,
                    char *err, size_t errlen)
{
    if (r->pl.snapshot && upto > r->pl.max_windows)
        upto = r->pl.max_windows;   /* a window without the lattice's caches would start cold */
    if (upto > r->cap) {
        win_piece *nw = realloc(r->win, (size_t)upto * sizeof *nw);
        if (!nw) {
            snprintf(err, errlen, "out of memory");
            return 2;
        }
        r->win = nw, r->cap = upto;
    }
    win_plan pl = r->pl;
    pl.first = r->count, pl.count = upto > r->count ? upto - r->count : 0;
    pl.lat = &r->lat;
    int rc = 0;
    /* the lattice runs here, in this process: the windows' auxiliary
     * figures need its per-pixel DRAM lines */
    if ((lattice || pl.snapshot) && !r->has_lat) {   /* functional warming needs the lattice first */
        const double t0 = ks_pool_process_cpu_s();
        rc = run_lattice(&pl, &r->lat, err, errlen);
        r->has_lat = rc == 0;
        out->lattice_cpu_s = ks_pool_process_cpu_s() - t0;
    }
    if (rc == 0 && pl.count > 0) {
        win_piece *pc = calloc(pl.count, sizeof *pc);
        if (!pc) {
            snprintf(err, errlen, "out of memory");
            return 2;
        }
        rc = ks_pool_run((int)pl.count, job->jobs, sizeof *pc, run_win_piece, &pl, pc, err, errlen);
        if (rc == 0) {
            memcpy(r->win + r->count, pc, pl.count * sizeof *pc);
            r->count += pl.count;
        }
        free(pc);
    }
    if (rc == 0) {
        /* the cold fills, known from any windows; the figures need the lattice */
        double fills = 0, cold = 0;
        for (uint32_t i = 0; i < r->count; i++) {
            fills += (double)(r->win[i].b.backed_fills - r->win[i].a.backed_fills);
            cold += (double)(r->win[i].b.backed_cold_fills - r->win[i].a.backed_cold_fills);
        }
        out->cold_share = fills > 0 ? cold / fills : 0;
        out->windows = r->count;
        if (r->has_lat)
            estimate(job, r, out);
    }
    return rc;
}

/* Bytes of one snapshot of the machine's caches: a copy of each cache core
 * (fid_func_snap: every node L1, the node L2, the primitive cache). */
static double snap_bytes(const rtcfg *cfg)
{
    cache_params l1, l2, prim;
    memsys_cache_params(cfg, "node_l1", &l1);
    memsys_cache_params(cfg, "node_l2", &l2);
    memsys_cache_params(cfg, "prim", &prim);
    return (double)rtcfg_int(cfg, "trv.count") * (double)cache_core_bytes(&l1) + (double)cache_core_bytes(&l2) +
           (double)cache_core_bytes(&prim);
}

/* growth: --accuracy may add windows (up to 2.4x the plan, auto_windowed,
 * within win_max_rate of the frame): their snapshots are taken with the
 * lattice's, as far as win_snap_max_bytes allows. */
static int start_plan(const fid_job *job, double rate, uint32_t windows, bool growth, fid_windowed *out, char *err,
                      size_t errlen)
{
    memset(out, 0, sizeof *out);
    struct fid_win_runs *r = calloc(1, sizeof *r);
    if (!r) {
        snprintf(err, errlen, "out of memory");
        return 2;
    }
    out->runs = r;
    int rc = plan(job, rate, windows, out, &r->pl, err, errlen);
    if (rc == 0 && r->pl.snapshot) {
        const fid_params *fp = fid_params_get();
        win_plan *pl = &r->pl;
        double per = snap_bytes(job->cfg), fit = fp->win_snap_max_bytes / per;
        double most = fmin(fp->win_max_rate * (double)pl->npix / (double)(pl->len + pl->warm), 2.4 * pl->max_windows + 2);
        if (fit < pl->max_windows) {
            snprintf(err, errlen,
                     "windowed: the caches' contents for %u windows would take %.0f MB (at most %.0f MB, "
                     "win_snap_max_bytes): use fewer --windows, smaller caches or --fidelity full",
                     pl->max_windows, per * pl->max_windows / 1e6, fp->win_snap_max_bytes / 1e6);
            rc = 2;
        } else if (growth)
            pl->max_windows = (uint32_t)fmax(pl->max_windows, fmin(most, fit));
    }
    if (rc == 0 && !rtsim_pixel_order(job->cfg, job->width, job->height, &r->order, err, errlen))
        rc = 2;
    r->pl.have_order = rc == 0, r->pl.order = r->order;
    return rc;
}

int fid_windowed_run(const fid_job *job, double rate, uint32_t windows, fid_windowed *out, char *err, size_t errlen)
{
    int rc = start_plan(job, rate, windows, false, out, err, errlen);
    return rc ? rc : run_more(job, out->runs, out->windows, true, out, err, errlen);
}

int fid_windowed_probe(const fid_job *job, double rate, uint32_t windows, uint32_t count, fid_windowed *out,
                       char *err, size_t errlen)
{
    int rc = start_plan(job, rate, windows, true, out, err, errlen);
    if (rc)
        return rc;
    uint32_t planned = out->windows;
    rc = run_more(job, out->runs, count < planned ? count : planned, true, out, err, errlen);
    out->planned = planned;
    return rc;
}

int fid_windowed_cold_probe(const fid_job *job, double *cold_share, double *turnover, char *err, size_t errlen)
{
    *turnover = 0;
    const fid_params *fp = fid_params_get();
    win_plan pl;
    memset(&pl, 0, sizeof pl);
    pl.job = job;
    pl.npix = (uint64_t)job->width * job->height;
    pl.warm = (uint32_t)fp->win_warm_pixels;
    pl.len = (uint32_t)fp->win_probe_pixels;
    pl.lattice_period = (uint32_t)fp->win_lattice;
    *cold_share = 0;
    if (pl.npix < (uint64_t)pl.warm + pl.len) {
        snprintf(err, errlen, "windowed: the frame has %llu pixels, too few for the probe", (unsigned long long)pl.npix);
        return 2;
    }
    /* window 1 of the sequence: the middle of the frame's order, away
     * from its first pixels (the probe's warm-up must be whole) */
    win_piece r;
    memset(&r, 0, sizeof r);
    int rc = run_window(&pl, 1, &r, err, errlen);
    double fills = (double)(r.b.backed_fills - r.a.backed_fills);
    *cold_share = fills > 0 ? (double)(r.b.backed_cold_fills - r.a.backed_cold_fills) / fills : 0;
    /* the frame's fills at the window's rate, in cache capacities (node L2
     * + primitive cache lines) */
    double cap = (double)rtcfg_int(job->cfg, "node_l2.size") / (double)rtcfg_int(job->cfg, "node_l2.line") +
                 (double)rtcfg_int(job->cfg, "prim.size") / (double)rtcfg_int(job->cfg, "prim.line");
    double measured = (double)(r.b.primaries - r.a.primaries);
    *turnover = cap > 0 && measured > 0 ? fills / measured * (double)pl.npix / cap : 0;
    return rc;
}

int fid_windowed_more(const fid_job *job, uint32_t windows, fid_windowed *out, char *err, size_t errlen)
{
    return run_more(job, out->runs, windows, true, out, err, errlen);
}

/* The start correction's and the lattice's errors of headline figure k as
 * residuals that pair across machines (windowed.h lat_resid, start_resid):
 * the same windows and the same lattice pixels give every machine of a
 * sweep the same sampling, so in a change between two machines these
 * errors largely cancel, as the windows' do. ex[i]: window i's start
 * excess (estimate's). Each set's sum of squares is
 * the variance of its part of the figure (relative): the start
 * correction is the mean of cn windows' excesses; the lattice's part is the
 * mean of FID_LAT_GROUPS interleaved groups' estimates (replicated
 * sampling: the groups' spread stands for the lattice's). */
static void pairing_residuals(const win_lattice *lat, const double beta[FID_AUX_COUNT], const double *ex,
                              const win_piece *pc, const uint32_t *order, uint32_t M, double cbar, double cn,
                              double fpc, double N, double e, int k, fid_windowed *out)
{
    double norm = cn > 1 ? 1.0 / (e * sqrt(cn * (cn - 1))) : 0;
    for (uint32_t q = 0; q < M; q++) {
        const win_piece *w = &pc[order[q]];
        out->start_resid[(size_t)k * M + q] =
            w->a.primaries ? (ex[order[q]] - cbar) * norm : 0;
    }
    out->start_windows = (uint32_t)cn;
    double T[FID_LAT_GROUPS], mean = 0;
    int G = 0;
    for (int g = 0; g < FID_LAT_GROUPS; g++)
        if (lat->gn[g] > 0) {
            T[g] = N / lat->gn[g] * fid_dot(beta, lat->gx[g]);
            mean += T[g], G++;
        }
    mean = G ? mean / G : 0;
    double gnorm = G > 1 && G == FID_LAT_GROUPS ? sqrt(fpc) / (e * sqrt((double)G * (G - 1))) : 0;
    for (int g = 0; g < FID_LAT_GROUPS; g++)
        out->lat_resid[(size_t)k * FID_LAT_GROUPS + g] = gnorm > 0 ? (T[g] - mean) * gnorm : 0;
}

/* The frame's figures and their errors from the windows run so far. */
static void estimate(const fid_job *job, const struct fid_win_runs *r, fid_windowed *out)
{
    const win_plan pl = r->pl;
    const uint32_t M = r->count;
    const win_piece *pc = r->win;
    (void)job;
    out->windows = M;
    out->model_pixels = 0;
    /* the lattice: the frame's auxiliary figures and rays */
    const win_lattice *lat = &r->lat;
    double N = (double)pl.npix, n = lat->n > 0 ? lat->n : 1, fpc = fmax(0.0, 1.0 - n / N);
    double X[FID_AUX_COUNT];
    for (int a = 0; a < FID_AUX_COUNT; a++)
        X[a] = N * lat->x[a] / n;
    double mr = lat->r / n, vr = fmax(0.0, lat->r2 / n - mr * mr) * n / fmax(n - 1, 1);
    out->lattice_pixels = lat->n;
    out->rays_err = mr > 0 ? 1.96 * sqrt(vr * fpc / n) / mr : 1.0;
    out->primaries = N;
    out->rays = N * mr;

    /* the windows, and their auxiliary figures with the lattice's DRAM lines */
    double(*xw)[FID_AUX_COUNT] = malloc((size_t)M * sizeof *xw), (*xs)[FID_AUX_COUNT] = malloc((size_t)M * sizeof *xs);
    double *y = malloc((size_t)M * sizeof *y), *ex = malloc((size_t)M * sizeof *ex);
    uint32_t *order = malloc((size_t)M * sizeof *order);
    uint64_t *pos = malloc((size_t)M * sizeof *pos);
    if (!xw || !xs || !y || !ex || !order || !pos) {
        free(xw), free(xs), free(y), free(ex), free(order), free(pos);
        for (int k = 0; k < FID_WIN_FIGS; k++)
            out->ci[k] = 1.0;   /* no interval: flagged by the bound */
        return;
    }
    double rays = 0, lat_sum = 0, prim = 0, fills = 0, cold = 0, s_static = 0, s_dram = 0, cycles_win = 0;
    for (uint32_t i = 0; i < M; i++) {
        const win_piece *w = &pc[i];
        s_static += w->s_win;
        s_dram += w->u_win[EU_COUNT];
        cycles_win += (double)(w->b.cycle - w->a.cycle);
        rays += (double)(w->b.completed - w->a.completed);
        lat_sum += (double)(w->b.latency_sum - w->a.latency_sum);
        prim += (double)(w->b.primaries - w->a.primaries);
        out->model_pixels += (double)w->b.primaries;
        fills += (double)(w->b.backed_fills - w->a.backed_fills);
        cold += (double)(w->b.backed_cold_fills - w->a.backed_cold_fills);
        uint64_t first, st, end;
        window_range(&pl, i, &first, &st, &end);
        pos[i] = st, order[i] = i;
        memcpy(xw[i], w->x_win, sizeof xw[i]);
        memcpy(xs[i], w->x_warm, sizeof xs[i]);
        xs[i][FID_AUX_DRAM_LINES] = lattice_lines(lat, first, first + w->a.primaries);
        xw[i][FID_AUX_DRAM_LINES] = lattice_lines(lat, first + w->a.primaries, first + w->b.primaries);
    }
    out->measured_pixels = prim;
    out->mean_latency = rays > 0 ? lat_sum / rays : 0;
    out->cold_share = fills > 0 ? cold / fills : 0;
    /* The windows are a stratified sample, one window per band of rows
     * (radical_inverse): the interval uses collapsed strata, the windows in
     * image order paired with their neighbours, each pair's difference of
     * residuals standing for the spread within its two bands (the formula
     * of a simple random sample, or a jackknife over groups spread over the
     * image, counts the differences between distant bands too, which the
     * stratification removes: 3-6x the spread of the estimate over shifted
     * window sets on interior diffuse). An odd window out is paired with its
     * neighbour once more. */
    for (uint32_t i = 1; i < M; i++)   /* insertion sort: M is small */
        for (uint32_t j = i; j > 0 && pos[order[j - 1]] > pos[order[j]]; j--) {
            uint32_t tmp = order[j];
            order[j] = order[j - 1], order[j - 1] = tmp;
        }
    uint32_t npairs = M / 2 + M % 2;
    double t = fid_t95((int)npairs), f = fmin(1.0, prim / N);
    double *res = malloc((size_t)(M ? M : 1) * sizeof *res);
    free(out->resid);
    free(out->lat_resid);
    free(out->start_resid);
    out->resid = malloc((size_t)(M ? M : 1) * FID_WIN_HEADLINE * sizeof *out->resid);
    out->lat_resid = calloc((size_t)FID_LAT_GROUPS * FID_WIN_HEADLINE, sizeof *out->lat_resid);
    out->start_resid = calloc((size_t)(M ? M : 1) * FID_WIN_HEADLINE, sizeof *out->start_resid);
    out->start_windows = 0;
    out->t95 = t, out->npairs = npairs;
    /* the drain: the last pixel's path ends one path latency after its admission */
    double drain = out->mean_latency * (prim > 0 ? rays / prim : 1.0);
    for (int k = 0; k < FID_WIN_FIGS; k++) {
        /* y = beta . x per window: node visits load the TRVs and triangle
         * tests the IST, and either may bound a window's cycles, so one
         * ratio to their sum would carry the windows' mix of the two into
         * the frame; the bounces' work costs differently from the primary
         * rays' (coherent primary rays hit in the caches); the lattice's
         * DRAM lines follow where in the scene the misses are */
        double beta[FID_AUX_COUNT], cs = 0, cs2 = 0, cn = 0, fitted = 0, pvar = 0;
        for (uint32_t i = 0; i < M; i++)
            y[i] = window_fig(&pc[i], k, false);
        int used = fid_fit_nonneg((const double(*)[FID_AUX_COUNT])xw, y, M, beta);
        double steady = fid_dot(beta, X);
        for (uint32_t i = 0; i < M; i++)
            fitted += fid_dot(beta, xw[i]);
        for (uint32_t q = 0; q < M && res; q++)
            res[q] = y[order[q]] - fid_dot(beta, xw[order[q]]);   /* in image order */
        pvar = res ? fid_pairs_sumsq(res, M, NULL) : 0;
        /* the windows' residual sum scaled to the frame as the fit scales
         * them; residuals of a fit are smaller than the errors by M - used
         * of M degrees of freedom */
        double scale = fitted > 0 ? steady / fitted : 0, dof = M > (uint32_t)used ? (double)M / (M - used) : 1.0;
        pvar *= scale * scale * dof;
        /* the warm-up's excess over its steady share: the cost of a cold start */
        for (uint32_t i = 0; i < M; i++) {
            const win_piece *w = &pc[i];
            if (!w->a.primaries)
                continue;
            double c = ex[i] = window_fig(w, k, true) - fid_dot(beta, xs[i]);
            cs += c, cs2 += c * c, cn += 1;
        }
        double cbar = cn > 0 ? cs / cn : 0;
        double csd = cn > 1 ? sqrt(fmax(0.0, (cs2 - cn * cbar * cbar) / (cn - 1))) : fabs(cbar);
        double e = steady + cbar;
        if (k == FID_WIN_CYCLES)
            e += drain;
        else if (k == FID_WIN_ENERGY && cycles_win > 0)
            e += s_static / cycles_win * drain;   /* the drain's static energy */
        else if (k == FID_WIN_DRAM_STATIC && cycles_win > 0)
            e += s_dram / cycles_win * drain;
        out->ci[k] = e > 0 && M > 1 && res ? t * sqrt((1.0 - f) * pvar) / e : 1.0;
        /* each window's residual as it enters the interval, relative to the
         * frame's figure: the paired estimates of a sweep pair these
         * across machines (ci = t . sqrt(fid_pairs_sumsq(resid))) */
        for (uint32_t q = 0; k < FID_WIN_HEADLINE && q < M && res && out->resid; q++)
            out->resid[(size_t)k * M + q] = e > 0 ? res[q] * scale * sqrt(dof * (1.0 - f)) / e : 0;
        out->start_err[k] = e > 0 && cn > 0 ? fid_t95((int)cn - 1) * csd / sqrt(cn) / e : 0;
        if (k < FID_WIN_HEADLINE && e > 0 && out->start_resid && out->lat_resid)
            pairing_residuals(lat, beta, ex, pc, order, M, cbar, cn, fpc, N, e, k, out);
        /* the lattice's standard error of beta . x per pixel */
        double m = 0, v = 0;
        for (int a = 0; a < FID_AUX_COUNT; a++) {
            m += beta[a] * lat->x[a] / n;
            for (int b = 0; b < FID_AUX_COUNT; b++)
                v += beta[a] * beta[b] * (lat->xx[a][b] / n - (lat->x[a] / n) * (lat->x[b] / n));
        }
        v = fmax(0.0, v) * n / fmax(n - 1, 1);
        out->lattice_err[k] = m > 0 ? 1.96 * sqrt(v * fpc / n) / m * (steady / e) : 1.0;
        if (k == FID_WIN_CYCLES)
            out->cycles = e;
        else if (k == FID_WIN_DRAM)
            out->dram_bytes = e;
        else if (k == FID_WIN_ENERGY)
            out->energy_mj = e;
        else
            out->unit_mj[k - FID_WIN_UNIT0] = e;
    }
    out->has_units = M > 0 && pc[0].has_units;
    for (int u = 0; u < EU_COUNT && out->has_units; u++)
        out->leak_mw[u] = pc[0].leak_mw[u], out->area_mm2[u] = pc[0].area_mm2[u];
    out->static_mj = cycles_win > 0 ? s_static / cycles_win * out->cycles : 0;
    free(xw), free(xs), free(y), free(ex), free(order), free(pos), free(res);
}
