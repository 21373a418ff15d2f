/* output_path.c — planning and writing the tools' outputs (cli/output_path.h). */
#include <string.h>

#include "cli/output_path.h"
#include "kernel/json.h"

bool cli_plan_outputs(cli_output *outs, int n, char *err, size_t errlen)
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

void cli_json_put(FILE *f, const char *json, const char *reason)
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
    fputs("\"partial_reason\": ", f);
    ks_json_string(f, reason);
    fputc(',', f);
    fwrite(sep, 1, (size_t)seplen, f);
    fputs(key, f);
}

int cli_write_json(ks_out *out, const char *json, const char *reason, char *err, size_t errlen)
{
    FILE *f = ks_out_begin(out, err, errlen);
    if (!f)
        return -1;
    cli_json_put(f, json, reason);
    return ks_out_commit(out, err, errlen);
}
