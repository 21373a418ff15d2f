/* fuzz_obj.c — OBJ meshes (tracer/io/obj_load.h), as rtsim reads SCENE.obj. */
#include "testbench/fuzz/fuzz.h"
#include "testbench/fuzz/fuzz_check.h"
#include "tracer/io/obj_load.h"

const char fuzz_name[] = "fuzz_obj";

int fuzz_one(const char *path, const unsigned char *data, size_t len)
{
    rt_mesh m;
    char err[512] = "";
    if (!rt_obj_parse((const char *)data, len, path, &m, err, sizeof err))
        return fuzz_rejected(fuzz_name, err);
    rt_mesh_free(&m);
    return 1;
}
