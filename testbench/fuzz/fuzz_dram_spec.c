/* fuzz_dram_spec.c — DRAM standard files (model/dram/dram_timing.h): the INI that
 * rtdram --config and [memory] spec= name; a spec that loads is also turned
 * into a controller, which checks it against its own limits. */
#include "model/dram/dram_ctrl.h"
#include "model/dram/dram_timing.h"
#include "testbench/fuzz/fuzz.h"
#include "testbench/fuzz/fuzz_check.h"

const char fuzz_name[] = "fuzz_dram_spec";

int fuzz_one(const char *path, const unsigned char *data, size_t len)
{
    (void)data;
    (void)len;
    dram_spec spec;
    char err[512] = "";
    if (dram_spec_load(&spec, path, NULL, 0, err, sizeof err))
        return fuzz_rejected(fuzz_name, err);
    dram_ctrl *c = dram_ctrl_create(&spec, NULL, NULL, err, sizeof err);
    if (!c)
        return fuzz_rejected(fuzz_name, err);
    dram_ctrl_destroy(c);
    return 1;
}
