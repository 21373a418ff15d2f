/* tb_tracer_io_real.c — the real scenes of ../shared/scenes load with the
 * vertex and triangle counts stated in their SOURCE.txt, and their views.txt
 * is picked up. Skips when the folder is absent; the scenes above 500K
 * triangles run only in the release build (RTSIM_TB_SANITIZED unset).
 * The folder is $RTSIM_SCENES, else ../shared/scenes from the repository
 * root, else ../../shared/scenes (a git worktree under <root>/wt/). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "testbench/tb.h"
#include "testbench/tracer/tb_tracer_util.h"
#include "tracer/io/scene.h"


/* Reads "<key> N,NNN" from SOURCE.txt (first occurrence at a line start,
 * after optional spaces); -1 when absent. */
static long long source_count(const char *dir, const char *key)
{
    char path[TB_PATH_MAX], line[512];
    tb_pathf(path, sizeof path, "%s/SOURCE.txt", dir);
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    long long v = -1;
    while (v < 0 && fgets(line, sizeof line, f)) {
        char *p = line;
        while (*p == ' ')
            p++;
        if (strncmp(p, key, strlen(key)) != 0)
            continue;
        p += strlen(key);
        v = 0;
        for (; *p && *p != '\n' && *p != '('; p++)
            if (*p >= '0' && *p <= '9')
                v = v * 10 + (*p - '0');
    }
    fclose(f);
    return v;
}

static void one(const char *root, const char *folder, const char *file, bool big)
{
    char name[128];
    snprintf(name, sizeof name, "real_scene_%s_counts_match_source", folder);
    if (!root) {
        tb_skip(name, "../shared/scenes absent (set RTSIM_SCENES)");
        return;
    }
    if (big && tb_is_sanitized()) {
        tb_skip(name, "large scene: release build only");
        return;
    }
    char dir[TB_PATH_MAX], path[TB_PATH_MAX];
    tb_pathf(dir, sizeof dir, "%s/%s", root, folder);
    tb_pathf(path, sizeof path, "%s/%s", dir, file);
    if (access(path, R_OK) != 0) {
        tb_skip(name, "scene file absent");
        return;
    }
    tb_begin(name);
    long long want_v = source_count(dir, "Vertices:"), want_t = source_count(dir, "Triangles:");
    rt_scene s;
    char err[TB_ERR_MAX] = "";
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    bool ok = rt_scene_load(path, &s, err, sizeof err);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    if (TB_CHECK(ok, "load failed: %s", err)) {
        fprintf(stderr, "%s: %u vertices, %u triangles in %.2f s\n", folder, s.mesh.nverts,
                s.mesh.ntris, (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec));
        TB_CHECK(want_t > 0 && want_v > 0, "SOURCE.txt lacks 'Vertices:'/'Triangles:' lines");
        TB_EQ_INT(s.mesh.ntris, want_t);
        TB_EQ_INT(s.mesh.nverts, want_v);
        TB_EQ_INT(s.views.n, 2);
        uint32_t bad = 0;
        for (uint64_t i = 0; i < 3ull * s.mesh.ntris; i++)
            bad += s.mesh.tris[i] >= s.mesh.nverts;
        TB_EQ_INT(bad, 0);
        rt_scene_free(&s);
    }
    tb_end();
}

/* scenes/shared-*.scene point at ../../shared/scenes relative to themselves,
 * which resolves from a checkout whose parent holds shared/ (not from a
 * worktree one level deeper: then this case skips). */
static void scene_file(const char *file, const char *folder, uint32_t views)
{
    char name[128], path[TB_PATH_MAX];
    snprintf(name, sizeof name, "real_scene_file_%s_loads", file);
    snprintf(path, sizeof path, "../shared/scenes/%s", folder);
    if (access(path, R_OK) != 0) {
        tb_skip(name, "../shared/scenes not beside the repository");
        return;
    }
    tb_begin(name);
    snprintf(path, sizeof path, "scenes/%s", file);
    rt_scene s;
    char err[TB_ERR_MAX] = "";
    bool ok = rt_scene_load(path, &s, err, sizeof err);
    TB_CHECK(ok && s.views.n == views, "%s (views %u, expected %u)", err, ok ? s.views.n : 0u, views);
    if (ok)
        rt_scene_free(&s);
    tb_end();
}

int main(void)
{
    scene_file("shared-bunny.scene", "bunny/stanford-bunny.obj.gz", 2);
    scene_file("shared-sponza.scene", "sponza-ravenbridge/stk_ravenbridge_mansion.ply.gz", 2);
    scene_file("paper-crytek-sponza.scene", "paper-crytek-sponza/crytek_sponza.ply.gz", 1);
    const char *root = tbt_scenes_dir();
    one(root, "bunny", "stanford-bunny.obj.gz", false);
    one(root, "sponza-ravenbridge", "stk_ravenbridge_mansion.ply.gz", false);
    one(root, "rungholt-candela", "stk_candela_city.ply.gz", false);
    one(root, "fairy-blackforest", "stk_black_forest.ply.gz", true);
    one(root, "hairball-furball", "furBall_A_tubes3.ply.gz", true);
    return tb_finish();
}
