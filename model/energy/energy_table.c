/* energy_table.c — SRAM and FPU figures and the matching rule (see energy_table.h). */
#include "model/energy/energy_table.h"

#include "config/ini_file.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Scaling limit of the matching rule (energy_table.h): a row stands for
 * structures up to 4x larger or smaller in size and in word width. Beyond
 * that CACTI picks other array organisations and the square-root law is no
 * longer a fair guess. */
#define ENERGY_SCALE_LIMIT 4.0

typedef struct loader {
    energy_table *t;
    unsigned seen[ENERGY_MAX_ROWS]; /* bit per SRAM key below */
    unsigned fpu_seen;
} loader;

static const char *const sram_keys[] = {"kind", "size", "ways", "line", "ports", "area", "read", "write", "leak"};
#define N_SRAM_KEYS 9

static int parse_positive(ini_file *f, const char *name, const char *value, double *out)
{
    double v;
    if (ini_file_number(value, &v) || !(v > 0 && v < 1e12))
        return ini_file_error(f, "%s = '%s' invalid, allowed a number > 0", name, value);
    *out = v;
    return 0;
}

static int multiport_handler(ini_file *f, loader *L, const char *name, const char *value)
{
    energy_multiport *m = &L->t->mp;
    static const char *const keys[] = {"ports", "area", "read", "write", "leak"};
    double *dst[] = {&m->p0, &m->area, &m->read, &m->write, &m->leak};
    const int k = ini_file_key_index(f, "multiport", name, keys, 5);
    return k < 0 ? -1 : parse_positive(f, name, value, dst[k]);
}

static int sram_handler(ini_file *f, void *user, const char *section, const char *name, const char *value)
{
    loader *L = user;
    energy_table *t = L->t;
    if (!strcmp(section, "multiport"))
        return multiport_handler(f, L, name, value);
    int r = t->nrows - 1;
    if (r < 0 || strcmp(t->rows[r].name, section) != 0) {
        for (int i = 0; i < t->nrows; i++)
            if (strcmp(t->rows[i].name, section) == 0)
                return ini_file_error(f, "section [%s] appears twice", section);
        if (t->nrows == ENERGY_MAX_ROWS)
            return ini_file_error(f, "more than %d rows (section [%s])", ENERGY_MAX_ROWS, section);
        if (strlen(section) >= sizeof t->rows[0].name)
            return ini_file_error(f, "section name [%s] longer than %d characters", section,
                                  (int)sizeof t->rows[0].name - 1);
        r = t->nrows++;
        memset(&t->rows[r], 0, sizeof t->rows[r]);
        snprintf(t->rows[r].name, sizeof t->rows[r].name, "%s", section);
        L->seen[r] = 0;
    }
    energy_sram *row = &t->rows[r];
    const int k = ini_file_key_index(f, section, name, sram_keys, N_SRAM_KEYS);
    if (k < 0)
        return -1;
    L->seen[r] |= 1u << k;
    switch (k) {
    case 0:
        if (strcmp(value, "cache") == 0)
            row->kind = ENERGY_CACHE;
        else if (strcmp(value, "ram") == 0)
            row->kind = ENERGY_RAM;
        else
            return ini_file_error(f, "kind = '%s' invalid, allowed cache|ram", value);
        return 0;
    case 4:
        if (strcmp(value, "1rw") == 0)
            row->ports = ENERGY_1RW;
        else if (strcmp(value, "1r1w") == 0)
            row->ports = ENERGY_1R1W;
        else
            return ini_file_error(f, "ports = '%s' invalid, allowed 1rw|1r1w", value);
        return 0;
    case 1: return parse_positive(f, name, value, &row->size);
    case 2: return parse_positive(f, name, value, &row->ways);
    case 3: return parse_positive(f, name, value, &row->line);
    case 5: return parse_positive(f, name, value, &row->area_mm2);
    case 6: return parse_positive(f, name, value, &row->read_nj);
    case 7: return parse_positive(f, name, value, &row->write_nj);
    default: return parse_positive(f, name, value, &row->leak_mw);
    }
}

static const char *const fpu_keys[] = {"energy_pj_per_flop", "area_mm2_per_flop_unit", "leak_mw_per_flop_unit"};

static int fpu_handler(ini_file *f, void *user, const char *section, const char *name, const char *value)
{
    loader *L = user;
    double *dst[] = {&L->t->fpu.energy_pj_per_flop, &L->t->fpu.area_mm2_per_flop_unit,
                     &L->t->fpu.leak_mw_per_flop_unit};
    const int k = ini_file_key_index(f, section, name, fpu_keys, 3);
    if (k < 0)
        return -1;
    L->fpu_seen |= 1u << k;
    return parse_positive(f, name, value, dst[k]);
}

