/* fuzz_dram_trace.c — rtdram request traces (model/dram/dram_trace.h) replayed
 * through the LPDDR3 controller of model/data/lpddr3_1600.ini. */
#include <stdio.h>

#include "model/dram/dram_ctrl.h"
#include "model/dram/dram_timing.h"
#include "model/dram/dram_trace.h"
#include "testbench/fuzz/fuzz.h"
#include "testbench/fuzz/fuzz_check.h"

const char fuzz_name[] = "fuzz_dram_trace";

int fuzz_one(const char *path, const unsigned char *data, size_t len)
{
    (void)data;
    (void)len;
    dram_spec spec;
    char err[512] = "";
    if (dram_spec_load(&spec, "model/data/lpddr3_1600.ini", NULL, 0, err, sizeof err)) {
        fprintf(stderr, "%s: run from the repository root: %s\n", fuzz_name, err);
        abort();
    }
    dram_ctrl *c = dram_ctrl_create(&spec, NULL, NULL, err, sizeof err);
    FILE *f = fopen(path, "r");
    if (!c || !f) {
        fprintf(stderr, "%s: setup failed\n", fuzz_name);
        abort();
    }
    dram_trace_result res;
    int rc = dram_trace_run(c, f, path, &res, err, sizeof err);
    fclose(f);
    dram_ctrl_destroy(c);
    return rc == 0 ? 1 : fuzz_rejected(fuzz_name, err);
}
