/* output_path.h — what rtsim, rttrace and rtdram share around their outputs
 * (header-only: cli/ builds one binary per .c file).
 *  - cli_plan_outputs(): plans every output of the run through the output
 *    layer (kernel/out_file.h) before any work is done, in the order given,
 *    so a bad path, or two options naming the same file, fail at start-up
 *    with exit 2 instead of after the run.
 *  - cli_write_json(): writes a JSON text to a planned output, with
 *    "partial": true and "partial_reason" inserted as its first keys when
 *    the run was interrupted (the rest of the object is unchanged, so a
 *    complete run's JSON stays byte-identical). */
#ifndef RTSIM_CLI_OUTPUT_PATH_H
#define RTSIM_CLI_OUTPUT_PATH_H

#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "kernel/interrupt.h"
#include "kernel/out_file.h"

typedef struct cli_output {
    const char *opt;   /* "--json" */
    const char *path;  /* NULL: option not given */
    ks_out *out;       /* the plan, set by cli_plan_outputs */
} cli_output;

/* True when every given path could be planned; else false with "OPT PATH:
 * why" in err and nothing left on disk. */
static inline bool cli_plan_outputs(cli_output *outs, int n, char *err, size_t errlen)
{
    for (int i = 0; i < n; i++) {
        outs[i].out = NULL;
        if (!outs[i].path)
            continue;
        outs[i].out = ks_out_plan(outs[i].opt, outs[i].path, err, errlen);
        if (!outs[i].out) {
            for (int j = 0; j < i; j++)
                ks_out_discard(outs[j].out);
            return false;
        }
    }
    return true;
}

/* Writes json (a JSON object's text) to f; when reason is not NULL the keys
 * "partial": true and "partial_reason" come first, in the object's style
 * (one key a line, or all on one line). */
static inline void cli_json_put(FILE *f, const char *json, const char *reason)
{
    const char *open = reason ? strchr(json, '{') : NULL;
    if (!open) {
        fputs(json, f);
        return;
    }
    const char *key = open + 1;
    while (*key == ' ' || *key == '\n')
        key++;
    fwrite(json, 1, (size_t)(key - json), f);
    int indent = (int)(key - open - 1); /* "\n  " between keys, or "" */
    const char *sep = indent ? open + 1 : " ";
    int seplen = indent ? indent : 1;
    fputs("\"partial\": true,", f);
    fwrite(sep, 1, (size_t)seplen, f);
    fputs("\"partial_reason\": \"", f);
    for (const char *c = reason; *c; c++)
        if (*c == '"' || *c == '\\')
            fprintf(f, "\\%c", *c);
        else if ((unsigned char)*c >= 0x20)
            fputc(*c, f);
    fputs("\",", f);
    fwrite(sep, 1, (size_t)seplen, f);
    fputs(key, f);
}

/* Writes json to a planned output and commits it; 0, or -1 with err. */
static inline int cli_write_json(ks_out *out, const char *json, const char *reason, char *err, size_t errlen)
{
    FILE *f = ks_out_begin(out, err, errlen);
    if (!f)
        return -1;
    cli_json_put(f, json, reason);
    return ks_out_commit(out, err, errlen);
}

#endif
