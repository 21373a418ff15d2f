/* scene_file.c — see scene_file.h. */
#include "tracer/scene_file.h"

#include <ctype.h>
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "tracer/scene_error.h"

unsigned char *rt_read_file_gz(const char *path, size_t *len, char *err, size_t errlen)
{
    *len = 0;
    gzFile f = gzopen(path, "rb");
    if (!f) {
        rt_scene_errorf(err, errlen, "%s: cannot open: %s", path,
                        errno ? strerror(errno) : "out of memory");
        return NULL;
    }
    gzbuffer(f, 1u << 18);   /* 256 KiB: fewer read() calls on big scenes */
    size_t cap = 1u << 20, n = 0;
    unsigned char *buf = malloc(cap + 1);
    if (!buf) {
        gzclose(f);
        rt_scene_errorf(err, errlen, "%s: out of memory", path);
        return NULL;
    }
    for (;;) {
        if (cap - n < (1u << 20)) {
            if (cap > SIZE_MAX / 4) {
                rt_scene_errorf(err, errlen, "%s: file too large", path);
                goto fail;
            }
            size_t ncap = cap * 2;
            unsigned char *nb = realloc(buf, ncap + 1);
            if (!nb) {
                rt_scene_errorf(err, errlen, "%s: out of memory reading %zu bytes", path, ncap);
                goto fail;
            }
            buf = nb;
            cap = ncap;
        }
        size_t want = cap - n;
        if (want > (1u << 30))
            want = 1u << 30;
        int got = gzread(f, buf + n, (unsigned)want);
        if (got < 0) {
            int code;
            const char *msg = gzerror(f, &code);
            rt_scene_errorf(err, errlen, "%s: read error: %s",
                            path, code == Z_ERRNO ? strerror(errno) : msg);
            goto fail;
        }
        if (got == 0)
            break;
        n += (size_t)got;
    }
    {
        int code;
        const char *msg = gzerror(f, &code);
        if (code != Z_OK) {
            /* zlib reports a cut-off gzip stream as Z_BUF_ERROR "unexpected end of file". */
            rt_scene_errorf(err, errlen, "%s: corrupt or truncated gzip data after %zu bytes: %s",
                            path, n, msg);
            goto fail;
        }
    }
    gzclose(f);
    buf[n] = 0;
    *len = n;
    return buf;
fail:
    gzclose(f);
    free(buf);
    return NULL;
}

bool rt_path_has_suffix(const char *path, const char *suffix)
{
    size_t n = strlen(path), m = strlen(suffix);
    if (m > n)
        return false;
    for (size_t i = 0; i < m; i++)
        if (tolower((unsigned char)path[n - m + i]) != tolower((unsigned char)suffix[i]))
            return false;
    return true;
}
