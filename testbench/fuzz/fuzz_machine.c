/* fuzz_machine.c — machine INI files (config/config.h), as --machine FILE
 * reads them: load, finish, build the accelerator and run it on a 4x4
 * diffuse frame of a small mesh (a 3x3 grid of quads), so that every value a
 * file can reach is also exercised by the model. A run may fail (deadlock,
 * stack overflow), but only with a message. */
#include <stdio.h>
#include <string.h>

#include "frame/frame.h"
#include "model/accel_config.h"
#include "model/accel_top.h"
#include "config/config.h"
#include "model/mem/memsys_config.h"
#include "testbench/fuzz/fuzz.h"
#include "testbench/fuzz/fuzz_check.h"
#include "tracer/bvh/bvh.h"
#include "tracer/io/view.h"

const char fuzz_name[] = "fuzz_machine";

/* A wavy 3x3 grid of quads in z = 0 (18 triangles): several BVH levels. */
static void grid_mesh(rt_mesh *m, rt_vec3 *verts, uint32_t *tris)
{
    for (int y = 0; y < 4; y++)
        for (int x = 0; x < 4; x++)
            verts[y * 4 + x] = (rt_vec3){(float)x - 1.5f, (float)y - 1.5f, 0.25f * (float)((x + y) & 1)};
    uint32_t n = 0;
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 3; x++) {
            const uint32_t a = (uint32_t)(y * 4 + x), b = a + 1, c = a + 4, d = a + 5;
            uint32_t t[6] = {a, b, d, a, d, c};
            memcpy(tris + n, t, sizeof t);
            n += 6;
        }
    m->verts = verts;
    m->tris = tris;
    m->nverts = 16;
    m->ntris = 18;
}

static int run_machine(rtcfg *cfg, char *err, size_t errlen)
{
    rt_vec3 verts[16];
    uint32_t tris[54];
    rt_mesh mesh;
    grid_mesh(&mesh, verts, tris);
    rt_views views;
    if (!rt_views_parse_text("view v eye 0.3 0.2 4 at 0 0 0 up 0 1 0 fov 60\n", "fuzz_machine", &views, err,
                             errlen))
        return -1;
    rt_bvh_params bp;
    rt_bvh_params_default(&bp);
    bp.width = (int)rtcfg_int(cfg, "machine.branching");
    rt_bvh_image img;
    memset(&img, 0, sizeof img);
    int rc = -1;
    rtsim_frame frame;
    memset(&frame, 0, sizeof frame);
    accel_top *top = NULL;
    accel_source src;
    if (!rt_bvh_build(&mesh, &bp, &img, NULL, err, errlen))
        goto out;
    if (!rtsim_frame_init(&frame, cfg, &mesh, &views.v[0], 4, 4, true, 2, 1, false, &src, err, errlen))
        goto out;
    accel_image aimg = rtsim_image(&img);
    accel_top_opts o = {0};
    top = accel_top_create(cfg, &aimg, &src, &o, err, errlen);
    if (!top)
        goto out;
    rc = accel_top_run(top, NULL, NULL, err, errlen) == 0 ? 0 : -1;
out:
    accel_top_destroy(top);
    rtsim_frame_free(&frame);
    rt_bvh_image_free(&img);
    rt_views_free(&views);
    return rc;
}

int fuzz_one(const char *path, const unsigned char *data, size_t len)
{
    (void)data;
    (void)len;
    char err[1024] = "";
    rtcfg *cfg = rtcfg_create();
    if (!cfg || memsys_add_schemas(cfg, err, sizeof err) || accel_add_schemas(cfg, err, sizeof err)) {
        fprintf(stderr, "%s: setup failed: %s\n", fuzz_name, err);
        abort();
    }
    int ok = !rtcfg_load(cfg, path, err, sizeof err) && !rtcfg_finish(cfg, err, sizeof err) &&
             run_machine(cfg, err, sizeof err) == 0;
    rtcfg_destroy(cfg);
    return ok ? 1 : fuzz_rejected(fuzz_name, err);
}
