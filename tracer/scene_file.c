/* scene_file.c — see scene_file.h. */
#include "tracer/scene_file.h"

#include <ctype.h>
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

#include "tracer/scene_error.h"

/* Plain files: one allocation of the file's size and one fread. NULL with
 * *plain = false when the file is gzip data (magic 1f 8b, RFC 1952) or
 * cannot be sized, so the caller falls back to the gz reader. */
static unsigned char *read_plain(const char *path, size_t *len, bool *plain, char *err, size_t errlen)
{
    *plain = false;
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    unsigned char magic[2] = {0, 0};
    size_t nm = fread(magic, 1, 2, f);
    struct stat st;
    if ((nm == 2 && magic[0] == 0x1f && magic[1] == 0x8b) || fstat(fileno(f), &st) != 0 ||
        !S_ISREG(st.st_mode) || (uint64_t)st.st_size >= SIZE_MAX) {
        fclose(f);
        return NULL;
    }
    *plain = true;
    size_t n = (size_t)st.st_size;
    unsigned char *buf = malloc(n + 1);
    if (!buf) {
        fclose(f);
        rt_scene_errorf(err, errlen, "%s: out of memory reading %zu bytes", path, n);
        return NULL;
    }
    rewind(f);
    size_t got = fread(buf, 1, n, f);
    bool bad = ferror(f) || got != n;
    int e = errno;
    fclose(f);
    if (bad) {
        free(buf);
        rt_scene_errorf(err, errlen, "%s: read error after %zu of %zu bytes: %s", path, got, n,
                        got != n && !e ? "file changed while reading" : strerror(e));
        return NULL;
    }
    buf[n] = 0;
    *len = n;
    return buf;
}

unsigned char *rt_read_file_gz(const char *path, size_t *len, char *err, size_t errlen)
{
    *len = 0;
    bool plain;
    unsigned char *pb = read_plain(path, len, &plain, err, errlen);
    if (plain)
        return pb;
    errno = 0;
    /* Capacity hint: a gzip member ends with ISIZE, the uncompressed size
     * mod 2^32 (RFC 1952, section 2.3.1); it saves the doubling copies. */
    size_t hint = 1u << 20;
    FILE *raw = fopen(path, "rb");
    if (raw) {
        unsigned char t[4];
        long csize = fseek(raw, 0, SEEK_END) == 0 ? ftell(raw) : -1;
        if (csize >= 4 && fseek(raw, -4, SEEK_END) == 0 && fread(t, 1, 4, raw) == 4) {
            size_t isize = (size_t)t[0] | (size_t)t[1] << 8 | (size_t)t[2] << 16 | (size_t)t[3] << 24;
            /* Trust it only up to deflate's maximum ratio of about 1032:1
             * (zlib technical details, zlib.net/zlib_tech.html): a corrupt
             * trailer must not cause a huge allocation. */
            if (isize > hint && isize < ((size_t)1 << 32) - (1u << 21) &&
                (uint64_t)isize <= (uint64_t)csize * 1032u)
                hint = isize + (1u << 20);   /* + room so the final read sees EOF */
        }
        fclose(raw);
    }
    gzFile f = gzopen(path, "rb");
    if (!f) {
        rt_scene_errorf(err, errlen, "%s: cannot open: %s", path,
                        errno ? strerror(errno) : "out of memory");
        return NULL;
    }
    gzbuffer(f, 1u << 18);   /* 256 KiB: fewer read() calls on big scenes */
    size_t cap = hint, n = 0;
    unsigned char *buf = malloc(cap + 1);
    if (!buf && cap > (1u << 20)) {   /* the hint was too optimistic: grow instead */
        cap = 1u << 20;
        buf = malloc(cap + 1);
    }
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
        if (got <= 0)
            break;
        n += (size_t)got;
    }
    {
        int code;
        const char *msg = gzerror(f, &code);
        if (code == Z_ERRNO) {
            rt_scene_errorf(err, errlen, "%s: read error: %s", path, strerror(errno));
            goto fail;
        }
        if (code != Z_OK) {
            size_t pl = strlen(path);   /* zlib prefixes its message with the path */
            if (strncmp(msg, path, pl) == 0 && msg[pl] == ':' && msg[pl + 1] == ' ')
                msg += pl + 2;
            /* zlib reports a cut-off stream as Z_BUF_ERROR "unexpected end of
             * file", a bad trailer as Z_DATA_ERROR "incorrect length check". */
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
