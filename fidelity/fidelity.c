/* fidelity.c — the public side of the fidelity levels (fidelity.h,
 * docs/fidelity.md): level names, the result's statistics, summary and JSON
 * strings, and fid_run, which runs one level (level_*.c, model_run.c) or the
 * automatic choice (accuracy.c) and registers the figures; the outcome's
 * summary and release. */
#include "fidelity/fidelity.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fidelity/fidelity_params.h"
#include "fidelity/levels.h"
#include "kernel/json.h"

static const char *const level_names[FID_LEVEL_COUNT] = {"full",    "fixed-mem", "functional",
                                                         "sampled", "windowed"};

const char *fid_level_name(fid_level l) { return l < FID_LEVEL_COUNT ? level_names[l] : "?"; }

bool fid_level_parse(const char *s, fid_level *out)
{
    for (int i = 0; i < FID_LEVEL_COUNT; i++)
        if (!strcmp(s, level_names[i])) {
            *out = (fid_level)i;
            return true;
        }
    return false;
}

bool fid_accuracy_parse(const char *s, double *fraction)
{
    char *end;
    if (!s || !*s)
        return false;
    double v = strtod(s, &end);
    if (end == s || (*end && strcmp(end, "%")) || !(v > 0) || v > 100)
        return false;
    *fraction = v / 100.0;
    return true;
}

void fid_result_full(fid_result *r)
{
    memset(r, 0, sizeof *r);
    r->level = FID_FULL;
}

/* ---- statistics, summary, JSON ---------------------------------------- */


static double pct_fn(const ks_stats *reg, void *user)
{
    (void)reg;
    return *(const double *)user * 100.0;
}

static double level_fn(const ks_stats *reg, void *user)
{
    (void)reg;
    return (double)((const fid_result *)user)->level;
}

static const ks_desc_item fid_items[] = {
    {KS_DESC_STAT, "fidelity_level", "level", "", "",
     "fidelity of the figures: 0 full, 1 fixed-mem, 2 functional, 3 sampled, 4 windowed (the string is "
     "\"fidelity\")"},
    {KS_DESC_STAT, "unreliable", "flag", "", "",
     "1 when a figure may lie outside its error estimate (reason: \"unreliable_reason\")"},
    {KS_DESC_STAT, "error_estimate.mrps", "%", "", "", "estimated relative error of mrps against the full model"},
    {KS_DESC_STAT, "error_estimate.dram_mb", "%", "", "",
     "estimated relative error of dram_bytes against the full model"},
    {KS_DESC_STAT, "error_estimate.energy_mj", "%", "", "",
     "estimated relative error of energy_mj against the full model"},
    {KS_DESC_END, 0, 0, 0, 0, 0}};
const ks_module_desc fid_module_desc = {"fidelity", "fidelity of a run's figures and their error estimates",
                                        fid_items, NULL};

int fid_register_stats(fid_result *r, ks_stats *st)
{
    const ks_module_desc *d = &fid_module_desc;
    int rc = 0;
    rc |= ks_stat_decl_formula(st, d, NULL, "fidelity_level", level_fn, r);
    rc |= ks_stat_decl_counter(st, d, NULL, "unreliable", &r->unreliable);
    rc |= ks_stat_decl_formula(st, d, NULL, "error_estimate.mrps", pct_fn, &r->err_mrps);
    rc |= ks_stat_decl_formula(st, d, NULL, "error_estimate.dram_mb", pct_fn, &r->err_dram_mb);
    rc |= ks_stat_decl_formula(st, d, NULL, "error_estimate.energy_mj", pct_fn, &r->err_energy_mj);
    return rc;
}

void fid_print_summary(const fid_result *r, FILE *out)
{
    fprintf(out, "fidelity    %s; error estimate MRPS %.1f%%, DRAM MB %.1f%%, mJ/frame %.1f%%%s\n",
            fid_level_name(r->level), 100.0 * r->err_mrps, 100.0 * r->err_dram_mb, 100.0 * r->err_energy_mj,
            r->unreliable ? "; UNRELIABLE" : "");
    if (r->unreliable)
        fprintf(out, "unreliable  %s\n", r->reason);
    if (r->detail[0])
        fprintf(out, "method      %s\n", r->detail);
    if (r->choice[0])
        fprintf(out, "accuracy    %s\n", r->choice);
}

void fid_print_steps(const fid_result *r, FILE *out)
{
    if (r->nsteps < 1)
        return;
    fprintf(out, "host        --accuracy's steps:");
    double before = 0;
    for (int i = 0; i < r->nsteps; i++) {
        fprintf(out, "%s %s %.3f s", i ? "," : "", r->steps[i].name, r->steps[i].cpu_s);
        if (i + 1 < r->nsteps)
            before += r->steps[i].cpu_s;
    }
    const fid_step *last = &r->steps[r->nsteps - 1];
    fprintf(out, " CPU");
    /* a fallback: what the steps before the full run cost on top of it */
    if (r->nsteps > 1 && r->level == FID_FULL)
        fprintf(out, " (before full: %.3f s, %.1f%% of it)", before, last->cpu_s > 0 ? 100.0 * before / last->cpu_s : 0.0);
    fputc('\n', out);
}

/* The level's JSON members; strings through the project's one escaping
 * (kernel/json.h: control characters as \u00XX). */
