/* tb_tracer_rays.c — ray generation: PCG32 known answers and stream
 * independence, camera rays on known pixels against the convention of
 * ../shared/scenes/README.md, cosine-weighted bounce statistics with a fixed
 * seed, order independence, self-hit offset, path termination, shading. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "testbench/tb.h"
#include "tracer/trace/bounce.h"
#include "tracer/io/builtin.h"
#include "tracer/trace/camera.h"
#include "tracer/util/det_math.h"
#include "tracer/util/rng.h"
#include "tracer/trace/shade.h"

static void test_rng(void)
{
    tb_begin("rng_pcg32_reference_values");
    /* pcg32-demo of the reference C implementation (pcg-random.org):
     * pcg32_srandom_r(&rng, 42u, 54u) then six pcg32_random_r(). */
    static const uint32_t want[6] = {0xa15c02b7, 0x7b47f409, 0xba1d3330, 0x83d2f293, 0xbfa4784b, 0xcbed606e};
    rt_rng r;
    rt_rng_seed(&r, 42u, 54u);
    for (int i = 0; i < 6; i++) {
        uint32_t got = rt_rng_u32(&r);
        TB_CHECK(got == want[i], "output %d: %08x != %08x", i, got, want[i]);
    }
    tb_end();

    tb_begin("rng_streams_deterministic_and_distinct");
    rt_rng a = rt_rng_for_ray(1, 1234, 2), b = rt_rng_for_ray(1, 1234, 2);
    rt_rng c = rt_rng_for_ray(1, 1234, 3), d = rt_rng_for_ray(1, 1235, 2), e = rt_rng_for_ray(2, 1234, 2);
    uint32_t xa = rt_rng_u32(&a);
    TB_CHECK(xa == rt_rng_u32(&b), "same triple, same numbers");
    TB_CHECK(xa != rt_rng_u32(&c) && xa != rt_rng_u32(&d) && xa != rt_rng_u32(&e), "different triples differ");
    tb_end();

    tb_begin("rng_float_uniform_chi_square");
    rt_rng_seed(&r, 7, 0);
    enum { BINS = 16, N = 160000 };
    unsigned hist[BINS] = {0};
    float lo = 1, hi = 0;
    for (int i = 0; i < N; i++) {
        float f = rt_rng_float(&r);
        lo = f < lo ? f : lo, hi = f > hi ? f : hi;
        hist[(int)(f * BINS)]++;
    }
    double chi2 = 0, expect = (double)N / BINS;
    for (int i = 0; i < BINS; i++)
        chi2 += (hist[i] - expect) * (hist[i] - expect) / expect;
    /* 15 degrees of freedom: P(chi2 > 37.7) = 0.001 */
    TB_CHECK(chi2 < 37.7, "chi2 %.1f", chi2);
    TB_CHECK(lo >= 0 && hi < 1, "range [%g, %g]", (double)lo, (double)hi);
    unsigned below[5] = {0};
    for (int i = 0; i < 5000; i++)
        below[rt_rng_below(&r, 5)]++;
    for (int i = 0; i < 5; i++)
        TB_CHECK(below[i] > 850 && below[i] < 1150, "rt_rng_below(5) bin %d = %u", i, below[i]);
    tb_end();
}

static double dot3(rt_vec3 a, rt_vec3 b) { return (double)a.x * b.x + (double)a.y * b.y + (double)a.z * b.z; }

static void test_det_math(void)
{
    tb_begin("det_math_matches_libm");
    double worst = 0;
    for (int i = -4000; i <= 4000; i++) {
        double x = i * 0.0251327;   /* about -100 .. 100 */
        worst = fmax(worst, fabs(rt_det_sin(x) - sin(x)));
        worst = fmax(worst, fabs(rt_det_cos(x) - cos(x)));
        if (fabs(cos(x)) > 0.1)
            worst = fmax(worst, fabs(rt_det_tan(x) - tan(x)) * fabs(cos(x)) * fabs(cos(x)));
    }
    TB_CHECK(worst < 1e-12, "max error %g (documented bound 1e-12)", worst);
    TB_CHECK(rt_det_sqrt(2.0) == sqrt(2.0) && rt_det_sqrt(-1.0) == 0, "sqrt");
    tb_end();
}

