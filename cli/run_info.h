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
 * The code is in cli/lib/run_info.c (libcli). */
#ifndef RTSIM_CLI_RUN_INFO_H
#define RTSIM_CLI_RUN_INFO_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <time.h>

#include "config/config.h"

/* rtsim --accuracy's steps the run object holds (fidelity.h: FID_MAX_STEPS) */
#define CLI_RUN_MAX_STEPS 8

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
    /* rtsim --accuracy: the steps it ran and the CPU seconds of each (the
     * last is the level picked; nsteps 0: not asked) */
    int nsteps;
    const char *step_name[CLI_RUN_MAX_STEPS];
    double step_cpu_s[CLI_RUN_MAX_STEPS];
} cli_run_info;

/* Seconds on a host clock (CLOCK_MONOTONIC, CLOCK_PROCESS_CPUTIME_ID). */
double cli_run_clock(clockid_t id);

/* ri should be static in main: its copy of argv lives until exit. */
void cli_run_init(cli_run_info *ri, const char *tool, int argc, char **argv);

/* Sorts lines ("key=value", no newline) by key and hashes "line\n" of each. */
uint64_t cli_run_hash_lines(char **lines, size_t n);

/* A growing list of "key=value" lines to hash. */
typedef struct cli_run_lines {
    char **line;
    size_t n, cap;
    bool oom;
} cli_run_lines;

/* Adds the line a b c "=" v (the key given in up to three pieces). */
void cli_run_lines_add(cli_run_lines *l, const char *a, const char *b, const char *c, const char *v);

/* Hashes the lines (sorted by key), frees them; false when out of memory. */
bool cli_run_lines_hash(cli_run_lines *l, uint64_t *out);

/* rtdram's configuration hash: the DRAM file's keys after the overrides, and
 * the power file; false when the file cannot be read again or out of memory. */
bool cli_run_dram_hash(const char *path, const char *const *sets, int nsets, const char *power, uint64_t *out);

/* Hash of every registered key of a finished configuration; false when out
 * of memory. */
bool cli_run_config_hash(const rtcfg *cfg, uint64_t *out);

/* The member "run": {...}; sep goes before each of its members ("\n    "
 * or " "). */
void cli_run_write_member(FILE *f, const cli_run_info *ri, const char *sep);

/* Writes the JSON object json[0..len) to out with "run" as its first member:
 * on one line when one_line (rtdram's one-line JSON stays one line), else
 * on its own indented lines. Returns -1 when json is not an object or out
 * has an error. */
int cli_run_splice(FILE *out, const cli_run_info *ri, const char *json, size_t len, bool one_line);

#endif
