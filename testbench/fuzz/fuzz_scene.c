/* fuzz_scene.c — scene description files (tracer/io/scene.h), as rtsim SCENE.scene
 * reads them: the input is written to fuzz.scene in a scratch folder of its
 * own (the loader goes by the .scene suffix and resolves mesh and views paths
 * relative to the file), then loaded; a `mesh` line may name a built-in
 * scene, which is then built. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "testbench/fuzz/fuzz.h"
#include "testbench/fuzz/fuzz_check.h"
#include "tracer/io/scene.h"

const char fuzz_name[] = "fuzz_scene";

static char scratch_dir[] = "/tmp/rtsim-fuzz-scene-XXXXXX";
static char scene_path[sizeof scratch_dir + 16];

static void remove_scratch(void)
{
    unlink(scene_path);
    rmdir(scratch_dir);
}

int fuzz_one(const char *path, const unsigned char *data, size_t len)
{
    (void)path;
    if (!scene_path[0]) {
        if (!mkdtemp(scratch_dir)) {
            perror("fuzz_scene: mkdtemp");
            abort();
        }
        snprintf(scene_path, sizeof scene_path, "%s/fuzz.scene", scratch_dir);
        atexit(remove_scratch);
    }
    FILE *f = fopen(scene_path, "wb");
    if (!f || fwrite(data, 1, len, f) != len || fclose(f) != 0) {
        perror("fuzz_scene: scratch file");
        abort();
    }
    rt_scene s;
    char err[512] = "";
    if (!rt_scene_load(scene_path, &s, err, sizeof err))
        return fuzz_rejected(fuzz_name, err);
    rt_scene_free(&s);
    return 1;
}