int energy_table_load(energy_table *t, const char *sram_path, const char *fpu_path, char *err, size_t errlen)
{
    memset(t, 0, sizeof *t);
    if (strlen(sram_path) >= sizeof t->sram_path || strlen(fpu_path) >= sizeof t->fpu_path) {
        snprintf(err, errlen, "%s, %s: path longer than %zu characters", sram_path, fpu_path, sizeof t->sram_path - 1);
        return -1;
    }
    snprintf(t->sram_path, sizeof t->sram_path, "%s", sram_path);
    snprintf(t->fpu_path, sizeof t->fpu_path, "%s", fpu_path);
    loader L = {.t = t};
    static const ini_file_opts sram_opts = {.what = "an SRAM energy table", .example = "l1node_bvh"};
    if (ini_file_read(sram_path, &sram_opts, sram_handler, &L, err, errlen))
        return -1;
    if (t->nrows == 0) {
        snprintf(err, errlen, "%s: no SRAM rows", sram_path);
        return -1;
    }
    if (t->mp.p0 != 0 && !(t->mp.p0 >= 2 && t->mp.area > 0 && t->mp.read > 0 && t->mp.write > 0 && t->mp.leak > 0)) {
        snprintf(err, errlen, "%s: [multiport] needs ports >= 2 and area, read, write, leak > 0", sram_path);
        return -1;
    }
    for (int r = 0; r < t->nrows; r++) {
        unsigned need = (1u << N_SRAM_KEYS) - 1;
        if (t->rows[r].kind == ENERGY_RAM)
            need &= ~(1u << 2); /* ways: caches only */
        for (int k = 0; k < N_SRAM_KEYS; k++)
            if ((need >> k & 1) && !(L.seen[r] >> k & 1)) {
                snprintf(err, errlen, "%s: [%s] lacks key %s", sram_path, t->rows[r].name, sram_keys[k]);
                return -1;
            }
    }
    static const ini_file_opts fpu_opts = {.what = "an FPU energy table", .section = "fpu"};
    if (ini_file_read(fpu_path, &fpu_opts, fpu_handler, &L, err, errlen))
        return -1;
    for (int k = 0; k < 3; k++)
        if (!(L.fpu_seen >> k & 1)) {
            snprintf(err, errlen, "%s: [fpu] lacks key %s (a number > 0)", fpu_path, fpu_keys[k]);
            return -1;
        }
    return 0;
}

static const char *kind_name(energy_kind k) { return k == ENERGY_CACHE ? "cache" : "ram"; }
static const char *ports_name(energy_ports p) { return p == ENERGY_1RW ? "1rw" : "1r1w"; }

/* The rule of energy_table.h without the node-word interpolation. */
static int figure_of_row_line(const energy_table *t, const energy_sram_req *req, energy_sram *out, char *err,
                              size_t errlen)
{
    int best = -1;
    double best_d = 0;
    char offer[512] = "";
    size_t used = 0;
    for (int r = 0; r < t->nrows; r++) {
        const energy_sram *row = &t->rows[r];
        if (row->kind != req->kind || row->ports != req->ports)
            continue;
        if (req->kind == ENERGY_CACHE && (row->line != req->line || row->ways != req->ways))
            continue;
        if (used < sizeof offer - 64)
            used += (size_t)snprintf(offer + used, sizeof offer - used, "%s[%s] %.0f B x %.0f B", used ? ", " : "",
                                     row->name, row->size, row->line);
        double s = req->size / row->size, w = req->line / row->line;
        /* RAMs may be any smaller size (auto-sized FIFOs of a few entries):
         * the laws then overestimate, never underestimate */
        double s_min = req->kind == ENERGY_RAM ? 0 : 1 / ENERGY_SCALE_LIMIT;
        if (s <= 0 || s < s_min || s > ENERGY_SCALE_LIMIT || w > ENERGY_SCALE_LIMIT || w < 1 / ENERGY_SCALE_LIMIT)
            continue;
        double d = fabs(log(s)) + fabs(log(w));
        if (best < 0 || d < best_d) {
            best = r;
            best_d = d;
        }
    }
    if (best < 0) {
        if (req->kind == ENERGY_CACHE)
            snprintf(err, errlen,
                     "%s: no SRAM figure for a %.0f-byte %s (%.0f-way, %.0f-byte line, %s) in %s: rows of that "
                     "line, ways and ports: %s; a row covers sizes within 4x",
                     req->what, req->size, kind_name(req->kind), req->ways, req->line, ports_name(req->ports),
                     t->sram_path, *offer ? offer : "none");
        else
            snprintf(err, errlen,
                     "%s: no SRAM figure for a %.0f-byte %s of %.0f-byte words (%s) in %s: rows of that kind and "
                     "ports: %s; a row covers sizes and word widths within 4x",
                     req->what, req->size, kind_name(req->kind), req->line, ports_name(req->ports), t->sram_path,
                     *offer ? offer : "none");
        return -1;
    }
    const energy_sram *row = &t->rows[best];
    double s = req->size / row->size, w = req->line / row->line, e = sqrt(s * w);
    *out = *row;
    out->size = req->size;
    out->line = req->line;
    out->ways = req->kind == ENERGY_CACHE ? req->ways : 0;
    out->area_mm2 = row->area_mm2 * s;
    out->leak_mw = row->leak_mw * s;
    out->read_nj = row->read_nj * e;
    out->write_nj = row->write_nj * e;
    return 0;
}

