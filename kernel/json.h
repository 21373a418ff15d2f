/* json.h — the one JSON string escaping of the project: the statistics
 * registry (kernel/stats.c) and the command-line tools (cli/json.h) write
 * every JSON string through it.
 *
 * Contract: ks_json_string() writes s as a JSON string literal, quotes
 * included: '"' and '\' escaped with a backslash, every control character
 * (below 0x20) as \u00XX, all other bytes (UTF-8 included) as they are; a
 * NULL s is written as null. It lives in the kernel because the kernel
 * includes nothing from the other folders. */
#ifndef KS_JSON_H
#define KS_JSON_H

#include <stdio.h>

void ks_json_string(FILE *f, const char *s);

#endif
