/* tb.h — the tiny test protocol every testbench program speaks.
 *
 * A testbench program runs cases; each case prints exactly one line:
 *   PASS <case>            all its checks held
 *   FAIL <case>: <why>     at least one check failed (first failure shown)
 *   SKIP <case>: <why>     could not run here (e.g. ../shared/scenes absent)
 * testbench/run.sh counts these lines over all programs; a program that exits
 * non-zero without printing a FAIL (a crash, a sanitizer report) counts as one
 * failure. Header-only so every testbench is a single .c file. */
#ifndef RTSIM_TB_H
#define RTSIM_TB_H

#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *tb_case_name;
static int tb_case_failed;   /* checks failed in the current case */
static int tb_cases_failed;  /* cases failed in this program */

static inline void tb_begin(const char *name)
{
    tb_case_name = name;
    tb_case_failed = 0;
}

/* Records a failed check; the first one of a case is shown on its FAIL line,
 * later ones on stderr so the cause stays on one line. */
static inline bool tb_check_at(bool ok, const char *file, int line, const char *fmt, ...)
{
    if (ok)
        return true;
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (tb_case_failed++ == 0)
        printf("FAIL %s: %s:%d: %s\n", tb_case_name, file, line, msg);
    else
        fprintf(stderr, "  also %s:%d: %s\n", file, line, msg);
    fflush(stdout);
    return false;
}
#define TB_CHECK(cond, ...) tb_check_at((cond), __FILE__, __LINE__, __VA_ARGS__)
/* Evaluates each operand exactly once (they may be calls with side effects). */
static inline bool tb_eq_int_at(long long a, long long b, const char *as, const char *bs, const char *file, int line)
{
    return tb_check_at(a == b, file, line, "%s == %s: %lld != %lld", as, bs, a, b);
}
#define TB_EQ_INT(a, b) tb_eq_int_at((long long)(a), (long long)(b), #a, #b, __FILE__, __LINE__)

static inline void tb_end(void)
{
    if (tb_case_failed == 0)
        printf("PASS %s\n", tb_case_name);
    else
        tb_cases_failed++;
    fflush(stdout);
}

static inline void tb_skip(const char *name, const char *why)
{
    printf("SKIP %s: %s\n", name, why);
    fflush(stdout);
}

/* Exit status of the program: 0 when every case passed. */
static inline int tb_finish(void) { return tb_cases_failed ? 1 : 0; }

/* Reads a whole file into a NUL-terminated buffer (free() it); *len (may
 * be NULL) gets the byte count. NULL when the file cannot be opened. */
static inline char *tb_read_file(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *b = malloc(n > 0 ? (size_t)n + 1 : 1);
    size_t got = n > 0 ? fread(b, 1, (size_t)n, f) : 0;
    b[got] = 0;
    fclose(f);
    if (len)
        *len = got;
    return b;
}

/* Paths. The scratch folder (RTSIM_TMP) may sit anywhere, under a long path
 * with spaces (run.sh puts it under one): a path buffer of a testbench is
 * TB_PATH_MAX bytes, the longest path Linux takes, and tb_pathf formats into
 * it or ends the program with a FAIL naming the path. A path cut to a buffer
 * would name another file, and every later case would fail on it. */
#define TB_PATH_MAX 4096
/* A message buffer for errors that name a scratch file: the whole path and
 * the reason (a shorter buffer cuts the reason a check looks for). */
#define TB_ERR_MAX (TB_PATH_MAX + 1024)
static inline const char *tb_pathf(char *buf, size_t size, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(buf, size, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= size) {
        printf("FAIL %s: path longer than %zu bytes: %s...\n", tb_case_name ? tb_case_name : "tb_path", size - 1,
               buf);
        fflush(stdout);
        exit(1);
    }
    return buf;
}

/* system(cmd) on up to two paths of any name (quotes, backslashes, spaces:
 * /home/o'brien): they reach the shell as "$TB_ARG1" and "$TB_ARG2", set in
 * the environment, never pasted into the command's text. */
static inline int tb_system_args(const char *cmd, const char *arg1, const char *arg2)
{
    setenv("TB_ARG1", arg1 ? arg1 : "", 1);
    setenv("TB_ARG2", arg2 ? arg2 : "", 1);
    return system(cmd);
}

/* Set by run.sh for the sanitizer build: heavy cases may shrink their inputs. */
static inline bool tb_is_sanitized(void) { return getenv("RTSIM_TB_SANITIZED") != NULL; }

#endif
