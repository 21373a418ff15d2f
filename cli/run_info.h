/* run_info.h — the provenance record ("run" object) that rtsim, rttrace and
 * rtdram put first in every JSON they write, so that a result file alone says
 * which build, command, scene, machine and settings produced it, and what the
 * run cost on the host. The keys, their units and which tool leaves which key
 * null are documented in docs/results.md (a testbench checks that every key
 * written is documented there).
 *
 * Contract:
 *  - cli_run_init() at the start of main records the tool, the command line,
 *    the working folder, the date (UTC, ISO 8601) and the host clocks; the
 *    tool then fills the fields that apply to it (the others stay "not
 *    given" and are written as null).
 *  - Hashes are FNV-1a 64 (offset basis 14695981039346656037, prime
 *    1099511628211), written as 16 lower-case hex digits. The mesh hash is
 *    rt_mesh_hash (tracer/io/mesh.h: counts, vertex bits, indices as loaded).
 *    The configuration hash is over the configuration's canonical lines
 *    "key=value\n", sorted by key (byte order): cli_run_config_hash() for an
 *    rtcfg (every registered key, [dram] included; integers in decimal,
 *    reals as %.17g, booleans true/false, enums and strings as text),
 *    cli_run_hash_lines() for a tool's own list of lines, cli_run_dram_hash()
 *    for rtdram (the DRAM standard's keys after --set, named as rtsim's
 *    dram.SECTION.KEY, and memory.dram_power=FILE).
 *  - cli_run_splice() writes a JSON object's text with the run object
 *    inserted as its first member; the object's own members are unchanged.
 *  - The commit and dirty flag are the build's (cli/version.h; the Makefile
 *    passes RTSIM_GIT and RTSIM_GIT_DIRTY, mk/version.mk).
 * Header-only (static functions) because cli/ builds one binary per .c. */
#ifndef RTSIM_CLI_RUN_INFO_H
#define RTSIM_CLI_RUN_INFO_H

#include <inttypes.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "cli/version.h"
#include "config/config.h"
#include "model/dram/dram_timing.h"

typedef struct cli_run_info {
    const char *tool;             /* "rtsim" */
    int argc;
    char **argv;                  /* a copy of main's: getopt_long permutes main's */
    char cwd[4096];               /* "" when unknown */
    char date[32];                /* start, UTC: 2026-11-26T12:34:56Z */
    double wall0, cpu0;           /* host clocks at cli_run_init */
    /* input: scene (or trace) as given, view, mesh */
    const char *scene, *views_file, *view, *trace;
    bool has_mesh_hash;
    uint64_t mesh_hash;
    /* machine: preset or file as given, hash of the resolved configuration */
    const char *machine;
    bool has_config_hash;
    uint64_t config_hash;
    /* rays: 0 / NULL / has_* false = not applicable (null) */
    uint32_t width, height;
    const char *rays;             /* "primary" | "diffuse" */
    bool has_bounces, has_seed;
    uint32_t bounces;
    uint64_t seed;
    /* host cost: the simulation proper (sim_*) and its simulated cycles */
    bool has_sim;
    double sim_cpu_s, sim_wall_s;
    bool has_cycles;
    uint64_t cycles;
    /* worker processes (rtsim's fidelity levels, kernel/fork_pool.h): the
     * --jobs limit, how many ran, and their CPU (part of sim_cpu_s) */
    bool has_workers;
    uint64_t jobs, workers;
    double worker_cpu_s;
} cli_run_info;

