/* tb_cli_json — the one JSON string escaping (kernel/json.h) and the tools'
 * member writer on top of it (cli/json.h): quotes and backslashes escaped,
 * every control character as \u00XX (none dropped), other bytes (UTF-8) as
 * they are, NULL as null; members separated and keyed as the tools write
 * them, the first without a comma; the provenance writer's nulls. */
#include <stdlib.h>
#include <string.h>

#include "cli/json.h"
#include "cli/output_path.h"
#include "kernel/json.h"
#include "testbench/tb.h"

/* What f wrote, as a string (freed by the caller). */
static char *written(void (*write)(FILE *f, const void *arg), const void *arg)
{
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    if (!f)
        abort();
    write(f, arg);
    fclose(f);
    return text;
}

static void write_string(FILE *f, const void *arg) { ks_json_string(f, arg); }

static void write_members(FILE *f, const void *arg)
{
    cli_json j = {f, arg, true};
    fputc('{', f);
    cli_json_str(&j, "name", "a \"b\"");
    cli_json_uint(&j, "count", 18446744073709551615ULL);
    cli_json_real(&j, "ratio", 0.1);
    cli_json_str(&j, "none", NULL);
    fputs("}", f);
}

static void write_partial(FILE *f, const void *arg) { cli_json_put(f, "{\n  \"a\": 1\n}\n", arg); }

static void expect(void (*write)(FILE *f, const void *arg), const void *arg, const char *want)
{
    char *got = written(write, arg);
    TB_CHECK(!strcmp(got, want), "wrote [%s], expected [%s]", got, want);
    free(got);
}

int main(void)
{
    tb_begin("cli_json_escapes_quote_backslash");
    expect(write_string, "say \"hi\" \\ there", "\"say \\\"hi\\\" \\\\ there\"");
    tb_end();

    tb_begin("cli_json_control_characters_as_u00xx");
    expect(write_string, "a\nb\tc\rd\001e\037f", "\"a\\u000ab\\u0009c\\u000dd\\u0001e\\u001ff\"");
    tb_end();

    tb_begin("cli_json_utf8_and_del_kept");
    expect(write_string, "J\xc3\xa4\xc3\xa4skel\xc3\xa4inen \x7f", "\"J\xc3\xa4\xc3\xa4skel\xc3\xa4inen \x7f\"");
    tb_end();

    tb_begin("cli_json_null");
    expect(write_string, NULL, "null");
    expect(write_string, "", "\"\"");
    tb_end();

    tb_begin("cli_json_members_one_a_line");
    expect(write_members, "\n  ",
           "{\n  \"name\": \"a \\\"b\\\"\",\n  \"count\": 18446744073709551615,\n  \"ratio\": 0.1,\n  \"none\": null}");
    tb_end();

    tb_begin("cli_json_members_one_line");
    expect(write_members, " ",
           "{ \"name\": \"a \\\"b\\\"\", \"count\": 18446744073709551615, \"ratio\": 0.1, \"none\": null}");
    tb_end();

    /* an interrupted run's reason goes through the same escaping (it used
     * to drop control characters) */
    tb_begin("cli_json_partial_reason_escaped");
    expect(write_partial, "cut\nshort \"here\"",
           "{\n  \"partial\": true,\n  \"partial_reason\": \"cut\\u000ashort \\\"here\\\"\",\n  \"a\": 1\n}\n");
    tb_end();
    return tb_finish();
}
