/* stats.h — the statistics registry.
 *
 * Contract:
 *  - A registry holds named statistics, each with a unit and a one-line
 *    description; names are dotted paths ("trv0.node_visits"), unique within
 *    a registry (a duplicate name returns the existing counter's storage for
 *    counters/reals and NULL otherwise, message in ks_stats_error).
 *  - Counters (uint64, incremented in place through the returned pointer, or
 *    registered over a field of a module's struct), reals (double), histograms
 *    (linear bins over [lo, hi) plus under/overflow, count/sum/min/max), and
 *    derived formulas (a callback computing a double from the others, e.g. a
 *    hit rate; or ks_stat_ratio of two named statistics).
 *  - Output, in registration order: ks_stats_write_json (one JSON object:
 *    a field per statistic, histograms as objects, plus "_units" and
 *    "_descriptions" tables), ks_stats_write_csv (name,value,unit,description)
 *    and ks_stats_write_summary (aligned human-readable table). Numbers are
 *    printed deterministically (integers exact, reals with %.17g or shorter
 *    round-trip form; non-finite reals as null in JSON).
 *  - Declared registration (ks_stat_decl_*): a module registers a statistic
 *    by its name in the module's description table (kernel/module_desc.h):
 *    the unit and description come from the table's KS_DESC_STAT item, the
 *    full name is "scope.name" (scope may be NULL: the name alone), and a
 *    name the table does not declare is an error (-1, message naming the
 *    module). In a declared name '#' matches one or more digits and '*' one
 *    or more of [a-z0-9_] ("stack_bank#_reads", "energy.*_mj"); the first
 *    matching item wins; a '#' in the item's description stands for the
 *    digits its name's '#' matched. ks_stats_registered_from() tells whether an item of
 *    a table was registered, so a test can find declared statistics that no
 *    unit registers.
 * The registry is independent of any sim. */
#ifndef KS_STATS_H
#define KS_STATS_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "kernel/module_desc.h"

typedef struct ks_stats ks_stats;
typedef struct ks_histogram ks_histogram;
typedef double (*ks_formula_fn)(const ks_stats *reg, void *user);

ks_stats *ks_stats_create(void);
void ks_stats_destroy(ks_stats *reg);
const char *ks_stats_error(const ks_stats *reg);

/* Returns storage owned by the registry, zero-initialised. */
uint64_t *ks_stat_counter(ks_stats *reg, const char *name, const char *unit, const char *desc);
double *ks_stat_real(ks_stats *reg, const char *name, const char *unit, const char *desc);
/* Registers caller-owned storage (must outlive the registry's use); 0 / -1. */
int ks_stat_counter_ref(ks_stats *reg, const char *name, const char *unit, const char *desc,
                        const uint64_t *value);
/* The same for a statistic of a module instance: registered as
 * "scope.name" (e.g. scope "trv0", name "visits" -> "trv0.visits"). */
int ks_stat_counter_ref_in(ks_stats *reg, const char *scope, const char *name, const char *unit,
                           const char *desc, const uint64_t *value);
int ks_stat_real_ref(ks_stats *reg, const char *name, const char *unit, const char *desc,
                     const double *value);
ks_histogram *ks_stat_histogram(ks_stats *reg, const char *name, const char *unit,
                                const char *desc, double lo, double hi, unsigned bins);
int ks_stat_formula(ks_stats *reg, const char *name, const char *unit, const char *desc,
                    ks_formula_fn fn, void *user);
/* name = numerator / denominator (0 when the denominator is 0). */
int ks_stat_ratio(ks_stats *reg, const char *name, const char *unit, const char *desc,
                  const char *numerator, const char *denominator);

void ks_histogram_add(ks_histogram *h, double value);
uint64_t ks_histogram_count(const ks_histogram *h);
double ks_histogram_mean(const ks_histogram *h);

/* Declared registration (see the contract above). */
int ks_stat_decl_counter(ks_stats *reg, const ks_module_desc *m, const char *scope, const char *name,
                         const uint64_t *value);
int ks_stat_decl_real(ks_stats *reg, const ks_module_desc *m, const char *scope, const char *name,
                      const double *value);
int ks_stat_decl_formula(ks_stats *reg, const ks_module_desc *m, const char *scope, const char *name,
                         ks_formula_fn fn, void *user);
ks_histogram *ks_stat_decl_histogram(ks_stats *reg, const ks_module_desc *m, const char *scope, const char *name,
                                     double lo, double hi, unsigned bins);
/* numerator and denominator are names within the same scope */
int ks_stat_decl_ratio(ks_stats *reg, const ks_module_desc *m, const char *scope, const char *name,
                       const char *numerator, const char *denominator);
/* The KS_DESC_STAT item of m that name matches ('#', '*' as above), or NULL. */
const ks_desc_item *ks_desc_stat_match(const ks_module_desc *m, const char *name);
/* True when some statistic was registered from item `item` of m. */
bool ks_stats_registered_from(const ks_stats *reg, const ks_module_desc *m, const ks_desc_item *item);

/* Value of a statistic by name (histograms: their mean); 0 when found. */
int ks_stats_value(const ks_stats *reg, const char *name, double *out);
/* The same, or `fallback` when no statistic has that name. */
double ks_stats_value_or(const ks_stats *reg, const char *name, double fallback);
unsigned ks_stats_count(const ks_stats *reg);

/* 0 on success, -1 on a write error. */
int ks_stats_write_json(const ks_stats *reg, FILE *out);
int ks_stats_write_csv(const ks_stats *reg, FILE *out);
int ks_stats_write_summary(const ks_stats *reg, FILE *out);

#endif
