/* tb_fidelity_functional.c — the functional level's per-pixel attribution
 * (fidelity/functional.h fid_functional_run_attributed), which the windowed
 * level's lattice uses as its auxiliary figures (fidelity/windowed.h):
 *   - what it charges to the pixels adds up to the run's own totals: the
 *     node visits, the triangle tests, the rays and the DRAM lines; the
 *     bounces' work is a part of the work;
 *   - asking for it changes nothing of the run (the same counts and cycles
 *     as fid_functional_run on the same pixels);
 *   - every pixel gets its primary ray's visits, and primary rays get no
 *     bounce work;
 * and the phase excess (fid_func.phase_excess), which the sampled level's
 * estimate adds: rays that load the TRVs, then rays that load the IST show
 * it; the same rays alternating do not. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fidelity/functional.h"
#include "frame/frame.h"
#include "model/accel_config.h"
#include "model/mem/memsys_config.h"
#include "testbench/tb.h"
#include "tracer/io/scene.h"

/* The machine preset's configuration and the scene's BVH for it (*img;
 * freed by the caller, built or not), or NULL with a message. */
static rtcfg *machine_bvh(const rt_scene *sc, const char *preset, rt_bvh_image *img, char *err, size_t errlen)
{
    memset(img, 0, sizeof *img);
    rtcfg *cfg = rtcfg_create();
    if (!cfg || memsys_add_schemas(cfg, err, errlen) || accel_add_schemas(cfg, err, errlen) ||
        rtcfg_load(cfg, preset, err, errlen) || rtcfg_finish(cfg, err, errlen)) {
        rtcfg_destroy(cfg);
        return NULL;
    }
    rt_bvh_params bp;
    rt_bvh_params_default(&bp);
    bp.width = (int)rtcfg_int(cfg, "machine.branching");
    if (!rt_bvh_build(&sc->mesh, &bp, img, NULL, err, errlen)) {
        rtcfg_destroy(cfg);
        return NULL;
    }
    return cfg;
}

static void check_attribution(const rt_scene *sc, const char *preset, bool diffuse)
{
    char name[400], err[1024];
    snprintf(name, sizeof name, "functional_attribution_%s_%s_%s", sc->name, preset, diffuse ? "diffuse" : "primary");
    tb_begin(name);
    rt_bvh_image img;
    rtcfg *cfg = machine_bvh(sc, preset, &img, err, sizeof err);
    if (!TB_CHECK(cfg != NULL, "machine: %s", err)) {
        rt_bvh_image_free(&img);
        tb_end();
        return;
    }
    const uint32_t w = 64, h = 36;
    /* a subset in a lattice's order, as the windowed level runs it: 1 pixel in 3 */
    uint32_t px[64 * 36], n = 0;
    for (uint32_t p = 0; p < w * h; p++)
        if ((p % w + 5 * (p / w)) % 3 == 0)
            px[n++] = p;
    fid_func_attr *attr = calloc(n, sizeof *attr);
    if (TB_CHECK(attr != NULL, "out of memory")) {
        fid_job job = {cfg, &sc->mesh, &sc->views.v[0], &img, w, h, diffuse, 2, 1, 0, NULL, NULL, 1, 0, NULL, 0};
        fid_func plain, withattr;
        bool ran = TB_CHECK(fid_functional_run(&job, px, n, &plain, err, sizeof err) == 0, "run: %s", err) &&
                   TB_CHECK(fid_functional_run_attributed(&job, px, n, &withattr, attr, err, sizeof err) == 0,
                            "attributed run: %s", err);
        if (ran) {
            double visits = 0, tests = 0, work_b = 0, lines = 0, rays = 0;
            uint32_t no_primary = 0;
            for (uint32_t i = 0; i < n; i++) {
                visits += attr[i][FID_ATTR_VISITS], tests += attr[i][FID_ATTR_TRI_TESTS];
                work_b += attr[i][FID_ATTR_BOUNCE_WORK];
                lines += attr[i][FID_ATTR_DRAM_LINES], rays += attr[i][FID_ATTR_RAYS];
                no_primary += !(attr[i][FID_ATTR_VISITS] > 0) || !(attr[i][FID_ATTR_RAYS] >= 1);
            }
            TB_EQ_INT(visits, withattr.visits);
            TB_EQ_INT(tests, withattr.tri_tests);
            TB_CHECK(work_b <= visits + tests, "bounce work %.0f over all the work %.0f", work_b, visits + tests);
            TB_EQ_INT(lines, withattr.dram_lines);
            TB_EQ_INT(rays, withattr.rays);
            TB_EQ_INT(no_primary, 0);
            TB_CHECK(withattr.dram_lines > 0, "the run fetched no DRAM line");
            if (diffuse)
                TB_CHECK(work_b > 0 && withattr.bounces > 0, "diffuse rays: bounce work %.0f", work_b);
            else
                TB_EQ_INT(work_b, 0);
            /* the attributed run is the plain one */
            TB_EQ_INT(withattr.dram_lines, plain.dram_lines);
            TB_EQ_INT(withattr.row_hits, plain.row_hits);
            TB_EQ_INT(withattr.visits, plain.visits);
            TB_EQ_INT(withattr.l2.misses, plain.l2.misses);
            TB_CHECK(withattr.cycles == plain.cycles, "cycles %.1f vs %.1f", withattr.cycles, plain.cycles);
        }
    }
    free(attr);
    rt_bvh_image_free(&img);
    rtcfg_destroy(cfg);
    tb_end();
}

