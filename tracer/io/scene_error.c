/* scene_error.c — see scene_error.h. */
#include "tracer/io/scene_error.h"

#include <stdarg.h>
#include <stdio.h>

void rt_scene_errorf(char *err, size_t errlen, const char *fmt, ...)
{
    if (!err || errlen == 0)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}
