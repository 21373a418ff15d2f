/* tb_tracer_io_image.c — images through OpenImageIO: PNG and EXR round
 * trips, heatmap colours and metadata, errors leave no file behind. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "testbench/tb.h"
#include "tracer/io/image.h"

static char tmp[TB_PATH_MAX];

static const char *at(const char *rel)
{
    static char path[TB_PATH_MAX];
    tb_pathf(path, sizeof path, "%s/%s", tmp, rel);
    return path;
}

/* Number of directory entries whose name contains ".tmp" (leftovers). */
static int leftovers(void)
{
    DIR *d = opendir(tmp);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d)))
        n += strstr(e->d_name, ".tmp") != NULL;
    if (d)
        closedir(d);
    return n;
}

static void test_round_trip(void)
{
    enum { W = 7, H = 5 };
    float rgb[3 * W * H];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            float *p = rgb + 3 * (y * W + x);
            p[0] = (float)x / (W - 1), p[1] = (float)y / (H - 1), p[2] = 0.123f + 0.01f * (float)(x * y);
        }
    rgb[0] = -0.5f;   /* clamps to 0 in PNG, kept in EXR */
    rgb[1] = 2.0f;    /* clamps to 1 in PNG */
    char err[TB_ERR_MAX] = "";
    float *back;
    uint32_t w, h;

    tb_begin("image_png_round_trip_8bit");
    bool ok = rt_image_write_rgb(at("rt.png"), rgb, W, H, err, sizeof err);
    if (TB_CHECK(ok, "%s", err) && TB_CHECK(rt_image_read_rgb(at("rt.png"), &back, &w, &h, err, sizeof err), "%s", err)) {
        TB_CHECK(w == W && h == H, "size %ux%u", w, h);
        double maxerr = 0;
        for (int i = 3; i < 3 * W * H; i++)
            maxerr = fmax(maxerr, fabs(back[i] - rgb[i]));
        TB_CHECK(maxerr <= 0.5 / 255 + 1e-6, "max error %g > half a step of 8 bits", maxerr);
        TB_CHECK(back[0] == 0 && back[1] == 1, "out of range values clamp: %g %g", (double)back[0], (double)back[1]);
        /* pixel (0,0) is the top-left: the top row has y = 0 -> green 0 */
        TB_CHECK(back[3 * (W - 1) + 1] == 0 && back[3 * ((H - 1) * W) + 1] == 1, "row order");
        free(back);
    }
    tb_end();

    tb_begin("image_exr_round_trip_exact");
    ok = rt_image_write_rgb(at("rt.exr"), rgb, W, H, err, sizeof err);
    if (TB_CHECK(ok, "%s", err) && TB_CHECK(rt_image_read_rgb(at("rt.exr"), &back, &w, &h, err, sizeof err), "%s", err)) {
        TB_CHECK(w == W && h == H && memcmp(back, rgb, sizeof rgb) == 0, "EXR float data differs");
        free(back);
    }
    tb_end();
}

