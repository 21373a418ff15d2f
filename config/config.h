/* config.h — rtcfg, the machine configuration: a typed key/value store
 * validated against schema tables that each module declares.
 *
 * Contract:
 *  - Keys are "section.name". Every module declares an rtcfg_schema (a section
 *    and a table of rtcfg_param: type int/real/bool/enum/string, default,
 *    inclusive range, power-of-two flag, unit, one-line description) and
 *    registers it with rtcfg_add_schema(). Several schemas may share a section
 *    as long as their keys differ (e.g. "fifo.*" from several modules).
 *  - Values come from, in increasing priority: the schema default, a preset or
 *    INI file (rtcfg_load; presets "bvh2", "mbvh4" are model/data/machines/
 *    NAME.ini), then overrides "key=value" (rtcfg_set, the CLI's --set).
 *    Entries may arrive before their schema is registered: they are kept as
 *    text and validated when the schema arrives; rtcfg_finish() reports any
 *    entry no schema claimed and runs every schema's cross-key check.
 *  - Every error returns -1 with one line in err naming the file:line (or
 *    "--set KEY=VALUE") and the key, and the allowed values or range.
 *  - Getters take a registered key of the right type; anything else is a
 *    programming error: message on stderr and abort().
 *  - Deferred schemas (rtcfg_add_deferred): a section whose keys depend on a
 *    value (the [dram] keys are those of the DRAM standard file named by
 *    memory.dram_config) is registered by a callback that rtcfg_finish runs
 *    once, after every file and override, before unclaimed entries are errors.
 *  - rtcfg_write_ini() writes every key with its current value (temp file,
 *    then rename), so the output loads back to the same configuration.
 * Deterministic: no host state other than the files named. Not thread-safe
 * during loading; getters are read-only. */
#ifndef RTSIM_MODEL_CONFIG_H
#define RTSIM_MODEL_CONFIG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

typedef enum rtcfg_type {
    RTCFG_INT,     /* decimal or 0x hex, optional binary suffix K, M, G (x1024^n) */
    RTCFG_REAL,    /* finite decimal number */
    RTCFG_BOOL,    /* true/false, yes/no, on/off, 1/0 */
    RTCFG_ENUM,    /* one of choices "a|b|c" */
    RTCFG_STRING,  /* any text (e.g. a file path) */
} rtcfg_type;

#define RTCFG_POW2 1u   /* int must be a power of two */

/* A path buffer of the configuration and of the files it names (machines,
 * the DRAM standard and its currents, energy tables, estimate.ini): PATH_MAX
 * on Linux. A path that does not fit is refused with a message naming it,
 * never cut (a cut path names another file). */
#define RTCFG_PATH_MAX 4096
/* "FILE:LINE" or "--set KEY=VALUE": where a value came from */
#define RTCFG_WHERE_MAX (RTCFG_PATH_MAX + 64)
/* a message that names a file: the whole path and room for the reason */
#define RTCFG_MSG_MAX (RTCFG_PATH_MAX + 1024)

typedef struct rtcfg_param {
    const char *name;     /* key within the section, e.g. "size" */
    rtcfg_type type;
    const char *def;      /* default, as text (parsed like a file value) */
    double min, max;      /* int/real: inclusive allowed range */
    unsigned flags;       /* RTCFG_POW2 */
    const char *choices;  /* enum: "fixed|lpddr3"; string: what it accepts, or NULL = any text */
    const char *unit;     /* "bytes", "cycles", "" ... */
    const char *desc;     /* one line */
} rtcfg_param;

typedef struct rtcfg rtcfg;

typedef struct rtcfg_schema {
    const char *section;              /* "node_l1" */
    const char *title;                /* one line: what the section configures */
    const rtcfg_param *params;
    int nparams;
    /* Optional cross-key check run by rtcfg_finish (e.g. sets = size/(line*ways)
     * must be a power of two); returns -1 with a message naming the keys. */
    int (*check)(const rtcfg *cfg, char *err, size_t errlen);
} rtcfg_schema;

rtcfg *rtcfg_create(void);   /* with the built-in [machine] schema registered */
void rtcfg_destroy(rtcfg *cfg);

/* The schema must outlive cfg. Validates already loaded entries of its keys. */
int rtcfg_add_schema(rtcfg *cfg, const rtcfg_schema *schema, char *err, size_t errlen);
/* Preset name (letters, digits, '_', '-') or a path (contains '/' or ends in .ini). */
int rtcfg_load(rtcfg *cfg, const char *preset_or_path, char *err, size_t errlen);
/* "section.name=value" (spaces around '=' allowed). */
int rtcfg_set(rtcfg *cfg, const char *assignment, char *err, size_t errlen);
/* Runs the deferred callbacks (once); then unclaimed keys are errors; runs
 * every schema's check. Call once all schemas are registered and all
 * files/overrides applied. */
int rtcfg_finish(rtcfg *cfg, char *err, size_t errlen);

/* fn(cfg, user, err, errlen) is called by rtcfg_finish (in registration
 * order) and may read registered keys and register schemas; -1 fails finish. */
typedef int (*rtcfg_deferred_fn)(rtcfg *cfg, void *user, char *err, size_t errlen);
void rtcfg_add_deferred(rtcfg *cfg, rtcfg_deferred_fn fn, void *user);
/* cfg frees block (malloc'ed; e.g. a schema built at run time) when destroyed. */
void rtcfg_own(rtcfg *cfg, void *block);

/* Directory of the presets (model/data/machines; RTSIM_DATA_DIR overrides the
 * compiled-in model/data) and the file of a preset name. */
const char *rtcfg_data_dir(void);
int rtcfg_preset_path(const char *name, char *buf, size_t len);

bool rtcfg_has(const rtcfg *cfg, const char *key);           /* registered key */
int64_t rtcfg_int(const rtcfg *cfg, const char *key);
double rtcfg_real(const rtcfg *cfg, const char *key);        /* int keys too */
bool rtcfg_bool(const rtcfg *cfg, const char *key);
int rtcfg_enum(const rtcfg *cfg, const char *key);           /* index into choices */
const char *rtcfg_str(const rtcfg *cfg, const char *key);    /* value text, any type */
/* Where the value came from: "default", "FILE:LINE" or "--set". */
const char *rtcfg_source(const rtcfg *cfg, const char *key);

/* Programmatic update (e.g. FIFO auto-sizing), validated like rtcfg_set. */
int rtcfg_set_int(rtcfg *cfg, const char *key, int64_t value, char *err, size_t errlen);

/* Writes all registered keys, by section, with descriptions as comments. */
int rtcfg_write_ini(const rtcfg *cfg, const char *path, char *err, size_t errlen);
/* The same text to an open stream (the tools write it through their output layer). */
void rtcfg_write_ini_file(const rtcfg *cfg, FILE *f);

/* Iteration over registered schemas (registration order). */
int rtcfg_schema_count(const rtcfg *cfg);
const rtcfg_schema *rtcfg_schema_at(const rtcfg *cfg, int i);
/* Human-readable table of a schema's keys with current values (or defaults
 * when cfg is NULL): key, type, default/value, range, unit, description. */
void rtcfg_print_schema(FILE *out, const rtcfg_schema *schema, const rtcfg *cfg);
/* "1..64, power of two" / "fixed|lpddr3" / "true|false" / "any text". */
void rtcfg_describe_range(const rtcfg_param *p, char *buf, size_t len);

/* Helpers for schema checks: "node_l1.size" etc. in messages. */
int rtcfg_errorf(char *err, size_t errlen, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

#endif