static void test_camera(void)
{
    tb_begin("camera_known_pixels_match_readme_convention");
    rt_view v;
    memset(&v, 0, sizeof v);
    strcpy(v.name, "t");
    v.eye = (rt_vec3){1, 2, 3};
    v.at = (rt_vec3){1, 2, 2};       /* forward = -z */
    v.up = (rt_vec3){0, 5, 0};       /* need not be unit */
    v.fov_deg = 90;                   /* s = tan(45) = 1 */
    rt_camera cam;
    char err[256] = "";
    if (TB_CHECK(rt_camera_init(&cam, &v, 4, 2, err, sizeof err), "%s", err)) {
        /* right = cross(forward, up) = +x; up' = +y.
         * (0,0): u = (2*0.5/4-1)*1*2 = -1.5, v = (1-2*0.5/2)*1 = 0.5 -> (-1.5, 0.5, -1)
         * (3,1): u = (2*3.5/4-1)*2 = 1.5,   v = (1-2*1.5/2) = -0.5 -> (1.5, -0.5, -1) */
        static const struct { uint32_t px, py; double d[3]; } cases[] = {
            {0, 0, {-1.5, 0.5, -1}}, {3, 1, {1.5, -0.5, -1}}, {1, 0, {-0.5, 0.5, -1}}, {2, 1, {0.5, -0.5, -1}}};
        for (int i = 0; i < 4; i++) {
            rt_ray r = rt_camera_primary_ray(&cam, cases[i].px, cases[i].py);
            double l = sqrt(cases[i].d[0] * cases[i].d[0] + cases[i].d[1] * cases[i].d[1] + cases[i].d[2] * cases[i].d[2]);
            double ex = cases[i].d[0] / l, ey = cases[i].d[1] / l, ez = cases[i].d[2] / l;
            TB_CHECK(fabs(r.dir.x - ex) < 1e-6 && fabs(r.dir.y - ey) < 1e-6 && fabs(r.dir.z - ez) < 1e-6,
                     "pixel (%u,%u): dir (%g %g %g) want (%g %g %g)", cases[i].px, cases[i].py, (double)r.dir.x,
                     (double)r.dir.y, (double)r.dir.z, ex, ey, ez);
            TB_CHECK(r.org.x == 1 && r.org.y == 2 && r.org.z == 3, "origin = eye");
            TB_EQ_INT(r.pixel, cases[i].py * 4 + cases[i].px);
            TB_EQ_INT(r.bounce, 0);
            TB_CHECK(r.tmin == 0 && r.tmax == RT_RAY_TMAX, "tmin/tmax");
        }
    }
    tb_end();

    tb_begin("camera_centre_ray_points_at_target_and_rejects_bad_views");
    /* The bunny's default view from ../shared/scenes/bunny/views.txt: with an
     * odd resolution the centre pixel's ray goes exactly towards `at`. */
    v.eye = (rt_vec3){-0.21f, 0.16f, 0.235f};
    v.at = (rt_vec3){-0.0168f, 0.104f, -0.0015f};
    v.up = (rt_vec3){0, 1, 0};
    v.fov_deg = 36;
    if (TB_CHECK(rt_camera_init(&cam, &v, 641, 361, err, sizeof err), "%s", err)) {
        rt_ray r = rt_camera_primary_ray(&cam, 320, 180);
        rt_vec3 f = {v.at.x - v.eye.x, v.at.y - v.eye.y, v.at.z - v.eye.z};
        double c = dot3(r.dir, f) / sqrt(dot3(f, f));
        TB_CHECK(c > 1 - 1e-6, "centre ray cos to target %.9f", c);
        rt_ray tl = rt_camera_primary_ray(&cam, 0, 0);
        TB_CHECK(tl.dir.y > r.dir.y, "top row looks up (py = 0 is the top)");
    }
    rt_view bad = v;
    bad.up = (rt_vec3){v.at.x - v.eye.x, v.at.y - v.eye.y, v.at.z - v.eye.z};
    TB_CHECK(!rt_camera_init(&cam, &bad, 64, 64, err, sizeof err) && strstr(err, "parallel"), "up || forward: %s", err);
    bad = v;
    bad.fov_deg = 180;
    TB_CHECK(!rt_camera_init(&cam, &bad, 64, 64, err, sizeof err) && strstr(err, "0 < fov < 180"), "fov: %s", err);
    TB_CHECK(!rt_camera_init(&cam, &v, 0, 64, err, sizeof err) && strstr(err, "1..65535"), "res: %s", err);
    uint32_t w, h;
    TB_CHECK(rt_parse_resolution("1280x720", &w, &h, err, sizeof err) && w == 1280 && h == 720, "1280x720");
    TB_CHECK(!rt_parse_resolution("1280x", &w, &h, err, sizeof err) && strstr(err, "WxH"), "bad: %s", err);
    TB_CHECK(!rt_parse_resolution("0x10", &w, &h, err, sizeof err), "0x10 rejected");
    TB_CHECK(!rt_parse_resolution("70000x10", &w, &h, err, sizeof err), "70000x10 rejected");
    tb_end();
}