static void test_heatmap(void)
{
    enum { W = 9, H = 2 };
    float v[W * H];
    for (int i = 0; i < W * H; i++)
        v[i] = 10.0f + 10.0f * (float)(i % W) / (W - 1);   /* 10 .. 20 across */
    v[W] = NAN;
    char err[TB_ERR_MAX] = "", desc[256] = "";
    float *back;
    uint32_t w, h;

    tb_begin("heatmap_viridis_png_colours_and_range_metadata");
    bool ok = rt_image_write_heatmap(at("hm.png"), v, W, H, 10, 20, RT_COLORMAP_VIRIDIS, err, sizeof err);
    if (TB_CHECK(ok, "%s", err) && TB_CHECK(rt_image_read_rgb(at("hm.png"), &back, &w, &h, err, sizeof err), "%s", err)) {
        /* ends of viridis: #440154 and #fde725 */
        TB_CHECK(fabsf(back[0] - 0x44 / 255.0f) < 1e-3f && fabsf(back[2] - 0x54 / 255.0f) < 1e-3f, "low end colour");
        float *e = back + 3 * (W - 1);
        TB_CHECK(fabsf(e[0] - 0xfd / 255.0f) < 1e-3f && fabsf(e[1] - 0xe7 / 255.0f) < 1e-3f, "high end colour");
        float *n = back + 3 * W;
        TB_CHECK(n[0] == 1 && n[1] == 0 && n[2] == 1, "NaN is magenta");
        free(back);
        TB_CHECK(rt_image_read_description(at("hm.png"), desc, sizeof desc, err, sizeof err) &&
                     strstr(desc, "viridis") && strstr(desc, "range=[10, 20]"),
                 "description '%s'", desc);
    }
    tb_end();

    tb_begin("heatmap_exr_keeps_raw_values");
    ok = rt_image_write_heatmap(at("hm.exr"), v, W, H, 10, 20, RT_COLORMAP_GRAY, err, sizeof err);
    if (TB_CHECK(ok, "%s", err) && TB_CHECK(rt_image_read_rgb(at("hm.exr"), &back, &w, &h, err, sizeof err), "%s", err)) {
        TB_CHECK(back[0] == 0 && back[3 * (W - 1)] == 1 && fabsf(back[3 * 4] - 0.5f) < 1e-6f, "gray ramp");
        free(back);
    }
    float *raw;
    if (TB_CHECK(rt_image_read_channel(at("hm.exr"), "value", &raw, &w, &h, err, sizeof err), "%s", err)) {
        TB_CHECK(w == W && h == H && raw[3] == v[3] && raw[W - 1] == 20 && isnan(raw[W]), "raw values kept");
        free(raw);
    }
    TB_CHECK(!rt_image_read_channel(at("hm.exr"), "Z", &raw, &w, &h, err, sizeof err) && strstr(err, "R, G, B, value"),
             "missing channel: %s", err);
    float lo, hi;
    rt_image_value_range(v, W * H, &lo, &hi);
    TB_CHECK(lo == 10 && hi == 20, "range of values with a NaN: [%g, %g]", (double)lo, (double)hi);
    float nans[2] = {NAN, INFINITY};
    rt_image_value_range(nans, 2, &lo, &hi);
    TB_CHECK(lo == 0 && hi == 0, "no finite value -> [0, 0]");
    float rgb[3];
    rt_colormap_eval(RT_COLORMAP_GRAY, 5, 10, 20, rgb);
    TB_CHECK(rgb[0] == 0, "below range clamps");
    rt_colormap_eval(RT_COLORMAP_GRAY, 7, 7, 7, rgb);
    TB_CHECK(rgb[0] == 0, "empty range maps to 0");
    tb_end();
}

static void test_errors(void)
{
    float rgb[3 * 4] = {0};
    char err[TB_ERR_MAX] = "";
    tb_begin("image_error_unsupported_extension");
    bool ok = rt_image_write_rgb(at("x.bmpx"), rgb, 2, 2, err, sizeof err);
    TB_CHECK(!ok && strstr(err, "x.bmpx") && strstr(err, ".png or .exr"), "%s", err);
    TB_CHECK(access(at("x.bmpx"), F_OK) != 0, "file created");
    tb_end();

    tb_begin("image_error_missing_folder_leaves_nothing");
    ok = rt_image_write_rgb(at("nosuch/dir/x.png"), rgb, 2, 2, err, sizeof err);
    TB_CHECK(!ok && strstr(err, "nosuch/dir"), "%s", err);
    TB_EQ_INT(leftovers(), 0);
    tb_end();

    tb_begin("image_error_bad_size_and_range");
    ok = rt_image_write_rgb(at("z.png"), rgb, 0, 2, err, sizeof err);
    TB_CHECK(!ok && strstr(err, "0x2"), "%s", err);
    ok = rt_image_write_heatmap(at("z.png"), rgb, 2, 2, 5, 1, RT_COLORMAP_VIRIDIS, err, sizeof err);
    TB_CHECK(!ok && strstr(err, "lo <= hi"), "%s", err);
    TB_CHECK(access(at("z.png"), F_OK) != 0, "file created");
    float *none;
    uint32_t nw, nh;
    TB_CHECK(!rt_image_read_rgb(at("nosuch.png"), &none, &nw, &nh, err, sizeof err) && strstr(err, "nosuch.png"),
             "read error: %s", err);
    tb_end();

    tb_begin("image_overwrite_is_atomic_replace");
    float a[12] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
    ok = rt_image_write_rgb(at("atomic.png"), rgb, 2, 2, err, sizeof err) &&
         rt_image_write_rgb(at("atomic.png"), a, 2, 2, err, sizeof err);
    float *back;
    uint32_t w, h;
    if (TB_CHECK(ok, "%s", err) && TB_CHECK(rt_image_read_rgb(at("atomic.png"), &back, &w, &h, err, sizeof err), "%s", err)) {
        TB_CHECK(back[0] == 1 && back[11] == 1, "second write replaced the first");
        free(back);
    }
    TB_EQ_INT(leftovers(), 0);
    tb_end();
}

int main(void)
{
    const char *t = getenv("RTSIM_TMP");
    tb_pathf(tmp, sizeof tmp, "%s/tb_tracer_io_image", t && *t ? t : "/tmp");
    mkdir(tmp, 0777);
    test_round_trip();
    test_heatmap();
    test_errors();
    return tb_finish();
}
