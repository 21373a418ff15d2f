/* output_path.h — what rtsim, rttrace and rtdram share around their outputs
 * (cli/lib/output_path.c, in libcli).
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
#include <stddef.h>
#include <stdio.h>

#include "kernel/out_file.h"

typedef struct cli_output {
    const char *opt;   /* "--json" */
    const char *path;  /* NULL: option not given */
    ks_out *out;       /* the plan, set by cli_plan_outputs */
} cli_output;

/* True when every given path could be planned; else false with "OPT PATH:
 * why" in err and nothing left on disk. */
bool cli_plan_outputs(cli_output *outs, int n, char *err, size_t errlen);

/* Writes json (a JSON object's text) to f; when reason is not NULL the keys
 * "partial": true and "partial_reason" come first, in the object's style
 * (one key a line, or all on one line). */
void cli_json_put(FILE *f, const char *json, const char *reason);

/* Writes json to a planned output and commits it; 0, or -1 with err. */
int cli_write_json(ks_out *out, const char *json, const char *reason, char *err, size_t errlen);

#endif