/* fid_functional_add: the counts of two passes add; and a pass added to
 * itself has the pass's throughput (the figures are ratios of counts, but
 * for the drain at the end), which is what lets sampled's groups, summed,
 * stand in for the frame's pass (level_sampled.c). */
static void check_add(const rt_scene *sc)
{
    char err[1024];
    tb_begin("functional_add_counts_and_scale");
    rt_bvh_image img;
    rtcfg *cfg = machine_bvh(sc, "mbvh4", &img, err, sizeof err);
    if (!TB_CHECK(cfg != NULL, "machine: %s", err)) {
        rt_bvh_image_free(&img);
        tb_end();
        return;
    }
    /* big enough for the drain (one path's latency) to be small beside the run */
    const uint32_t w = 320, h = 180;
    static uint32_t even[320 * 90], odd[320 * 90];
    uint32_t ne = 0, no = 0;
    for (uint32_t p = 0; p < w * h; p++) {
        if ((p / w) % 2)
            odd[no++] = p;
        else
            even[ne++] = p;
    }
    fid_job job = {cfg, &sc->mesh, &sc->views.v[0], &img, w, h, true, 2, 1, 0, NULL, NULL, 1, 0, NULL, 0};
    fid_func a, b;
    if (TB_CHECK(fid_functional_run(&job, even, ne, &a, err, sizeof err) == 0, "run: %s", err) &&
        TB_CHECK(fid_functional_run(&job, odd, no, &b, err, sizeof err) == 0, "run: %s", err)) {
        fid_func sum, twice;
        memset(&sum, 0, sizeof sum);
        fid_functional_add(&sum, &a);
        fid_functional_add(&sum, &b);
        TB_EQ_INT(sum.rays, a.rays + b.rays);
        TB_EQ_INT(sum.visits, a.visits + b.visits);
        TB_EQ_INT(sum.tri_tests, a.tri_tests + b.tri_tests);
        TB_EQ_INT(sum.trv_visits[1], a.trv_visits[1] + b.trv_visits[1]);
        TB_EQ_INT(sum.l1.misses, a.l1.misses + b.l1.misses);
        TB_EQ_INT(sum.l2.fills, a.l2.fills + b.l2.fills);
        TB_EQ_INT(sum.prim.accesses, a.prim.accesses + b.prim.accesses);
        TB_EQ_INT(sum.dram_bytes, a.dram_bytes + b.dram_bytes);
        TB_EQ_INT(sum.row_hits, a.row_hits + b.row_hits);
        memset(&twice, 0, sizeof twice);
        fid_functional_add(&twice, &a);
        fid_functional_add(&twice, &a);
        fid_functional_retime(&job, &twice, 1.0);
        TB_CHECK(a.mrps > 0 && fabs(twice.mrps / a.mrps - 1.0) < 0.01, "a pass added to itself: %.3f MRPS, alone %.3f",
                 twice.mrps, a.mrps);
        TB_CHECK(twice.dram_util > 0 && fabs(twice.dram_util / a.dram_util - 1.0) < 0.01,
                 "DRAM utilisation %.4f, alone %.4f", twice.dram_util, a.dram_util);
    }
    rt_bvh_image_free(&img);
    rtcfg_destroy(cfg);
    tb_end();
}

