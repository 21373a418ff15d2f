/* run_info.c — the provenance record "run" (cli/run_info.h). */
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/json.h"
#include "cli/run_info.h"
#include "cli/version.h"
#include "kernel/fork_pool.h"
#include "model/dram/dram_timing.h"
#include "tracer/util/fnv1a.h"

double cli_run_clock(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void cli_run_init(cli_run_info *ri, const char *tool, int argc, char **argv)
{
    memset(ri, 0, sizeof *ri);
    ri->tool = tool;
    ri->argv = malloc(((size_t)argc + 1) * sizeof *ri->argv);
    if (ri->argv) {
        memcpy(ri->argv, argv, (size_t)argc * sizeof *argv);
        ri->argc = argc;
    }
    if (!getcwd(ri->cwd, sizeof ri->cwd))
        ri->cwd[0] = 0;
    time_t now = time(NULL);
    struct tm tm;
    if (gmtime_r(&now, &tm))
        strftime(ri->date, sizeof ri->date, "%Y-%m-%dT%H:%M:%SZ", &tm);
    ri->wall0 = cli_run_clock(CLOCK_MONOTONIC);
    ri->cpu0 = ks_pool_process_cpu_s();
}

/* ---- hashes ---- */


static int cli_run_cmp_lines(const void *a, const void *b)
{
    /* by key: the text up to '=' (keys are unique, so lines never tie) */
    const char *x = *(const char *const *)a, *y = *(const char *const *)b;
    size_t kx = strcspn(x, "="), ky = strcspn(y, "=");
    int c = memcmp(x, y, kx < ky ? kx : ky);
    return c ? c : (kx > ky) - (kx < ky);
}

uint64_t cli_run_hash_lines(char **lines, size_t n)
{
    qsort(lines, n, sizeof *lines, cli_run_cmp_lines);
    uint64_t h = RT_FNV1A64_BASIS;
    for (size_t i = 0; i < n; i++) {
        h = rt_fnv1a64(h, lines[i], strlen(lines[i]));
        h = rt_fnv1a64(h, "\n", 1);
    }
    return h;
}

void cli_run_lines_add(cli_run_lines *l, const char *a, const char *b, const char *c, const char *v)
{
    if (l->oom)
        return;
    if (l->n == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : 128;
        char **g = realloc(l->line, cap * sizeof *g);
        if (!g) {
            l->oom = true;
            return;
        }
        l->line = g, l->cap = cap;
    }
    size_t len = strlen(a) + strlen(b) + strlen(c) + strlen(v) + 2;
    char *t = malloc(len);
    if (!t) {
        l->oom = true;
        return;
    }
    snprintf(t, len, "%s%s%s=%s", a, b, c, v);
    l->line[l->n++] = t;
}

bool cli_run_lines_hash(cli_run_lines *l, uint64_t *out)
{
    bool ok = !l->oom;
    if (ok)
        *out = cli_run_hash_lines(l->line, l->n);
    for (size_t i = 0; i < l->n; i++)
        free(l->line[i]);
    free(l->line);
    memset(l, 0, sizeof *l);
    return ok;
}

static void cli_run_dram_entry(void *user, const char *section, const char *key, const char *value)
{
    char sec[DRAM_NAME_LEN + 8];
    snprintf(sec, sizeof sec, "dram.%s.", section);
    cli_run_lines_add(user, sec, key, "", value);
}

bool cli_run_dram_hash(const char *path, const char *const *sets, int nsets, const char *power,
                                     uint64_t *out)
{
    cli_run_lines l = {0};
    char err[600];
    bool ok = dram_spec_entries(path, sets, nsets, cli_run_dram_entry, &l, err, sizeof err) == 0;
    cli_run_lines_add(&l, "memory.dram_power", "", "", power ? power : "");
    return cli_run_lines_hash(&l, out) && ok;
}

bool cli_run_config_hash(const rtcfg *cfg, uint64_t *out)
{
    cli_run_lines l = {0};
    for (int i = 0; i < rtcfg_schema_count(cfg); i++) {
        const rtcfg_schema *s = rtcfg_schema_at(cfg, i);
        for (int k = 0; k < s->nparams; k++) {
            const rtcfg_param *p = &s->params[k];
            char key[256], val[64];
            snprintf(key, sizeof key, "%s.%s", s->section, p->name);
            const char *v = val;
            if (p->type == RTCFG_INT)
                snprintf(val, sizeof val, "%" PRId64, rtcfg_int(cfg, key));
            else if (p->type == RTCFG_REAL)
                snprintf(val, sizeof val, "%.17g", rtcfg_real(cfg, key));
            else if (p->type == RTCFG_BOOL)
                v = rtcfg_bool(cfg, key) ? "true" : "false";
            else
                v = rtcfg_str(cfg, key);
            cli_run_lines_add(&l, key, "", "", v);
        }
    }
    return cli_run_lines_hash(&l, out);
}

/* ---- JSON ---- */

/* Values that may be absent (null): a hash as 16 hex digits, a count, a
 * time in seconds with 6 decimals. */
static void cli_run_json_hash(cli_json *j, const char *key, bool has, uint64_t h)
{
    cli_json_key(j, key);
    if (has)
        fprintf(j->f, "\"%016" PRIx64 "\"", h);
    else
        fputs("null", j->f);
}

static void cli_run_json_uint(cli_json *j, const char *key, bool has, uint64_t v)
{
    cli_json_key(j, key);
    if (has)
        fprintf(j->f, "%" PRIu64, v);
    else
        fputs("null", j->f);
}

static void cli_run_json_real(cli_json *j, const char *key, bool has, double v)
{
    cli_json_key(j, key);
    if (has)
        fprintf(j->f, "%.6f", v);
    else
        fputs("null", j->f);
}

void cli_run_write_member(FILE *f, const cli_run_info *ri, const char *sep)
{
    double host_wall = cli_run_clock(CLOCK_MONOTONIC) - ri->wall0;
    double host_cpu = ks_pool_process_cpu_s() - ri->cpu0;
    cli_json j = {f, sep, true};
    fputs("\"run\": {", f);
    cli_json_str(&j, "tool", ri->tool);
    cli_json_str(&j, "version", RTSIM_VERSION);
    cli_json_str(&j, "commit", RTSIM_GIT);
    cli_json_key(&j, "dirty");
    fputs(RTSIM_GIT_DIRTY < 0 ? "null" : RTSIM_GIT_DIRTY ? "true" : "false", f);
    cli_json_key(&j, "command_line");
    fputc('[', f);
    for (int i = 0; i < ri->argc; i++) {
        fputs(i ? ", " : "", f);
        ks_json_string(f, ri->argv[i]);
    }
    fputc(']', f);
    cli_json_str(&j, "cwd", ri->cwd[0] ? ri->cwd : NULL);
    cli_json_str(&j, "scene", ri->scene);
    cli_json_str(&j, "views_file", ri->views_file);
    cli_json_str(&j, "view", ri->view);
    cli_run_json_hash(&j, "mesh_hash", ri->has_mesh_hash, ri->mesh_hash);
    cli_json_str(&j, "trace", ri->trace);
    cli_json_str(&j, "machine", ri->machine);
    cli_run_json_hash(&j, "config_hash", ri->has_config_hash, ri->config_hash);
    cli_run_json_uint(&j, "width_px", ri->width != 0, ri->width);
    cli_run_json_uint(&j, "height_px", ri->height != 0, ri->height);
    cli_json_str(&j, "ray_type", ri->rays);
    cli_run_json_uint(&j, "bounces", ri->has_bounces, ri->bounces);
    cli_run_json_uint(&j, "seed", ri->has_seed, ri->seed);
    cli_run_json_real(&j, "host_cpu_s", true, host_cpu);
    cli_run_json_real(&j, "host_wall_s", true, host_wall);
    cli_run_json_real(&j, "sim_cpu_s", ri->has_sim, ri->sim_cpu_s);
    cli_run_json_real(&j, "sim_wall_s", ri->has_sim, ri->sim_wall_s);
    cli_run_json_uint(&j, "sim_jobs", ri->has_workers, ri->jobs);
    cli_run_json_uint(&j, "sim_workers", ri->has_workers, ri->workers);
    cli_run_json_real(&j, "sim_worker_cpu_s", ri->has_workers, ri->worker_cpu_s);
    cli_run_json_real(&j, "cycles_per_host_s", ri->has_sim && ri->has_cycles,
                      ri->sim_cpu_s > 0 ? (double)ri->cycles / ri->sim_cpu_s : 0.0);
    cli_json_key(&j, "accuracy_steps");
    if (ri->nsteps > 0) {
        fputc('[', f);
        for (int i = 0; i < ri->nsteps; i++) {
            fputs(i ? ", {\"step\": " : "{\"step\": ", f);
            ks_json_string(f, ri->step_name[i]);
            fprintf(f, ", \"cpu_s\": %.6f}", ri->step_cpu_s[i]);
        }
        fputc(']', f);
    } else
        fputs("null", f);
    cli_json_str(&j, "date", ri->date[0] ? ri->date : NULL);
    fputs(sep[0] == '\n' ? "\n  }" : "}", f);
}

int cli_run_splice(FILE *out, const cli_run_info *ri, const char *json, size_t len, bool one_line)
{
    const char *open = memchr(json, '{', len);
    if (!open)
        return -1;
    const char *rest = open + 1, *end = json + len;
    const char *p = rest;
    while (p < end && (*p == ' ' || *p == '\n' || *p == '\t' || *p == '\r'))
        p++;
    bool empty = p < end && *p == '}';
    fwrite(json, 1, (size_t)(rest - json), out);
    fputs(one_line ? "" : "\n  ", out);
    cli_run_write_member(out, ri, one_line ? " " : "\n    ");
    fputs(empty ? "" : one_line ? ", " : ",", out);
    fwrite(rest, 1, (size_t)(end - rest), out);
    return ferror(out) ? -1 : 0;
}
