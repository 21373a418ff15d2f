/* module_desc.h — self-description of model modules.
 *
 * Contract: each module (a model/ source file) declares its parameters, ports and
 * statistics in one static table of ks_desc_item, terminated by an item
 * with kind KS_DESC_END, wrapped in a ks_module_desc with the module's name
 * and a one-line summary. A module whose parameters are configuration keys
 * does not list them as KS_DESC_PARAM rows: it names the configuration
 * sections that hold them (config_sections), whose schema is then the only
 * place a key's type, default, range, unit and source are written; the
 * kernel treats that field as text. From it, ks_module_desc_print writes --help-module
 * documentation; ks_module_desc_check validates a table (unique names, every
 * field filled where its kind needs it) so a unit test can keep tables honest.
 *
 *   static const ks_desc_item trv_items[] = {
 *     {KS_DESC_PARAM, "ray_slots", "int", "32", "1..1024", "rays in flight per TRV"},
 *     {KS_DESC_PORT,  "node_req", "out fifo<node_req>", "", "", "requests to the node L1"},
 *     {KS_DESC_STAT,  "node_visits", "visits", "", "", "nodes visited"},
 *     {KS_DESC_PART,  "fpu", "FPU", "", "", "slab tests: FLOPs per cycle; energy per FLOP"},
 *     {KS_DESC_END, 0, 0, 0, 0, 0}};
 *   const ks_module_desc trv_desc = {"trv", "BVH traversal unit", trv_items, NULL};
 */
#ifndef KS_MODULE_DESC_H
#define KS_MODULE_DESC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

typedef enum ks_desc_kind {
    KS_DESC_END = 0,
    KS_DESC_PARAM, /* type = value type ("int", "bool", "double", "enum a|b") */
    KS_DESC_PORT,  /* type = direction and channel ("in fifo<ray>") */
    KS_DESC_STAT,  /* type = unit ("cycles", "accesses") */
    KS_DESC_PART,  /* an energy and area part: type = its class ("FPU", "SRAM",
                      "DRAM"), desc = what sets its size and which activity
                      spends its energy */
} ks_desc_kind;

typedef struct ks_desc_item {
    ks_desc_kind kind;
    const char *name;
    const char *type;  /* value type, port type or stat unit */
    const char *def;   /* default value (params) */
    const char *range; /* allowed range (params), e.g. "1..1024", "power of two" */
    const char *desc;  /* one line */
} ks_desc_item;

typedef struct ks_module_desc {
    const char *name;
    const char *summary;
    const ks_desc_item *items; /* terminated by KS_DESC_END */
    /* comma-separated configuration sections holding the module's
     * parameters ("trv"; "node_l1,node_l2,prim" for the caches), or NULL */
    const char *config_sections;
} ks_module_desc;

/* Prints the documentation (sections Parameters, Ports, Statistics, Energy
 * and area parts); for config_sections, a line pointing at those sections,
 * whose keys the caller prints from their schemas. */
void ks_module_desc_print(const ks_module_desc *m, FILE *out);
/* Item of the given kind and name, or NULL. */
const ks_desc_item *ks_module_desc_find(const ks_module_desc *m, ks_desc_kind kind,
                                        const char *name);
size_t ks_module_desc_count(const ks_module_desc *m, ks_desc_kind kind);
/* True when section is one of m->config_sections. */
bool ks_module_desc_names_section(const ks_module_desc *m, const char *section);
/* 0 when valid, else -1 with a message naming the module and item in err. */
int ks_module_desc_check(const ks_module_desc *m, char *err, size_t cap);

#endif