/* One big triangle in the plane z = 0 (normal +z as stored). */
static rt_vec3 tri_verts[3] = {{-100, -100, 0}, {100, -100, 0}, {0, 100, 0}};
static uint32_t tri_idx[3] = {0, 1, 2};
static const rt_mesh plane = {tri_verts, tri_idx, 3, 1};

static void test_bounce(void)
{
    tb_begin("bounce_cosine_distribution_and_hemisphere");
    /* A ray coming down onto the plane from +z: the facing normal is +z. For
     * cosine-weighted sampling cos^2(theta) is uniform on [0,1] and the
     * azimuth is uniform; chi-square tests over 10 bins each. */
    enum { N = 100000, BINS = 10 };
    unsigned hc[BINS] = {0}, ha[BINS] = {0}, below = 0;
    double mean_cos = 0;
    for (uint32_t p = 0; p < N; p++) {
        rt_ray in = {{0.25f, 0.5f, 10}, {0, 0, -1}, 0, RT_RAY_TMAX, p, 0, 0};
        rt_hit hit = {10, 0.1f, 0.1f, 0};
        rt_ray out;
        if (!rt_bounce_ray(&plane, &in, &hit, 99, 4, &out)) {
            below++;
            continue;
        }
        double c = out.dir.z;
        below += c <= 0;
        mean_cos += c;
        int bc = (int)(c * c * BINS), ba = (int)((atan2(out.dir.y, out.dir.x) + M_PI) / (2 * M_PI) * BINS);
        hc[bc < BINS ? bc : BINS - 1]++;
        ha[ba < BINS ? ba : BINS - 1]++;
    }
    TB_EQ_INT(below, 0);
    double chic = 0, chia = 0, e = (double)N / BINS;
    for (int i = 0; i < BINS; i++) {
        chic += (hc[i] - e) * (hc[i] - e) / e;
        chia += (ha[i] - e) * (ha[i] - e) / e;
    }
    /* 9 degrees of freedom: P(chi2 > 27.9) = 0.001 */
    TB_CHECK(chic < 27.9, "cos^2 histogram chi2 %.1f", chic);
    TB_CHECK(chia < 27.9, "azimuth histogram chi2 %.1f", chia);
    mean_cos /= N;
    TB_CHECK(fabs(mean_cos - 2.0 / 3.0) < 0.005, "E[cos] %.4f, cosine-weighted gives 2/3", mean_cos);
    tb_end();

    tb_begin("bounce_faces_incoming_side_offsets_and_terminates");
    rt_ray up = {{0, 0, -5}, {0, 0, 1}, 0, RT_RAY_TMAX, 42, 1, 0};
    rt_hit hit = {5, 0, 0, 0};
    rt_ray out;
    TB_CHECK(rt_bounce_ray(&plane, &up, &hit, 1, 4, &out), "bounce from below");
    TB_CHECK(out.dir.z < 0 && out.org.z < 0, "leaves on the side the ray came from: dir.z %g org.z %g",
             (double)out.dir.z, (double)out.org.z);
    TB_CHECK(out.org.z > -1e-3f, "offset small: %g", (double)out.org.z);
    TB_CHECK(fabs(dot3(out.dir, out.dir) - 1) < 1e-6, "unit direction");
    TB_EQ_INT(out.bounce, 2);
    TB_EQ_INT(out.pixel, 42);
    TB_CHECK(out.tmin == 0 && out.tmax == RT_RAY_TMAX, "tmin/tmax");
    /* Far from the origin the offset is RT_BOUNCE_OFFSET_ULPS ulps. */
    rt_vec3 p = rt_offset_ray_origin((rt_vec3){1000, 1000, 1000}, (rt_vec3){0, 0, 1});
    TB_CHECK(p.x == 1000 && p.y == 1000 && p.z > 1000 && p.z == nextafterf(1000, 2000) + 255 * (nextafterf(1000, 2000) - 1000),
             "ulp offset: %.9g", (double)p.z);
    rt_hit miss = {RT_RAY_TMAX, 0, 0, RT_NO_HIT};
    TB_CHECK(!rt_bounce_ray(&plane, &up, &miss, 1, 4, &out), "miss ends the path");
    rt_ray last = up;
    last.bounce = 4;
    TB_CHECK(!rt_bounce_ray(&plane, &last, &hit, 1, 4, &out), "bounce 4 is the last (at most 4 bounces)");
    last.bounce = 3;
    TB_CHECK(rt_bounce_ray(&plane, &last, &hit, 1, 4, &out) && out.bounce == 4, "bounce 3 -> 4");
    tb_end();

    tb_begin("bounce_independent_of_processing_order");
    enum { P = 64 };
    rt_ray fwd[P], rev[P];
    memset(fwd, 0, sizeof fwd);   /* padding bytes compare equal too */
    memset(rev, 0, sizeof rev);
    for (int pass = 0; pass < 2; pass++)
        for (int k = 0; k < P; k++) {
            uint32_t i = pass ? (uint32_t)(P - 1 - k) : (uint32_t)k;
            rt_ray in = {{0, 0, 3}, {0.1f, 0, -1}, 0, RT_RAY_TMAX, i * 977u, (uint8_t)(i % 4), 0};
            rt_hit h = {3, 0, 0, 0};
            rt_bounce_ray(&plane, &in, &h, 5, 4, pass ? &rev[i] : &fwd[i]);
        }
    TB_CHECK(memcmp(fwd, rev, sizeof fwd) == 0, "forward and reverse order give the same rays");
    rt_ray in = {{0, 0, 3}, {0.1f, 0, -1}, 0, RT_RAY_TMAX, 7, 0, 0};
    rt_hit h = {3, 0, 0, 0};
    rt_ray s1, s2;
    rt_bounce_ray(&plane, &in, &h, 5, 4, &s1);
    rt_bounce_ray(&plane, &in, &h, 6, 4, &s2);
    TB_CHECK(memcmp(&s1.dir, &s2.dir, sizeof s1.dir) != 0, "seed changes the direction");
    tb_end();
}