static inline double cli_run_clock(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU seconds of this process and of its reaped children (rtsim's worker
 * processes): what the host_cpu_s key counts. */
static inline double cli_run_cpu(void)
{
    struct rusage ru;
    double children = 0;
    if (getrusage(RUSAGE_CHILDREN, &ru) == 0)
        children = (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec + (double)ru.ru_stime.tv_sec +
                   1e-6 * (double)ru.ru_stime.tv_usec;
    return cli_run_clock(CLOCK_PROCESS_CPUTIME_ID) + children;
}

/* ri should be static in main: its copy of argv lives until exit. */
static inline void cli_run_init(cli_run_info *ri, const char *tool, int argc, char **argv)
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
    ri->cpu0 = cli_run_cpu();
}

/* ---- hashes ---- */

static inline uint64_t cli_run_fnv1a64(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 1099511628211ULL;
    }
    return h;
}
#define CLI_RUN_FNV_BASIS 14695981039346656037ULL

static inline int cli_run_cmp_lines(const void *a, const void *b)
{
    /* by key: the text up to '=' (keys are unique, so lines never tie) */
    const char *x = *(const char *const *)a, *y = *(const char *const *)b;
    size_t kx = strcspn(x, "="), ky = strcspn(y, "=");
    int c = memcmp(x, y, kx < ky ? kx : ky);
    return c ? c : (kx > ky) - (kx < ky);
}

/* Sorts lines ("key=value", no newline) by key and hashes "line\n" of each. */
static inline uint64_t cli_run_hash_lines(char **lines, size_t n)
{
    qsort(lines, n, sizeof *lines, cli_run_cmp_lines);
    uint64_t h = CLI_RUN_FNV_BASIS;
    for (size_t i = 0; i < n; i++) {
        h = cli_run_fnv1a64(h, lines[i], strlen(lines[i]));
        h = cli_run_fnv1a64(h, "\n", 1);
    }
    return h;
}

/* A growing list of "key=value" lines to hash. */
typedef struct cli_run_lines {
    char **line;
    size_t n, cap;
    bool oom;
} cli_run_lines;

/* Adds the line a b c "=" v (the key given in up to three pieces). */
static inline void cli_run_lines_add(cli_run_lines *l, const char *a, const char *b, const char *c, const char *v)
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

/* Hashes the lines (sorted by key), frees them; false when out of memory. */
static inline bool cli_run_lines_hash(cli_run_lines *l, uint64_t *out)
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

static inline void cli_run_dram_entry(void *user, const char *section, const char *key, const char *value)
{
    char sec[DRAM_NAME_LEN + 8];
    snprintf(sec, sizeof sec, "dram.%s.", section);
    cli_run_lines_add(user, sec, key, "", value);
}

/* rtdram's configuration hash: the DRAM file's keys after the overrides, and
 * the power file; false when the file cannot be read again or out of memory. */
static inline bool cli_run_dram_hash(const char *path, const char *const *sets, int nsets, const char *power,
                                     uint64_t *out)
{
    cli_run_lines l = {0};
    char err[600];
    bool ok = dram_spec_entries(path, sets, nsets, cli_run_dram_entry, &l, err, sizeof err) == 0;
    cli_run_lines_add(&l, "memory.dram_power", "", "", power ? power : "");
    return cli_run_lines_hash(&l, out) && ok;
}

/* Hash of every registered key of a finished configuration; false when out
 * of memory. */
static inline bool cli_run_config_hash(const rtcfg *cfg, uint64_t *out)
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

static inline void cli_run_json_str(FILE *f, const char *s)
{
    if (!s) {
        fputs("null", f);
        return;
    }
    fputc('"', f);
    for (const unsigned char *c = (const unsigned char *)s; *c; c++) {
        if (*c == '"' || *c == '\\')
            fprintf(f, "\\%c", *c);
        else if (*c < 0x20)
            fprintf(f, "\\u%04x", *c);
        else
            fputc(*c, f);
    }
    fputc('"', f);
}

static inline void cli_run_json_hash(FILE *f, bool has, uint64_t h)
{
    if (has)
        fprintf(f, "\"%016" PRIx64 "\"", h);
    else
        fputs("null", f);
}

static inline void cli_run_json_uint(FILE *f, bool has, uint64_t v)
{
    if (has)
        fprintf(f, "%" PRIu64, v);
    else
        fputs("null", f);
}

