/* json.c — a JSON object's members (cli/json.h). */
#include <inttypes.h>

#include "cli/json.h"

void cli_json_key(cli_json *j, const char *key)
{
    fprintf(j->f, "%s%s", j->first ? "" : ",", j->sep);
    ks_json_string(j->f, key);
    fputs(": ", j->f);
    j->first = false;
}

void cli_json_uint(cli_json *j, const char *key, uint64_t v)
{
    cli_json_key(j, key);
    fprintf(j->f, "%" PRIu64, v);
}

void cli_json_real(cli_json *j, const char *key, double v)
{
    cli_json_key(j, key);
    fprintf(j->f, "%.9g", v);
}

void cli_json_str(cli_json *j, const char *key, const char *s)
{
    cli_json_key(j, key);
    ks_json_string(j->f, s);
}
