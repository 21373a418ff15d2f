/* fuzz_main.c — driver of a fuzz harness (fuzz.h): runs fuzz_one on each
 * file given, printing "accepted"/"rejected" per file with -v; exit 0 unless
 * a file cannot be read (2). Built by AFL++'s afl-cc it instead runs in
 * persistent mode: the fuzzer hands over inputs through shared memory, and
 * each is also written to one scratch file for the parsers that take a
 * path (thousands of inputs per process instead of one fork each). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "testbench/fuzz/fuzz.h"

#ifdef __AFL_FUZZ_TESTCASE_LEN
__AFL_FUZZ_INIT();

int main(void)
{
    /* One scratch file for the whole run, made before the fork server starts
     * and unlinked at once: every forked child reaches it as /proc/self/fd/N
     * (a child that crashes leaves nothing behind). */
    char tmpl[] = "/tmp/rtsim-fuzz-XXXXXX", path[64];
    int fd = mkstemp(tmpl);
    if (fd < 0) {
        perror("fuzz: mkstemp");
        return 2;
    }
    unlink(tmpl);
    snprintf(path, sizeof path, "/proc/self/fd/%d", fd);
    __AFL_INIT();
    const unsigned char *shm = __AFL_FUZZ_TESTCASE_BUF;
    while (__AFL_LOOP(10000)) {
        const size_t len = (size_t)__AFL_FUZZ_TESTCASE_LEN;
        unsigned char *data = malloc(len + 1);
        if (!data || ftruncate(fd, 0) || pwrite(fd, shm, len, 0) != (ssize_t)len) {
            perror("fuzz: scratch file");
            return 2;
        }
        memcpy(data, shm, len);
        data[len] = 0;
        fuzz_one(path, data, len);
        free(data);
    }
    close(fd);
    return 0;
}
#else
static unsigned char *read_all(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 4096, n = 0;
    unsigned char *buf = malloc(cap + 1);
    for (size_t got; buf && (got = fread(buf + n, 1, cap - n, f)) > 0;) {
        n += got;
        if (n == cap) {
            unsigned char *nb = realloc(buf, 2 * cap + 1);
            if (!nb) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = nb;
            cap *= 2;
        }
    }
    int bad = ferror(f);
    fclose(f);
    if (!buf || bad) {
        free(buf);
        return NULL;
    }
    buf[n] = 0;
    *len = n;
    return buf;
}

int main(int argc, char **argv)
{
    int verbose = argc > 1 && strcmp(argv[1], "-v") == 0;
    if (argc < 2 + verbose) {
        fprintf(stderr, "usage: %s [-v] FILE...\n", argv[0]);
        return 2;
    }
    for (int i = 1 + verbose; i < argc; i++) {
        size_t len = 0;
        unsigned char *data = read_all(argv[i], &len);
        if (!data) {
            fprintf(stderr, "%s: cannot read %s\n", fuzz_name, argv[i]);
            return 2;
        }
        int ok = fuzz_one(argv[i], data, len);
        if (verbose)
            printf("%s %s\n", ok ? "accepted" : "rejected", argv[i]);
        free(data);
    }
    return 0;
}
#endif
