/* tb_config_ini_file.c — the shared INI reader (config/ini_file.h): keys reach
 * the handler in file order with their lines; every file error names
 * file:line and what is wrong (syntax, over-long line, key outside a section,
 * key given twice, unexpected section, the handler's own), the error of the
 * lowest line wins, and the handler is not called after an error. */
#include "config/ini_file.h"
#include "testbench/tb.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char tmpdir[TB_PATH_MAX];

static const char *tmp_file(const char *name, const char *text)
{
    static char path[TB_PATH_MAX];
    tb_pathf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *f = fopen(path, "w");
    fputs(text, f);
    fclose(f);
    return path;
}

static bool contains(const char *s, const char *sub) { return strstr(s, sub) != NULL; }
#define TB_HAS(msg, sub) TB_CHECK(contains((msg), (sub)), "message '%s' lacks '%s'", (msg), (sub))

/* Records "section.key=value@line;" per call; refuses the key "bad". */
typedef struct seen {
    char log[1024];
    int calls;
} seen;

static int record(ini_file *f, void *user, const char *section, const char *key, const char *value)
{
    seen *s = user;
    s->calls++;
    size_t n = strlen(s->log);
    snprintf(s->log + n, sizeof s->log - n, "%s.%s=%s@%d;", section, key, value, ini_file_line(f));
    if (strcmp(key, "bad") == 0)
        return ini_file_error(f, "key bad refused");
    return 0;
}

static const ini_file_opts any = {.what = "a test file", .example = "sec"};
static const ini_file_opts memspec_only = {.what = "a test file", .section = "memspec"};

/* Reads text as t.ini; returns the status, the message in err. */
static int read_text(const char *text, const ini_file_opts *o, seen *s, char *err, size_t errlen)
{
    memset(s, 0, sizeof *s);
    return ini_file_read(tmp_file("t.ini", text), o, record, s, err, errlen);
}

static void test_reads_in_order(void)
{
    tb_begin("ini_file_keys_in_order_with_lines");
    seen s;
    char err[TB_ERR_MAX];
    TB_EQ_INT(read_text("; comment\n[a]\nx = 1\n\n[b]\ny=two words ; note\n[a]\nz = 3\n", &any, &s, err, sizeof err), 0);
    TB_CHECK(strcmp(s.log, "a.x=1@3;b.y=two words@6;a.z=3@8;") == 0, "%s", s.log);
    tb_end();
}

static void test_file_errors(void)
{
    char err[TB_ERR_MAX];
    seen s;
    tb_begin("ini_file_cannot_open");
    char path[TB_PATH_MAX];
    tb_pathf(path, sizeof path, "%s/none.ini", tmpdir);
    TB_EQ_INT(ini_file_read(path, &any, record, &s, err, sizeof err), -1);
    TB_HAS(err, "none.ini: cannot open: No such file or directory");
    tb_end();

    tb_begin("ini_file_folder");
    tb_pathf(path, sizeof path, "%s/adir", tmpdir);
    mkdir(path, 0700);
    TB_EQ_INT(ini_file_read(path, &any, record, &s, err, sizeof err), -1);
    TB_HAS(err, "adir: is a folder, not a test file (.ini) file");
    rmdir(path);
    tb_end();

    static const struct {
        const char *name, *text, *want;
        const ini_file_opts *opts;
    } cases[] = {
        {"ini_file_syntax", "[a]\nx = 1\nno equals here\n", "t.ini:3: syntax error (expected [section], key = value", &any},
        {"ini_file_outside_section", "x = 1\n", "t.ini:1: key 'x' outside a [section] (write e.g. [sec] above it)", &any},
        {"ini_file_given_twice", "[a]\nx = 1\ny = 2\nx = 3\n", "t.ini:4: a.x given twice (first at line 2)", &any},
        {"ini_file_given_twice_across_headings", "[a]\nx = 1\n[b]\nx = 2\n[a]\nx = 3\n",
         "t.ini:6: a.x given twice (first at line 2)", &any},
        {"ini_file_only_section", "[memspec]\nx = 1\n[other]\ny = 2\n", "t.ini:4: unknown section [other] (expected [memspec])",
         &memspec_only},
        {"ini_file_outside_only_section", "x = 1\n", "t.ini:1: key 'x' outside a [section] (write e.g. [memspec] above it)",
         &memspec_only},
        {"ini_file_handler_error", "[a]\nx = 1\nbad = 2\n", "t.ini:3: key bad refused", &any},
        {"ini_file_syntax_before_handler_error", "[a]\nnonsense\nbad = 1\n", "t.ini:2: syntax error", &any},
        {"ini_file_handler_error_before_syntax", "[a]\nbad = 1\nnonsense\n", "t.ini:2: key bad refused", &any},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        tb_begin(cases[i].name);
        TB_EQ_INT(read_text(cases[i].text, cases[i].opts, &s, err, sizeof err), -1);
        TB_HAS(err, cases[i].want);
        tb_end();
    }

    tb_begin("ini_file_no_handler_after_error");
    TB_EQ_INT(read_text("[a]\nbad = 1\ny = 2\nz = 3\n", &any, &s, err, sizeof err), -1);
    TB_EQ_INT(s.calls, 1);
    tb_end();

    tb_begin("ini_file_line_too_long");
    char text[600];
    snprintf(text, sizeof text, "[a]\nx = 1\ny = %0300d\nz = 3\n", 0);
    TB_EQ_INT(read_text(text, &any, &s, err, sizeof err), -1);
    TB_HAS(err, "t.ini:3: line too long (at most 198 characters)");
    tb_end();
}

static int unknown_key(ini_file *f, void *user, const char *section, const char *key, const char *value)
{
    (void)user;
    (void)value;
    static const char *const keys[] = {"alpha", "beta"};
    return ini_file_key_index(f, section, key, keys, 2) < 0 ? -1 : 0;
}

static void test_helpers(void)
{
    char err[TB_ERR_MAX];
    tb_begin("ini_file_unknown_key_lists_allowed");
    TB_EQ_INT(ini_file_read(tmp_file("k.ini", "[s]\nalpha = 1\ngamma = 2\n"), &any, unknown_key, NULL, err, sizeof err),
              -1);
    TB_HAS(err, "k.ini:3: unknown key 'gamma' in [s] (allowed alpha, beta)");
    tb_end();

    tb_begin("ini_file_number");
    double v = 0;
    TB_CHECK(ini_file_number("1.5", &v) == 0 && v == 1.5, "1.5 -> %g", v);
    TB_CHECK(ini_file_number("-2e3", &v) == 0 && v == -2000, "-2e3 -> %g", v);
    static const char *const bad[] = {"", "abc", "1x", "1 2", "nan", "inf", "1e999"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        TB_CHECK(ini_file_number(bad[i], &v) == -1, "'%s' taken as a number", bad[i]);
    tb_end();
}

int main(void)
{
    const char *base = getenv("RTSIM_TMP");
    tb_pathf(tmpdir, sizeof tmpdir, "%s/tb_ini_XXXXXX", base && *base ? base : "/tmp");
    if (!mkdtemp(tmpdir)) {
        printf("FAIL setup: mkdtemp %s\n", tmpdir);
        return 1;
    }
    test_reads_in_order();
    test_file_errors();
    test_helpers();
    if (tb_system_args("rm -rf \"$TB_ARG1\"", tmpdir, NULL) != 0)
        printf("INFO could not remove %s\n", tmpdir);
    return tb_finish();
}