void fid_json_strings(const fid_result *r, char *buf, size_t len)
{
    char *text = NULL;
    size_t n = 0;
    FILE *m = open_memstream(&text, &n);
    if (!m) {
        if (len)
            buf[0] = 0;
        return;
    }
    fprintf(m, "  \"fidelity\": \"%s\",\n  \"unreliable_reason\": ", fid_level_name(r->level));
    ks_json_string(m, r->reason);
    fputs(",\n  \"fidelity_choice\": ", m);
    ks_json_string(m, r->choice);
    fputs(",\n", m);
    fclose(m);
    snprintf(buf, len, "%s", text ? text : "");
    free(text);
}

/* ---- results and outcomes ---------------------------------------------- */

/* A second reason is appended, not dropped: each check that failed is named. */
void fid_set_unreliable(fid_result *r, const char *why)
{
    if (!r->unreliable)
        snprintf(r->reason, sizeof r->reason, "%s", why);
    else {
        size_t n = strlen(r->reason);
        snprintf(r->reason + n, sizeof r->reason - n, "; %s", why);
    }
    r->unreliable = 1;
}

double fid_lv_worst(const fid_result *r)
{
    return fmax(r->err_mrps, fmax(r->err_dram_mb, r->err_energy_mj));
}

/* An empty outcome with its own figures' storage (any storage it had freed
 * first): for one level's run, and for each of --accuracy's trials. 0, or
 * -1 with a message when out of memory. */
int fid_lv_fresh_trial(fid_outcome *t, double acc, char *err, size_t errlen)
{
    free(t->own);
    memset(t, 0, sizeof *t);
    if (!(t->own = calloc(1, sizeof *t->own))) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    t->res.accuracy = acc;
    return 0;
}

int fid_run(const fid_job *job, fid_level level, double accuracy, fid_outcome *o, char *err, size_t errlen)
{
    memset(o, 0, sizeof *o);
    int rc;
    if (accuracy > 0) {
        rc = fid_accuracy_run(job, accuracy, o, err, errlen);
        o->res.accuracy = accuracy;
    } else {
        if (fid_lv_fresh_trial(o, 0, err, errlen))
            return 2;
        fid_func ff;
        memset(&ff, 0, sizeof ff);
        switch (level) {
        case FID_FIXED_MEM: rc = fid_lv_fixed_mem(job, o, err, errlen); break;
        case FID_FUNCTIONAL: rc = fid_lv_functional(job, o, &ff, err, errlen); break;
        case FID_WINDOWED: rc = fid_lv_windowed(job, job->sample_rate, job->windows, o, err, errlen); break;
        case FID_SAMPLED:
            rc = fid_lv_sampled(job, job->sample_rate > 0 ? job->sample_rate : fid_params_get()->sample_rate, o, &ff,
                             err, errlen);
            break;
        default: rc = fid_lv_full(job, o, err, errlen); break;
        }
    }
    if (rc == 0 || o->top) {
        if (o->top) {
            ks_stats *st = accel_top_stats(o->top);
            model_fig f;
            fid_get_fig(o->top, &f);
            o->cycles = f.cycles, o->rays = f.rays, o->mrps = f.mrps, o->dram_bytes = f.dram_bytes,
            o->energy_mj = f.energy_mj;
            if (fid_register_stats(&o->res, st)) {
                snprintf(err, errlen, "fidelity statistics: %s", ks_stats_error(st));
                return 2;
            }
        } else if (o->own && fid_own_stats(o)) {
            snprintf(err, errlen, "fidelity statistics: %s", o->stats ? ks_stats_error(o->stats) : "out of memory");
            return 2;
        }
    }
    return rc;
}

ks_stats *fid_outcome_stats(fid_outcome *o) { return o->top ? accel_top_stats(o->top) : o->stats; }

void fid_outcome_print(fid_outcome *o, FILE *out)
{
    if (o->top) {
        accel_top_print_summary(o->top, out);
        return;
    }
    fid_own *w = o->own;
    if (!w)
        return;
    fprintf(out, "cycles      %llu (estimated)\n", (unsigned long long)w->cycles);
    fprintf(out, "rays        %llu (%llu primary, %llu bounce)\n", (unsigned long long)w->rays,
            (unsigned long long)w->primaries, (unsigned long long)w->bounces);
    fprintf(out, "MRPS        %.2f (estimated)\n", w->mrps);
    if (w->has_func) {
        fprintf(out, "bounds      trv %.0f, ist %.0f, dram %.0f, latency %.0f cycles: %s-bound\n", w->cyc_trv,
                w->cyc_ist, w->cyc_dram, w->cyc_lat, w->bound ? w->bound : "?");
        fprintf(out, "caches      node L1 %.2f%% hits, node L2 %.2f%%, prim %.2f%%; DRAM rows %.1f%% hits (functional)\n",
                100 * w->l1_hit, 100 * w->l2_hit, 100 * w->prim_hit, 100 * w->row_hit);
    }
    fprintf(out, "DRAM        %.2f MB, %.2f GB/s (estimated)\n", (double)w->dram_bytes / 1e6, w->dram_gbs);
    fprintf(out, "energy      %.4g mJ/frame (estimated)\n", w->energy_mj);
}

void fid_outcome_free(fid_outcome *o)
{
    accel_top_destroy(o->top);
    if (o->stats)
        ks_stats_destroy(o->stats);
    free(o->own);
    memset(o, 0, sizeof *o);
}