/* Closest hit by brute force in float (Moeller-Trumbore, as a float
 * traversal would compute it), t > tmin: test-only. */
static rt_hit closest(const rt_mesh *m, const rt_ray *r)
{
    rt_hit h = {r->tmax, 0, 0, RT_NO_HIT};
    for (uint32_t t = 0; t < m->ntris; t++) {
        const rt_vec3 *a = &m->verts[m->tris[3 * t]], *b = &m->verts[m->tris[3 * t + 1]],
                      *c = &m->verts[m->tris[3 * t + 2]];
        float e1[3] = {b->x - a->x, b->y - a->y, b->z - a->z}, e2[3] = {c->x - a->x, c->y - a->y, c->z - a->z};
        float d[3] = {r->dir.x, r->dir.y, r->dir.z};
        float p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
        float det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
        if (det == 0)
            continue;
        float inv = 1.0f / det;
        float sv[3] = {r->org.x - a->x, r->org.y - a->y, r->org.z - a->z};
        float u = (sv[0] * p[0] + sv[1] * p[1] + sv[2] * p[2]) * inv;
        if (u < 0 || u > 1)
            continue;
        float q[3] = {sv[1] * e1[2] - sv[2] * e1[1], sv[2] * e1[0] - sv[0] * e1[2], sv[0] * e1[1] - sv[1] * e1[0]};
        float v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inv;
        if (v < 0 || u + v > 1)
            continue;
        float tt = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv;
        if (tt > r->tmin && tt < h.t)
            h.t = tt, h.u = u, h.v = v, h.prim = t;
    }
    return h;
}

