/* fuzz_ply.c — PLY meshes, ASCII and binary (tracer/io/ply_load.h). */
#include "testbench/fuzz/fuzz.h"
#include "testbench/fuzz/fuzz_check.h"
#include "tracer/io/ply_load.h"

const char fuzz_name[] = "fuzz_ply";

int fuzz_one(const char *path, const unsigned char *data, size_t len)
{
    rt_mesh m;
    char err[512] = "";
    if (!rt_ply_parse(data, len, path, &m, err, sizeof err))
        return fuzz_rejected(fuzz_name, err);
    rt_mesh_free(&m);
    return 1;
}