/* Of pixels 0, 37, 74, ...: the one whose primary ray loads the TRVs most
 * against the IST (*trv_px) and the one that loads the IST most (*ist_px),
 * each traced alone. */
static bool extreme_pixels(const fid_job *job, uint32_t n, uint32_t *trv_px, uint32_t *ist_px, char *err, size_t errlen)
{
    double hi = -1, lo = 1e300;
    for (uint32_t p = 0; p < n; p += 37) {
        fid_func f;
        if (fid_functional_run(job, &p, 1, &f, err, errlen))
            return false;
        double r = (double)(f.visits + f.leaves) / (double)(f.tri_tests + 1);
        if (r > hi)
            hi = r, *trv_px = p;
        if (r < lo)
            lo = r, *ist_px = p;
    }
    return hi > 2 * lo;
}

/* The phase excess (functional.h): the same rays, a pixel that loads the
 * TRVs and one that loads the IST, either in two runs of half the list
 * each (the load moves from the TRVs to the IST half way) or alternating
 * (every phase carries both). */
static void check_phases(const rt_scene *sc)
{
    char err[1024];
    tb_begin("functional_phase_excess_interior_mbvh4_primary");
    rt_bvh_image img;
    rtcfg *cfg = machine_bvh(sc, "mbvh4", &img, err, sizeof err);
    enum { W = 64, H = 36, N = 16384 };   /* 512 rays a phase: the TRVs' shares even out */
    uint32_t a = 0, b = 0;
    static uint32_t halves[N], alternate[N];
    if (TB_CHECK(cfg != NULL, "machine: %s", err)) {
        fid_job job = {cfg, &sc->mesh, &sc->views.v[0], &img, W, H, false, 0, 1, 0, NULL, NULL, 1, 0, NULL, 0};
        fid_func f_halves, f_alt;
        if (TB_CHECK(extreme_pixels(&job, W * H, &a, &b, err, sizeof err), "no pixels of different loads: %s", err)) {
            for (uint32_t i = 0; i < N; i++)
                halves[i] = i < N / 2 ? a : b, alternate[i] = i % 2 ? b : a;
            if (TB_CHECK(fid_functional_run(&job, halves, N, &f_halves, err, sizeof err) == 0, "run: %s", err) &&
                TB_CHECK(fid_functional_run(&job, alternate, N, &f_alt, err, sizeof err) == 0, "run: %s", err)) {
                TB_EQ_INT(f_halves.visits, f_alt.visits);   /* the same rays */
                TB_EQ_INT(f_halves.tri_tests, f_alt.tri_tests);
                TB_CHECK(f_halves.phase_excess > 0.2, "in halves: excess %.4f", f_halves.phase_excess);
                TB_CHECK(f_alt.phase_excess >= 0 && f_alt.phase_excess < 0.05, "alternating: excess %.4f",
                         f_alt.phase_excess);
            }
        }
    }
    rt_bvh_image_free(&img);
    rtcfg_destroy(cfg);
    tb_end();
}

int main(void)
{
    static const char *const scenes[] = {"interior", "hairball"};
    for (int s = 0; s < 2; s++) {
        rt_scene sc;
        char err[512];
        if (!rt_scene_load(scenes[s], &sc, err, sizeof err)) {
            tb_begin("functional_attribution_load");
            TB_CHECK(false, "%s: %s", scenes[s], err);
            tb_end();
            continue;
        }
        check_attribution(&sc, "mbvh4", true);
        check_attribution(&sc, "bvh2", false);
        if (s == 0) {
            check_phases(&sc);
            check_add(&sc);
        }
        rt_scene_free(&sc);
    }
    return tb_finish();
}