int energy_sram_ports(const energy_table *t, const char *what, unsigned ports, energy_sram *fig, char *err,
                      size_t errlen)
{
    if (ports <= 1)
        return 0;
    if (t->mp.p0 < 2) {
        snprintf(err, errlen, "%s: %u ports, but %s has no [multiport] figure (1-port arrays only)", what, ports,
                 t->sram_path);
        return -1;
    }
    double e = log((double)ports) / log(t->mp.p0);
    fig->area_mm2 *= pow(t->mp.area, e);
    fig->read_nj *= pow(t->mp.read, e);
    fig->write_nj *= pow(t->mp.write, e);
    fig->leak_mw *= pow(t->mp.leak, e);
    return 0;
}

/* Node-word rule (energy_table.h): an index-addressed cache's word, a node
 * of N x 32 B, is a line width the CACTI rows may lack (96, 160, 192, 224,
 * 256 B against rows of 64 and 128 B). Each figure is interpolated linearly
 * in the line width between the two neighbouring widths the table covers at
 * this size and ways (each first scaled to the size by the rule above), or
 * extrapolated from the two nearest when the word lies outside them, at most
 * ENERGY_NODE_WORD_REACH times beyond (a 256 B word from 64 and 128 B rows).
 * Linear in the width because CACTI's cache rows are: between a 64 and a
 * 128 B line the 16 KB L1 grows in area 0.0827 -> 0.1524 mm2 and in read
 * energy 0.0335 -> 0.0424 nJ with the port and sense amplifiers, which grow
 * with the bits per access (model/data/energy/sram_45nm.ini). */
#define ENERGY_NODE_WORD_REACH 2.0

int energy_sram_figure(const energy_table *t, const energy_sram_req *req, energy_sram *out, char *err,
                       size_t errlen)
{
    if (!(req->kind == ENERGY_CACHE && req->node_word))
        return figure_of_row_line(t, req, out, err, errlen);
    char why[4096 + 1024];   /* names the table's file: a whole path (PATH_MAX) and the reason */
    if (figure_of_row_line(t, req, out, why, sizeof why) == 0)
        return 0;
    /* the line widths of the candidate rows, ascending, that cover this size */
    double width[ENERGY_MAX_ROWS];
    energy_sram fig[ENERGY_MAX_ROWS];
    int n = 0;
    for (int r = 0; r < t->nrows; r++) {
        const energy_sram *row = &t->rows[r];
        if (row->kind != req->kind || row->ports != req->ports || row->ways != req->ways)
            continue;
        int k = 0;
        while (k < n && width[k] < row->line)
            k++;
        if (k < n && width[k] == row->line)
            continue;
        energy_sram_req at = *req;
        at.line = row->line;
        at.node_word = 0;
        energy_sram f;
        char ignore[8];
        if (figure_of_row_line(t, &at, &f, ignore, sizeof ignore))
            continue;
        memmove(width + k + 1, width + k, (size_t)(n - k) * sizeof *width);
        memmove(fig + k + 1, fig + k, (size_t)(n - k) * sizeof *fig);
        width[k] = row->line;
        fig[k] = f;
        n++;
    }
    int a = -1;   /* the pair (a, a + 1) */
    if (n >= 2) {
        a = 0;
        while (a + 2 < n && width[a + 1] < req->line)
            a++;
        double lo = width[0], hi = width[n - 1];
        if (req->line > hi * ENERGY_NODE_WORD_REACH || req->line < lo / ENERGY_NODE_WORD_REACH)
            a = -1;
    }
    if (a < 0) {
        snprintf(err, errlen,
                 "%s; a node-sized word is interpolated in the line width between two rows of its size, ways and "
                 "ports, or extrapolated up to %gx beyond them: %d such row width(s)",
                 why, ENERGY_NODE_WORD_REACH, n);
        return -1;
    }
    const double f = (req->line - width[a]) / (width[a + 1] - width[a]);
    const energy_sram *x = &fig[a], *y = &fig[a + 1];
    *out = *x;
    snprintf(out->name, sizeof out->name, "%.20s~%.20s", x->name, y->name);
    out->line = req->line;
    out->area_mm2 = x->area_mm2 + f * (y->area_mm2 - x->area_mm2);
    out->read_nj = x->read_nj + f * (y->read_nj - x->read_nj);
    out->write_nj = x->write_nj + f * (y->write_nj - x->write_nj);
    out->leak_mw = x->leak_mw + f * (y->leak_mw - x->leak_mw);
    if (!(out->area_mm2 > 0 && out->read_nj > 0 && out->write_nj > 0 && out->leak_mw > 0)) {
        snprintf(err, errlen,
                 "%s: a %.0f-byte node word extrapolated from the %.0f and %.0f B rows of %s gives a figure <= 0 "
                 "(area %g mm2, read %g nJ, write %g nJ, leak %g mW)",
                 req->what, req->line, width[a], width[a + 1], t->sram_path, out->area_mm2, out->read_nj,
                 out->write_nj, out->leak_mw);
        return -1;
    }
    return 0;
}
