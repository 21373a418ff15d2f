/* accuracy.c — --accuracy P%: the cheapest level expected within P%
 * (docs/fidelity.md "--accuracy P%"), from the levels' runs (levels.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fidelity/estimator.h"
#include "fidelity/fidelity_params.h"
#include "fidelity/functional.h"
#include "fidelity/levels.h"
#include "fidelity/windowed.h"
#include "kernel/fork_pool.h"

/* How many times its windows a windowed estimate would need for every
 * headline figure to come within acc (at least 1): the windows' intervals
 * (ci) shrink as 1 / sqrt(windows); the lattice's and the start's errors
 * (other) and the bias bounds do not, so they may leave a figure too
 * little room: when the interval may grow only to a square of at most
 * min_room2, returns 0 and *blocking is that figure (else -1). */
static double windows_factor(const double *ci, const double *other, const double *bias, double acc,
                             double min_room2, int *blocking)
{
    double scale = 1;
    *blocking = -1;
    for (int k = 0; k < FID_WIN_HEADLINE; k++) {
        double rest = acc - bias[k], room2 = rest * rest - other[k] * other[k];
        if (rest <= 0 || room2 <= min_room2) {
            *blocking = k;
            return 0;
        }
        scale = fmax(scale, ci[k] * ci[k] / room2);
    }
    return scale;
}

/* What the plan would need to meet acc, for the user to choose a target
 * (ci already scaled to the plan's windows; windows_factor). plan_share:
 * the plan's pixels through the model, a fraction of the frame. */
static void windowed_need(const double *ci, const double *other, const double *bias, double acc,
                          double plan_share, char *out, size_t len)
{
    static const char *const fig_name[FID_WIN_HEADLINE] = {"MRPS", "DRAM MB", "mJ/frame"};
    int k;
    double scale = windows_factor(ci, other, bias, acc, 0, &k);
    if (k >= 0)
        snprintf(out, len, "; its lattice and bias errors alone are %.1f%% on %s", 100 * (bias[k] + other[k]),
                 fig_name[k]);
    else if (scale * plan_share > 1)
        snprintf(out, len, "; %.3g%% would need about %.1fx the plan's windows, more than the frame holds", 100 * acc,
                 scale);
    else
        snprintf(out, len, "; %.3g%% would need about %.1fx the plan's windows (%.0f%% of the frame through the model)",
                 100 * acc, scale, 100 * scale * plan_share);
}

/* The steps run so far and the CPU when the last one ended. */
typedef struct acc_steps {
    fid_step s[FID_MAX_STEPS];
    int n;
    double t;
} acc_steps;

/* The step that ran since the last one ended, of `cpu_s` (< 0: all of it). */
static void step_add(acc_steps *st, const char *name, double cpu_s)
{
    const double now = ks_pool_process_cpu_s();
    if (cpu_s < 0)
        cpu_s = now - st->t;
    if (st->n < FID_MAX_STEPS)
        st->s[st->n++] = (fid_step){name, cpu_s};
    st->t += cpu_s;
}

/* The steps into the result of the level picked (fid_result.steps). */
static void set_steps(fid_outcome *o, const acc_steps *st)
{
    memcpy(o->res.steps, st->s, sizeof st->s);
    o->res.nsteps = st->n;
}

/* The windowed pilot's step, split into its lattice and its windows. */
static void step_pilot(acc_steps *st, const fid_windowed *wd)
{
    step_add(st, "windowed's lattice", wd->lattice_cpu_s);
    step_add(st, "windowed's pilot windows", -1);
}

