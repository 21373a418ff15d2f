/* dram_timing.h — a DRAM standard as data: organization, timing parameters,
 * command-to-command constraints and controller policy, loaded from an INI
 * parameter file (one file per speed grade, e.g. model/data/lpddr3_1600.ini).
 *
 * The file has four sections (see model/data/lpddr3_1600.ini for the default
 * LPDDR3-1600 grade and docs/dram.md for the format):
 *   [organization]  channels, ranks, banks, rows, columns, dq_bits, prefetch, tck_ps
 *   [timing]        named cycle counts; each value is an integer expression
 *                   (+ - * and parentheses) over integers and earlier names
 *   [constraints]   "<scope> <FROM> -> <TO> [window N] = expression": after a FROM
 *                   command, TO may issue no earlier than expression cycles later
 *                   (window N: measured from the N-th most recent FROM, e.g. tFAW).
 *                   scope: channel (all ranks), rank (same rank), bank (same bank),
 *                   sibling (another bank of the same rank).
 *   [controller]    queue sizes, scheduler row-hit cap, write watermarks, read
 *                   latency, refresh interval, address mapping
 * Overrides "section.key=value" (rtdram --set; rtsim's dram.section.key keys,
 * model/mem/memsys_config.h) replace a value of the file; a key the file does not
 * define is an error. Every error names the file, line or key and the allowed
 * range. The loaded spec is immutable and shared read-only. */
#ifndef RTSIM_DRAM_TIMING_H
#define RTSIM_DRAM_TIMING_H

#include <stddef.h>
#include <stdint.h>

/* Commands of the controller (auto-precharge variants are not used: open page). */
enum dram_cmd { DRAM_ACT, DRAM_PRE, DRAM_PREA, DRAM_RD, DRAM_WR, DRAM_REF, DRAM_NCMD };
/* Scope of a constraint: which later commands it restricts. */
enum dram_scope { DRAM_SCOPE_CHANNEL, DRAM_SCOPE_RANK, DRAM_SCOPE_BANK, DRAM_SCOPE_SIBLING, DRAM_NSCOPE };

#define DRAM_MAX_PARAMS 64
#define DRAM_MAX_CONSTRAINTS 96
#define DRAM_MAX_WINDOW 8
#define DRAM_NAME_LEN 32
#define DRAM_MAX_ENTRIES 256   /* key = value lines of one file */
#define DRAM_KEY_LEN 64        /* longest key + 1 (constraint keys are phrases) */
#define DRAM_VALUE_LEN 160     /* longest value + 1 */

typedef struct dram_constraint {
    uint8_t scope;   /* enum dram_scope */
    uint8_t from;    /* enum dram_cmd */
    uint8_t to;      /* enum dram_cmd */
    uint8_t window;  /* 1 = from the latest FROM; N = from the N-th latest */
    int32_t cycles;  /* minimum distance FROM -> TO in DRAM cycles */
} dram_constraint;

typedef struct dram_spec {
    char source[4096];            /* file the spec was loaded from (PATH_MAX: whole, never cut) */
    /* [organization] */
    int channels, ranks, banks, rows, columns, dq_bits, prefetch;
    int tck_ps;                   /* clock period, picoseconds */
    int tx_bytes;                 /* bytes per RD/WR burst = dq_bits*prefetch/8 */
    /* [timing]: named values, in file order */
    int nparams;
    char param_name[DRAM_MAX_PARAMS][DRAM_NAME_LEN];
    int param_value[DRAM_MAX_PARAMS];
    /* [constraints] */
    int nconstraints;
    dram_constraint constraint[DRAM_MAX_CONSTRAINTS];
    /* [controller] */
    int read_queue, write_queue;  /* entries per channel */
    int row_hit_cap;              /* FR-FCFS: a row with more hits loses priority */
    int write_high_pct;           /* write mode when writeq > high% of write_queue (floor) */
    int write_low_pct;            /* read mode when writeq < low% of write_queue (floor) and reads wait */
    int read_latency;             /* RD issue -> data complete, cycles */
    int refresh_interval;         /* cycles between all-bank REF requests per rank */
    int max_postponed_refresh;    /* checker: REF gap allowed = (1+this) * refresh_interval */
    char mapping[DRAM_NAME_LEN];  /* address mapping, e.g. RoBaRaCoCh (dram_addrmap.h) */
} dram_spec;

/* Loads `path`, applies `nsets` overrides "section.key=value", validates.
 * Returns 0, or -1 with a one-line message in err (file:line or key, allowed range). */
int dram_spec_load(dram_spec *spec, const char *path, const char *const *sets, int nsets,
                   char *err, size_t errlen);

/* The same, with origins[i] (e.g. "--set dram.timing.nCL=14" or "FILE:LINE")
 * naming override i in messages instead of "--set SETS[i]"; origins may be NULL. */
int dram_spec_load_from(dram_spec *spec, const char *path, const char *const *sets, const char *const *origins,
                        int nsets, char *err, size_t errlen);

/* Every entry of the file in file order, values after the overrides (which
 * must name keys of the file), unevaluated: fn(user, section, key, value).
 * Returns 0, or -1 with a message in err. Values are not validated. */
typedef void (*dram_entry_fn)(void *user, const char *section, const char *key, const char *value);
int dram_spec_entries(const char *path, const char *const *sets, int nsets, dram_entry_fn fn, void *user, char *err,
                      size_t errlen);

/* Allowed range of a key, as text for messages and configuration listings
 * ("1..16", "integer expression 0..10000000", "address mapping, e.g. RoBaRaCoCh"). */
void dram_spec_describe_key(const char *section, const char *key, char *buf, size_t len);

/* Value of a [timing] parameter, or -1 when the spec has no such name. */
int dram_spec_param(const dram_spec *spec, const char *name);

extern const char *const dram_cmd_name[DRAM_NCMD];
extern const char *const dram_scope_name[DRAM_NSCOPE];
/* Command of a name ("ACT", ...), or -1. */
int dram_cmd_from_name(const char *name);
/* 1 if the command targets one bank (ACT PRE RD WR), 0 if the whole rank (PREA REF). */
static inline int dram_cmd_is_bank_scoped(int cmd) { return cmd != DRAM_PREA && cmd != DRAM_REF; }

#endif
