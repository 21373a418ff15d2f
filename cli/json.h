/* json.h — the members of a JSON object as the tools write them: one
 * "key": value after another, each preceded by a separator ("\n  " puts
 * one member a line; " " keeps the object on one line). Strings go
 * through the project's one escaping function (kernel/json.h).
 *
 * Contract: set up a cli_json with the stream and the separator, first =
 * true; cli_json_key() writes ",", the separator and "key": (no comma
 * before the first member); the typed writers write a key and its value:
 * integers in decimal, reals with 9 significant digits (%.9g), strings
 * escaped (NULL as null). */
#ifndef RTSIM_CLI_JSON_H
#define RTSIM_CLI_JSON_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "kernel/json.h"

typedef struct cli_json {
    FILE *f;
    const char *sep;   /* before every member: "\n  " or " " */
    bool first;        /* no member written yet */
} cli_json;

void cli_json_key(cli_json *j, const char *key);
void cli_json_uint(cli_json *j, const char *key, uint64_t v);
void cli_json_real(cli_json *j, const char *key, double v);
void cli_json_str(cli_json *j, const char *key, const char *s);

#endif