/* --accuracy, its first stage, spending little before it knows (a
 * fallback to full should cost at most a few percent over a plain full run):
 *   1. a cold probe: one window after a win_warm_pixels warm-up from empty
 *      caches (about 0.5% of a 1280x720 frame): where most of its fills are
 *      still cold, the caches keep their lines for most of the frame
 *      (primary rays: 43-100%), no window stands for the frame: give up;
 *   2. a pilot: the lattice and the first win_pilot_windows windows of the
 *      plan (kept if it goes on); its interval, scaled to the plan's
 *      windows (1 / sqrt(windows) and the t of the pairs), predicts the
 *      plan's estimate: beyond the target, give up; but when the low 95%
 *      bound of the pilot's spread (fid_spread_low95) would still meet
 *      it, first grow the pilot once to twice its windows and predict
 *      again;
 *   3. the plan; within the target and not flagged: windowed; else once
 *      more windows when the interval says at most twice the windows will
 *      do, within win_max_rate of the frame.
 * 0 and *picked when it meets acc; why: what it found otherwise; steps:
 * each of these it ran, with its CPU. */
static int auto_windowed(const fid_job *job, double acc, fid_outcome *o, bool *picked, char *why, size_t whylen,
                         acc_steps *steps, char *err, size_t errlen)
{
    const fid_params *fp = fid_params_get();
    fid_windowed wd = {0};
    *picked = false;
    char small[256];
    if (!fid_windowed_fits(job, job->sample_rate, job->windows, small, sizeof small)) {
        snprintf(why, whylen, "windowed not tried: %s", small);
        return 0;
    }
    double cold = 0, turnover = 0;
    int rc = fid_windowed_cold_probe(job, &cold, &turnover, err, errlen);
    step_add(steps, "windowed's probe", -1);
    if (rc)
        return rc;
    if (turnover < fp->win_probe_min_turnover) {
        snprintf(why, whylen,
                 "windowed's probe: the frame refills its node L2 and primitive cache about %.1f times (at least "
                 "%.0f: below it the caches keep their lines for most of the frame, and no window stands for it)",
                 turnover, fp->win_probe_min_turnover);
        return 0;
    }
    if (cold > fp->win_probe_max_cold) {
        snprintf(why, whylen,
                 "windowed's probe: %.1f%% of the fills cold after a %.0f-pixel warm-up from empty caches (at most "
                 "%.0f%%: the caches keep their lines for most of the frame)",
                 100.0 * cold, fp->win_warm_pixels, 100.0 * fp->win_probe_max_cold);
        return 0;
    }
    rc = fid_windowed_probe(job, job->sample_rate, job->windows, (uint32_t)fp->win_pilot_windows, &wd, err, errlen);
    double npix = (double)job->width * job->height;
    while (rc == 0 && wd.windows < wd.planned) {
        fid_lv_windowed_outcome(job, &wd, o);
        double e[FID_WIN_FIGS], ci[FID_WIN_FIGS], other[FID_WIN_FIGS], bias[FID_WIN_FIGS], worst_pred = 0, worst_low = 0;
        fid_lv_windowed_errors(&wd, e, ci, other, bias);
        int pairs = (int)(wd.windows / 2 + wd.windows % 2);
        double shrink = sqrt((double)wd.windows / wd.planned) * fid_t95((int)(wd.planned / 2 + wd.planned % 2)) /
                        fid_t95(pairs);
        for (int k = 0; k < FID_WIN_HEADLINE; k++) {
            ci[k] *= shrink;   /* the plan's */
            worst_pred = fmax(worst_pred, sqrt(ci[k] * ci[k] + other[k] * other[k]) + bias[k]);
            double lo = ci[k] * fid_spread_low95(pairs);
            worst_low = fmax(worst_low, sqrt(lo * lo + other[k] * other[k]) + bias[k]);
        }
        bool cold_flag = wd.cold_share > fp->win_max_cold;
        /* beyond the target, but not even at the low bound of the pilot's
         * spread: a few pairs misjudge it (fairy BVH2 diffuse: 7.4% predicted
         * from 8 windows, 3.8% with the plan's 48), so the pilot grows once */
        uint32_t grown = 2 * (uint32_t)fp->win_pilot_windows;
        if (!cold_flag && worst_pred > acc && worst_low <= acc && wd.windows < grown && grown < wd.planned) {
            rc = fid_windowed_more(job, grown, &wd, err, errlen);
            continue;
        }
        if (cold_flag || worst_pred > acc) {
            char need[160] = "";
            if (!cold_flag)
                windowed_need(ci, other, bias, acc, (double)wd.planned * (wd.window_pixels + wd.warm_pixels) / npix,
                              need, sizeof need);
            step_pilot(steps, &wd);
            snprintf(why, whylen,
                     "windowed's pilot of %u windows (%.1f%% of the pixels through the model): %s %.1f%%%s%s",
                     wd.windows, 100.0 * wd.model_pixels / npix,
                     cold_flag ? "cold fills" : "estimated error with the plan's windows about",
                     cold_flag ? 100.0 * wd.cold_share : 100.0 * worst_pred, cold_flag ? " (warm-ups too short)" : "",
                     need);
            fid_windowed_free(&wd);
            return 0;
        }
        step_pilot(steps, &wd);
        rc = fid_windowed_more(job, wd.planned, &wd, err, errlen);
    }
    for (int step = 0; rc == 0; step++) {
        fid_lv_windowed_outcome(job, &wd, o);
        double w = fid_lv_worst(&o->res);
        if (!o->res.unreliable && w <= acc) {
            *picked = true;
            snprintf(o->res.choice, sizeof o->res.choice,
                     "--accuracy %.3g%%: picked windowed, %u windows (%.1f%% of the pixels through the model; "
                     "estimated error %.1f%%)",
                     100 * acc, wd.windows, 100.0 * wd.model_pixels / npix, 100 * w);
            break;
        }
        size_t n = strlen(why);
        snprintf(why + n, whylen - n, "%swindowed with %u windows: %.1f%%%s", n ? ", " : "", wd.windows, 100 * w,
                 o->res.unreliable ? " (flagged)" : "");
        if (step == 1 || wd.too_small || wd.cold_share > fp->win_max_cold)
            break;
        /* the interval shrinks as 1 / sqrt(windows); the rest does not:
         * the interval may grow to sqrt((acc - bias)^2 - other^2). Only a
         * need of at most twice the windows is tried: beyond it the
         * attempt would cost more than it is likely to save */
        double e[FID_WIN_FIGS], ci[FID_WIN_FIGS], other[FID_WIN_FIGS], bias[FID_WIN_FIGS];
        fid_lv_windowed_errors(&wd, e, ci, other, bias);
        int blocking;
        double scale = windows_factor(ci, other, bias, acc, 0.01 * acc * acc, &blocking);
        double per = (double)(wd.window_pixels + wd.warm_pixels) / npix;
        if (scale <= 0 || scale > 2.0)
            break;
        uint32_t more = (uint32_t)ceil(fmax(scale * 1.2, 1.25) * wd.windows / 2) * 2;   /* whole pairs */
        if (more * per > fp->win_max_rate)
            more = (uint32_t)floor(fp->win_max_rate / per / 2) * 2;
        if (more <= wd.windows)
            break;
        rc = fid_windowed_more(job, more, &wd, err, errlen);
    }
    step_add(steps, "windowed's plan", -1);
    fid_windowed_free(&wd);
    return rc;
}

