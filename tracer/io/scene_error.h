/* scene_error.h — how tracer I/O functions report bad input.
 *
 * Contract: every loader/parser takes (char *err, size_t errlen); on failure it
 * returns false (or NULL) and writes one line "FILE:LINE: what is wrong; what is
 * allowed" (binary data: "FILE: byte N (element E): ...") into err, truncated
 * to errlen. err may be NULL or errlen 0 (the message is then dropped). */
#ifndef RTSIM_TRACER_SCENE_ERROR_H
#define RTSIM_TRACER_SCENE_ERROR_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* printf-style write of a message into err (always NUL-terminated). */
void rt_scene_errorf(char *err, size_t errlen, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

#ifdef __cplusplus
}
#endif

#endif
