/* module_desc.c — printing and checking module description tables
 * (contract in module_desc.h). */
#include <string.h>

#include "kernel/module_desc.h"

static const char *nz(const char *s) { return s ? s : ""; }

size_t ks_module_desc_count(const ks_module_desc *m, ks_desc_kind kind)
{
    size_t n = 0;
    for (const ks_desc_item *it = m->items; it && it->kind != KS_DESC_END; it++)
        n += it->kind == kind;
    return n;
}

const ks_desc_item *ks_module_desc_find(const ks_module_desc *m, ks_desc_kind kind,
                                        const char *name)
{
    for (const ks_desc_item *it = m->items; it && it->kind != KS_DESC_END; it++)
        if (it->kind == kind && it->name && !strcmp(it->name, name))
            return it;
    return NULL;
}

bool ks_module_desc_names_section(const ks_module_desc *m, const char *section)
{
    size_t n = strlen(section);
    for (const char *c = m->config_sections; c && *c; c = strchr(c, ',') ? strchr(c, ',') + 1 : NULL)
        if (!strncmp(c, section, n) && (c[n] == ',' || c[n] == 0))
            return true;
    return false;
}

static void section(const ks_module_desc *m, ks_desc_kind kind, const char *title, FILE *o)
{
    if (!ks_module_desc_count(m, kind))
        return;
    int wn = 4, wt = 4;
    for (const ks_desc_item *it = m->items; it->kind != KS_DESC_END; it++) {
        if (it->kind != kind)
            continue;
        int l = (int)strlen(nz(it->name));
        if (l > wn)
            wn = l;
        l = (int)strlen(nz(it->type));
        if (l > wt)
            wt = l;
    }
    fprintf(o, "  %s:\n", title);
    for (const ks_desc_item *it = m->items; it->kind != KS_DESC_END; it++) {
        if (it->kind != kind)
            continue;
        fprintf(o, "    %-*s  %-*s  %s", wn, nz(it->name), wt, nz(it->type), nz(it->desc));
        if (kind == KS_DESC_PARAM) {
            if (it->def && *it->def)
                fprintf(o, " (default %s", it->def);
            if (it->range && *it->range)
                fprintf(o, "%s%s", it->def && *it->def ? "; range " : " (range ", it->range);
            if ((it->def && *it->def) || (it->range && *it->range))
                fputc(')', o);
        }
        fputc('\n', o);
    }
}

void ks_module_desc_print(const ks_module_desc *m, FILE *o)
{
    fprintf(o, "%s — %s\n", nz(m->name), nz(m->summary));
    section(m, KS_DESC_PARAM, "Parameters (--set <module>.<name>=VALUE)", o);
    if (m->config_sections && *m->config_sections) {
        fprintf(o, "  Parameters: the configuration keys of [");
        for (const char *c = m->config_sections; *c; c++)
            fputs(*c == ',' ? "], [" : (char[]){*c, 0}, o);
        fprintf(o, "] (below; --set SECTION.KEY=VALUE)\n");
    }
    section(m, KS_DESC_PORT, "Ports", o);
    section(m, KS_DESC_STAT, "Statistics (name, unit, meaning)", o);
    section(m, KS_DESC_PART, "Energy and area parts (name, class, size and activity)", o);
}

int ks_module_desc_check(const ks_module_desc *m, char *err, size_t cap)
{
    if (!m->name || !*m->name || !m->summary || !*m->summary) {
        snprintf(err, cap, "module description without a name or summary");
        return -1;
    }
    if (!m->items) {
        snprintf(err, cap, "module %s: no item table", m->name);
        return -1;
    }
    for (const ks_desc_item *it = m->items; it->kind != KS_DESC_END; it++) {
        size_t idx = (size_t)(it - m->items);
        if (it->kind < KS_DESC_PARAM || it->kind > KS_DESC_PART) {
            snprintf(err, cap, "module %s: item %zu has an unknown kind %d", m->name, idx, (int)it->kind);
            return -1;
        }
        if (!it->name || !*it->name) {
            snprintf(err, cap, "module %s: item %zu has no name", m->name, idx);
            return -1;
        }
        if (!it->type || !*it->type) {
            snprintf(err, cap, "module %s: %s has no %s", m->name, it->name,
                     it->kind == KS_DESC_STAT ? "unit" : "type");
            return -1;
        }
        if (!it->desc || !*it->desc || strchr(it->desc, '\n')) {
            snprintf(err, cap, "module %s: %s needs a one-line description", m->name, it->name);
            return -1;
        }
        if (it->kind == KS_DESC_PARAM && (!it->def || !*it->def)) {
            snprintf(err, cap, "module %s: parameter %s has no default", m->name, it->name);
            return -1;
        }
        for (const ks_desc_item *jt = m->items; jt != it; jt++)
            if (jt->kind == it->kind && !strcmp(jt->name, it->name)) {
                snprintf(err, cap, "module %s: %s declared twice", m->name, it->name);
                return -1;
            }
    }
    return 0;
}