static inline void cli_run_json_real(FILE *f, bool has, double v)
{
    if (has)
        fprintf(f, "%.6f", v);
    else
        fputs("null", f);
}

/* The member "run": {...}; sep goes between members ("\n    " or " "). */
static inline void cli_run_write_member(FILE *f, const cli_run_info *ri, const char *sep)
{
    double host_wall = cli_run_clock(CLOCK_MONOTONIC) - ri->wall0;
    double host_cpu = cli_run_cpu() - ri->cpu0;
#define KEY(k) fprintf(f, "%s%s\"" k "\": ", first ? "" : ",", sep), first = false
    bool first = true;
    fputs("\"run\": {", f);
    KEY("tool");
    cli_run_json_str(f, ri->tool);
    KEY("version");
    cli_run_json_str(f, RTSIM_VERSION);
    KEY("commit");
    cli_run_json_str(f, RTSIM_GIT);
    KEY("dirty");
    fputs(RTSIM_GIT_DIRTY < 0 ? "null" : RTSIM_GIT_DIRTY ? "true" : "false", f);
    KEY("command_line");
    fputc('[', f);
    for (int i = 0; i < ri->argc; i++) {
        fputs(i ? ", " : "", f);
        cli_run_json_str(f, ri->argv[i]);
    }
    fputc(']', f);
    KEY("cwd");
    cli_run_json_str(f, ri->cwd[0] ? ri->cwd : NULL);
    KEY("scene");
    cli_run_json_str(f, ri->scene);
    KEY("views_file");
    cli_run_json_str(f, ri->views_file);
    KEY("view");
    cli_run_json_str(f, ri->view);
    KEY("mesh_hash");
    cli_run_json_hash(f, ri->has_mesh_hash, ri->mesh_hash);
    KEY("trace");
    cli_run_json_str(f, ri->trace);
    KEY("machine");
    cli_run_json_str(f, ri->machine);
    KEY("config_hash");
    cli_run_json_hash(f, ri->has_config_hash, ri->config_hash);
    KEY("width_px");
    cli_run_json_uint(f, ri->width != 0, ri->width);
    KEY("height_px");
    cli_run_json_uint(f, ri->height != 0, ri->height);
    KEY("ray_type");
    cli_run_json_str(f, ri->rays);
    KEY("bounces");
    cli_run_json_uint(f, ri->has_bounces, ri->bounces);
    KEY("seed");
    cli_run_json_uint(f, ri->has_seed, ri->seed);
    KEY("host_cpu_s");
    cli_run_json_real(f, true, host_cpu);
    KEY("host_wall_s");
    cli_run_json_real(f, true, host_wall);
    KEY("sim_cpu_s");
    cli_run_json_real(f, ri->has_sim, ri->sim_cpu_s);
    KEY("sim_wall_s");
    cli_run_json_real(f, ri->has_sim, ri->sim_wall_s);
    KEY("sim_jobs");
    cli_run_json_uint(f, ri->has_workers, ri->jobs);
    KEY("sim_workers");
    cli_run_json_uint(f, ri->has_workers, ri->workers);
    KEY("sim_worker_cpu_s");
    cli_run_json_real(f, ri->has_workers, ri->worker_cpu_s);
    KEY("cycles_per_host_s");
    cli_run_json_real(f, ri->has_sim && ri->has_cycles, ri->sim_cpu_s > 0 ? (double)ri->cycles / ri->sim_cpu_s : 0.0);
    KEY("date");
    cli_run_json_str(f, ri->date[0] ? ri->date : NULL);
#undef KEY
    fputs(sep[0] == '\n' ? "\n  }" : "}", f);
}

/* Writes the JSON object json[0..len) to out with "run" as its first member:
 * on one line when one_line (rtdram's one-line JSON stays one line), else
 * on its own indented lines. Returns -1 when json is not an object or out
 * has an error. */
static inline int cli_run_splice(FILE *out, const cli_run_info *ri, const char *json, size_t len, bool one_line)
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

#endif
