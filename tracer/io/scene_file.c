/* scene_file.c — see scene_file.h. */
#include "tracer/io/scene_file.h"

#include <ctype.h>
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "tracer/io/scene_error.h"

/* Plain files: one allocation of the file's size and one read. The file is
 * opened once (fd), so a FIFO is read once too; NULL with *plain = false when
 * the file is gzip data (magic 1f 8b, RFC 1952) or not a regular file (a
 * stream), and the caller reads it with the gz reader from offset 0. */
static unsigned char *read_plain(int fd, const struct stat *st, const char *path, const char *what, size_t max,
                                 size_t *len, bool *plain, char *err, size_t errlen)
{
    *plain = false;
    unsigned char magic[2] = {0, 0};
    if (!S_ISREG(st->st_mode) || (pread(fd, magic, 2, 0) == 2 && magic[0] == 0x1f && magic[1] == 0x8b))
        return NULL;
    *plain = true;
    /* the size is known: a file larger than the bound is refused unread */
    if ((uint64_t)st->st_size > (uint64_t)max) {
        rt_scene_errorf(err, errlen, "%s: %llu bytes, more than the %zu MiB a %s may hold", path,
                        (unsigned long long)st->st_size, max >> 20, what);
        return NULL;
    }
    size_t n = (size_t)st->st_size;
    unsigned char *buf = malloc(n + 1);
    if (!buf) {
        rt_scene_errorf(err, errlen, "%s: out of memory reading %zu bytes", path, n);
        return NULL;
    }
    size_t got = 0;
    int e = 0;
    while (got < n) {
        ssize_t k = pread(fd, buf + got, n - got, (off_t)got);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0) {
            e = k < 0 ? errno : 0;
            break;
        }
        got += (size_t)k;
    }
    if (got != n) {
        free(buf);
        rt_scene_errorf(err, errlen, "%s: read error after %zu of %zu bytes: %s", path, got, n,
                        !e ? "file changed while reading" : strerror(e));
        return NULL;
    }
    buf[n] = 0;
    *len = n;
    return buf;
}

unsigned char *rt_read_file_gz(const char *path, const char *what, size_t max, size_t *len, char *err,
                               size_t errlen)
{
    *len = 0;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        rt_scene_errorf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return NULL;
    }
    struct stat st;
    if (fstat(fd, &st) != 0) {
        rt_scene_errorf(err, errlen, "%s: cannot read: %s", path, strerror(errno));
        close(fd);
        return NULL;
    }
    /* a folder opens like a file on Linux; reading it fails with EISDIR */
    if (S_ISDIR(st.st_mode)) {
        rt_scene_errorf(err, errlen, "%s: is a folder, not a %s", path, what);
        close(fd);
        return NULL;
    }
    bool plain;
    unsigned char *pb = read_plain(fd, &st, path, what, max, len, &plain, err, errlen);
    if (plain) {
        close(fd);
        return pb;
    }
    errno = 0;
    /* Capacity hint (regular files only): a gzip member ends with ISIZE, the
     * uncompressed size mod 2^32 (RFC 1952, section 2.3.1); it saves the
     * doubling copies. */
    size_t hint = 1u << 20;
    if (S_ISREG(st.st_mode) && st.st_size >= 4) {
        unsigned char t[4];
        uint64_t csize = (uint64_t)st.st_size;
        if (pread(fd, t, 4, (off_t)(csize - 4)) == 4) {
            size_t isize = (size_t)t[0] | (size_t)t[1] << 8 | (size_t)t[2] << 16 | (size_t)t[3] << 24;
            /* Trust it only up to deflate's maximum ratio of about 1032:1
             * (zlib technical details, zlib.net/zlib_tech.html) and the
             * bound: a corrupt trailer must not cause a huge allocation. */
            if (isize > hint && isize < ((size_t)1 << 32) - (1u << 21) && isize <= max &&
                (uint64_t)isize <= csize * 1032u)
                hint = isize + (1u << 20);   /* + room so the final read sees EOF */
        }
    }
    /* gzdopen reads from the current offset (0: pread moved nothing) and
     * passes data that is not gzip through unchanged */
    gzFile f = gzdopen(fd, "rb");
    if (!f) {
        close(fd);
        rt_scene_errorf(err, errlen, "%s: cannot open: out of memory", path);
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
        /* a stream (pipe, FIFO, /dev/zero) or a gzip bomb: bounded here */
        if (n > max) {
            rt_scene_errorf(err, errlen, "%s: more than the %zu MiB a %s may hold%s", path, max >> 20, what,
                            S_ISREG(st.st_mode) ? ", uncompressed" : " (an endless stream?)");
            goto fail;
        }
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
            /* zlib prefixes its message with the path it was given, for
             * gzdopen "<fd:N>" */
            const char *colon = strstr(msg, ": ");
            if (msg[0] == '<' && colon)
                msg = colon + 2;
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