/* --accuracy: windowed when its estimates fit (with more windows if its
 * interval says so, auto_windowed); else functional when its estimates
 * fit; else sampled, at a rate raised (once) to what its first interval
 * says the bound needs; else full (docs/fidelity.md "--accuracy P%"). */
int fid_accuracy_run(const fid_job *job, double acc, fid_outcome *o, char *err, size_t errlen)
{
    const fid_params *fp = fid_params_get();
    fid_func ff;
    memset(&ff, 0, sizeof ff);
    fid_outcome trial = {0};
    if (fid_lv_fresh_trial(&trial, acc, err, errlen))
        return 2;
    char why[480] = "";
    int rc = 0;
    /* A level whose estimate can never come under the target is not tried:
     * its error floor is known before it runs (functional: func_err_base on
     * MRPS; sampled: the floor plus the DRAM bias bound on DRAM MB;
     * fidelity_params.h). Trying it anyway made --accuracy 2% cost 1.3-1.7x a
     * full run (docs/fidelity.md). */
    double func_floor = fp->func_err_base, sample_floor = fp->sample_err_floor + fp->sample_err_dram;
    bool picked;
    acc_steps steps = {.t = ks_pool_process_cpu_s()};
    if ((rc = auto_windowed(job, acc, &trial, &picked, why, sizeof why, &steps, err, errlen)))
        goto out;
    if (picked) {
        *o = trial;
        set_steps(o, &steps);
        return 0;
    }
    if (fid_lv_fresh_trial(&trial, acc, err, errlen))
        return 2;
    if (acc >= func_floor) {
        if ((rc = fid_lv_functional(job, &trial, &ff, err, errlen)))
            goto out;
        step_add(&steps, "functional", -1);
        if (!trial.res.unreliable && fid_lv_worst(&trial.res) <= acc) {
            *o = trial;
            set_steps(o, &steps);
            snprintf(o->res.choice, sizeof o->res.choice,
                     "--accuracy %.3g%%: picked functional (estimated error %.1f%%)", 100 * acc, 100 * fid_lv_worst(&o->res));
            return 0;
        }
        size_t n = strlen(why);
        snprintf(why + n, sizeof why - n, "; functional's estimate %.1f%%%s", 100 * fid_lv_worst(&trial.res),
                 trial.res.unreliable ? " (flagged)" : "");
    } else {
        size_t n = strlen(why);
        snprintf(why + n, sizeof why - n, "; functional not tried: its error floor is %.1f%%", 100 * func_floor);
    }
    if (acc < sample_floor) {
        size_t n = strlen(why);
        snprintf(why + n, sizeof why - n, "; sampled not tried: its DRAM MB error floor is %.1f%%",
                 100 * sample_floor);
    }
    double rate = job->sample_rate > 0 ? job->sample_rate : fp->sample_rate;
    for (int attempt = 0; attempt < 2 && acc >= sample_floor; attempt++) {
        if (fid_lv_fresh_trial(&trial, acc, err, errlen))
            return 2;
        /* its frame pass only when it may still pay: the groups' prediction
         * (over the real estimate by at most 1.26x on the 1280x720 diffuse
         * matrix, sample_give_up 1.25), taken at 1/sample_give_up of itself,
         * would be within acc or raise the rate for a second try */
        double give_up = acc * fp->sample_give_up *
                         (attempt ? 1.0 : fmax(1.0, sqrt(fp->sample_retry_max_rate / (rate * fp->sample_retry_margin))));
        bool gave_up = false;
        if ((rc = fid_lv_sampled_or_give_up(job, rate, give_up, &trial, &ff, &gave_up, err, errlen)))
            goto out;
        step_add(&steps, attempt ? "sampled at the raised rate" : "sampled", -1);
        double w = fid_lv_worst(&trial.res);
        if (!trial.res.unreliable && w <= acc) {
            *o = trial;
            set_steps(o, &steps);
            snprintf(o->res.choice, sizeof o->res.choice,
                     "--accuracy %.3g%%: picked sampled at %.2f%% of the pixels (estimated error %.1f%%; %s)",
                     100 * acc, 100 * rate, 100 * w, why);
            return 0;
        }
        size_t n = strlen(why);
        snprintf(why + n, sizeof why - n, ", sampled at %.2f%%: %.1f%%%s", 100 * rate, 100 * w,
                 gave_up ? " predicted by its groups (the frame's functional pass not run)" : "");
        /* the interval shrinks as 1/sqrt(sample): the rate the bound needs */
        double need = rate * (w / acc) * (w / acc) * fp->sample_retry_margin;
        if (need > fp->sample_retry_max_rate || attempt == 1)
            break;
        rate = need;
    }
    free(trial.own);
    trial.own = NULL;
    rc = fid_lv_full(job, o, err, errlen);
    step_add(&steps, "full", -1);
    set_steps(o, &steps);
    snprintf(o->res.choice, sizeof o->res.choice, "--accuracy %.3g%%: fell back to full (%s)", 100 * acc, why);
    return rc;
out:
    free(trial.own);
    return rc;
}