/* The offset of bounce.h keeps bounce rays (tmin = 0) from re-hitting the
 * triangle they leave, on every built-in scene and its default view. */
static void test_no_self_hits(void)
{
    tb_begin("bounce_no_self_hits_on_builtin_scenes");
    for (unsigned i = 0; i < rt_builtin_count(); i++) {
        rt_mesh m;
        rt_views vs;
        char err[256] = "";
        if (!TB_CHECK(rt_builtin_generate(rt_builtin_name(i), &m, &vs, err, sizeof err), "%s", err))
            continue;
        rt_camera cam;
        uint32_t w = tb_is_sanitized() ? 12 : 24, h = w * 9 / 16, bounces = 0, self = 0;
        rt_camera_init(&cam, &vs.v[0], w, h, err, sizeof err);
        for (uint32_t py = 0; py < h; py++)
            for (uint32_t px = 0; px < w; px++) {
                rt_ray r = rt_camera_primary_ray(&cam, px, py), next;
                rt_hit hit = closest(&m, &r);
                while (rt_bounce_ray(&m, &r, &hit, 3, 2, &next)) {
                    rt_hit nh = closest(&m, &next);
                    bounces++;
                    self += nh.prim == hit.prim;   /* a plane cannot be re-hit */
                    r = next, hit = nh;
                }
            }
        TB_CHECK(bounces > w * h / 4, "%s: only %u bounce rays", rt_builtin_name(i), bounces);
        TB_CHECK(self == 0, "%s: %u of %u bounce rays hit their own triangle", rt_builtin_name(i), self, bounces);
        rt_mesh_free(&m);
        rt_views_free(&vs);
    }
    tb_end();
}

static void test_shade(void)
{
    tb_begin("shade_headlight_sky_and_path_accumulation");
    rt_ray r = {{0, 0, 5}, {0, 0, -2}, 0, RT_RAY_TMAX, 0, 0, 0};
    rt_hit hit = {2.5f, 0, 0, 0}, miss = {RT_RAY_TMAX, 0, 0, RT_NO_HIT};
    rt_vec3 c = rt_shade_headlight(&plane, &r, &hit);
    TB_CHECK(fabsf(c.x - RT_SHADE_ALBEDO) < 1e-6f && c.x == c.y && c.y == c.z, "head-on grey %g", (double)c.x);
    rt_vec3 sky = rt_shade_headlight(&plane, &r, &miss), s2 = rt_shade_sky(r.dir);
    TB_CHECK(memcmp(&sky, &s2, sizeof sky) == 0 && sky.z > sky.x, "miss = sky (bluish)");
    rt_path p;
    rt_path_init(&p);
    rt_path_add(&p, &r, &hit);
    rt_path_add(&p, &r, &hit);
    rt_path_add(&p, &r, &miss);
    float k = RT_SHADE_ALBEDO * RT_SHADE_ALBEDO;
    TB_CHECK(fabsf(p.radiance.x - k * s2.x) < 1e-6f && fabsf(p.radiance.z - k * s2.z) < 1e-6f,
             "two bounces then sky: albedo^2 * sky");
    tb_end();
}

int main(void)
{
    test_rng();
    test_det_math();
    test_camera();
    test_bounce();
    test_no_self_hits();
    test_shade();
    return tb_finish();
}
