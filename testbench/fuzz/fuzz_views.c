/* fuzz_views.c — views files (tracer/io/view.h), as --views FILE reads them. */
#include "testbench/fuzz/fuzz.h"
#include "testbench/fuzz/fuzz_check.h"
#include "tracer/io/view.h"

const char fuzz_name[] = "fuzz_views";

int fuzz_one(const char *path, const unsigned char *data, size_t len)
{
    (void)len; /* text up to the first NUL, as rt_views_load reads it */
    rt_views v;
    char err[512] = "";
    if (!rt_views_parse_text((const char *)data, path, &v, err, sizeof err))
        return fuzz_rejected(fuzz_name, err);
    rt_views_free(&v);
    return 1;
}
