#!/usr/bin/env python3
"""accuracy_change.py — the steps of `scripts/sweep --accuracy-change P`
after its windowed points are merged (docs/sweep.md "Changes to a given
accuracy", docs/fidelity.md "Paired estimates").

    python3 scripts/accuracy_change.py plan-more DIR P   DIR/more/jobs.tsv: the points to rerun with more windows
    python3 scripts/accuracy_change.py plan-full DIR P   DIR/full/jobs.tsv: the points to rerun at full
    python3 scripts/accuracy_change.py final DIR P       DIR/changes.csv and the summary

DIR is a scripts/sweep folder whose points ran at --fidelity windowed. Each
point's change against its group's baseline and the change's 95% half-width
are scripts/paired.py's. A point is over P when the half-width of any
figure's change (MRPS, DRAM MB, mJ/frame) exceeds P percentage points or the
change is flagged (either point unreliable, or its run failed).

Only the windows' term of a half-width shrinks with more windows (as 1 /
sqrt(windows)); the lattice's and the start correction's terms and the bias
bound do not. So a point over P, not flagged, whose half-width would come
within P with at most MORE_MAX times the windows (with a margin of
MORE_MARGIN) is first rerun windowed with more windows of the same size,
together with its group's baseline (a change pairs only runs with the same
windows): every such point of a group and the baseline get the group's
largest need, within MAX_RATE of the frame. Those reruns are a sweep of
their own in DIR/more. A point still over P there, or over P with no room
for more windows, is rerun at full in DIR/full, together with its group's
baseline, once. The reruns use the same points and the arguments after
`--` (more windows: --fidelity windowed with --windows and --sample-rate
set; full: without --fidelity, --windows, --sample-rate and --jobs) and
run through scripts/sweep like any other, so an interrupted sweep resumes
there too. A rerun point's change is full against full (exact: half-width
0), or the paired change between the two runs with more windows; the others
keep their paired windowed change against the windowed baseline; a
baseline's change is 0.

DIR/changes.csv, one row per point in jobs.tsv order: point, scene, rays,
machine, res, the swept keys, baseline, change_from (`windowed-paired`,
`windowed-more` or `full`), fidelity (of the figures in the row),
unreliable, then for mrps, dram_mb and energy_mj the figure (DRAM in MB),
its change in percent and the change's half-width in percentage points. No
timing column: the same results give the same bytes. Standard library only.
"""
import csv
import io
import json
import math
import os
import signal
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import paired  # noqa: E402
import rtsim_runs  # noqa: E402

# rtsim arguments that choose or shape a cheaper level: dropped for the full reruns
LEVEL_ARGS = ("--fidelity", "--accuracy", "--windows", "--sample-rate", "--jobs")
# ... and the ones a rerun with more windows sets itself
PLAN_ARGS = ("--fidelity", "--accuracy", "--windows", "--sample-rate")

# More windows are tried when at most MORE_MAX times the windows should do
# (with MORE_MARGIN on the need, as --accuracy's own growth step,
# fidelity/accuracy.c): beyond it the point and its baseline would cost
# about as much as at full (a windowed 1280x720 diffuse point is about a
# fifth of a full one, docs/validation/fidelity-bench.md).
MORE_MAX = 3.0
MORE_MARGIN = 1.2
# at most this share of the frame's pixels through the model (as
# fidelity/fidelity_params.c win_max_rate bounds --accuracy's growth)
MAX_RATE = 0.4
# rtsim's --windows range
MAX_WINDOWS = 4096


def die(msg, code=2):
    print("sweep: " + msg, file=sys.stderr)
    sys.exit(code)


def strip_args(field, drop=LEVEL_ARGS):
    """The args field of a windowed point's jobs.tsv row without the options in drop."""
    out, skip = [], False
    for w in ([] if field == "-" else field.split()):
        if skip:
            skip = False
        elif w.split("=", 1)[0] in drop:
            skip = "=" not in w
        else:
            out.append(w)
    return out


def pts(p):
    return ("%g" % p) + "pt"


def flagged(ja, jb):
    return any(j.get("unreliable") or j.get("run_failed") for j in (ja, jb))


def over(ja, jb, p):
    """Why the change of jb against ja is not within p points ("" when it is)."""
    if flagged(ja, jb):
        return "flagged"
    out = []
    for fig in paired.FIGS:
        _, err, _ = paired.change(ja, jb, fig)
        if err is not None and err > p:
            out.append("%s +-%.3fpt" % (fig[0], err))
    return ", ".join(out)


def windows_need(ja, jb, p):
    """How many times its windows the change of jb against ja needs to come
    within p points (paired.change_parts), or None when more windows cannot
    bring it there (the terms that do not shrink already fill p)."""
    need = 1.0
    for fig in paired.FIGS:
        ch, ratio, win, other, bias, is_paired = paired.change_parts(ja, jb, fig)
        if ch is None:
            continue
        room = p / 100 / ratio - bias
        if not is_paired or room <= other:
            return None
        need = max(need, win * win / (room * room - other * other))
    return need


def more_plan(j, factor):
    """(windows, sample rate) for factor x the windows of windowed run j,
    each of the same size, or None when the frame has no room for them."""
    n, size = int(j["window.count"]), int(j["window.pixels"]) + int(j["window.warm_pixels"])
    npix = int(j["run"]["width_px"]) * int(j["run"]["height_px"])
    m = 2 * int(math.ceil(factor * n / 2))   # whole pairs
    return (m, m * size / npix) if m <= min(MAX_WINDOWS, MAX_RATE * npix / size) else None


def row_for(header, pt, args):
    """The jobs.tsv row of point pt (a windowed row) with rtsim arguments args."""
    grid = header[6:-1]
    fixed = [] if pt[5] == "-" else [kv for kv in pt[5].split(";") if kv]
    sets = ["%s=%s" % (k, v) for k, v in zip(grid, pt[6:-1])] + fixed
    extra = " ".join(args) or "-"
    name = rtsim_runs.sweep_point_name(pt[1], pt[2], pt[3], pt[4], extra, sets)
    return [name] + pt[1:-1] + [extra]


def full_row(header, pt):
    return row_for(header, pt, strip_args(pt[-1]))


def more_row(header, pt, plan):
    m, rate = plan
    return row_for(header, pt, strip_args(pt[-1], PLAN_ARGS) +
                   ["--fidelity", "windowed", "--windows", str(m), "--sample-rate", "%.9g" % rate])


def decide_more(d, p):
    """(header, results, baselines, more, why): more maps each point (and
    its group's baseline) to rerun with more windows to that plan; why, each
    point to rerun at full without trying more windows to its reason."""
    header, res = paired.load(d)
    base = paired.groups(header, res, rtsim_runs.sweep_conf(d, "baseline") or None)
    why, need, wants = {}, {}, []   # need: each group's (baseline's) factor; wants: the points asking
    for pt, j in res:
        b = base.get(pt[0])
        if b is None or b[0][0] == pt[0]:
            continue
        w = over(b[1], j, p)
        if not w:
            continue
        k = None if w == "flagged" else windows_need(b[1], j, p)
        if k is None or k * MORE_MARGIN > MORE_MAX:
            why[pt[0]] = w
        else:
            need[b[0][0]] = max(need.get(b[0][0], 1.25), k * MORE_MARGIN)
            wants.append(pt[0])
    more = {}
    for name in wants:
        b = base[name]
        plan = more_plan(b[1], need[b[0][0]])
        if plan is None:
            why[name] = "no room for more windows"
        else:
            more[name] = more[b[0][0]] = plan
    return header, res, base, more, why


def load_rows(d, rows):
    """{name of the original point: JSON} of the rerun rows [(name, row)] with a result in d."""
    out = {}
    for n, r in rows:
        path = os.path.join(d, "results", r[0] + ".json")
        if os.path.exists(path):
            with open(path) as f:
                out[n] = json.load(f)
    return out


def decide(d, p):
    """(header, results, baselines, more, more results, why): why maps each
    point to rerun at full to its reason ("" for a baseline rerun for its
    group's points)."""
    header, res, base, more, why = decide_more(d, p)
    rows = {pt[0]: pt for pt, _ in res}
    mres = load_rows(os.path.join(d, "more"), [(n, more_row(header, rows[n], more[n])) for n in more])
    for n in more:
        b = base[n][0][0]
        if n == b:
            continue
        if n not in mres or b not in mres:
            why[n] = "its run with more windows failed"
        else:
            w = over(mres[b], mres[n], p)
            if w:
                why[n] = w + " with %d windows" % more[n][0]
    for name in list(why):
        why.setdefault(base[name][0][0], "")
    return header, res, base, more, mres, why


def write_stage(d, sub, header, rows):
    fd = os.path.join(d, sub)
    for s in ("results", "logs"):
        os.makedirs(os.path.join(fd, s), exist_ok=True)
    rtsim_runs.write_jobs(fd, "\n".join("\t".join(r) for r in [header] + rows) + "\n")
    with open(os.path.join(d, "sweep.conf")) as f:
        rtsim_runs.write_atomic(os.path.join(fd, "sweep.conf"), f.read())


def plan_more(d, p):
    header, res, base, more, why = decide_more(d, p)
    write_stage(d, "more", header, [more_row(header, pt, more[pt[0]]) for pt, _ in res if pt[0] in more])
    nbase = sum(1 for n in more if base[n][0][0] == n)
    print("sweep: --accuracy-change %s: %d of %d points within %s at windowed, %d to rerun with more windows "
          "(%d over %s, baselines: %d), %d at full" % (pts(p), len(res) - len(why) - len(more) + nbase, len(res),
                                                     pts(p), len(more), len(more) - nbase, pts(p), nbase, len(why)))
    for pt, j in res:
        if pt[0] in more and base[pt[0]][0][0] != pt[0]:
            print("sweep:   %s: %s; %d windows" % (pt[0], over(base[pt[0]][1], j, p), more[pt[0]][0]))
    return 0


def plan_full(d, p):
    header, res, base, more, mres, why = decide(d, p)
    write_stage(d, "full", header, [full_row(header, pt) for pt, _ in res if pt[0] in why])
    nbase = sum(1 for n in why if not why[n])
    print("sweep: --accuracy-change %s: %d of %d points within %s at windowed or with more windows, %d to rerun "
          "at full (%d over %s or flagged, baselines: %d)" % (pts(p), len(res) - len(why), len(res), pts(p),
                                                              len(why), len(why) - nbase, pts(p), nbase))
    for pt, _ in res:
        if why.get(pt[0]):
            print("sweep:   %s: %s" % (pt[0], why[pt[0]]))
    return 0


def cpu(j):
    r = j.get("run", {})
    v = r.get("sim_cpu_s")
    return v if v is not None else (r.get("host_cpu_s") or 0.0)


def final(d, p):
    header, res, base, more, mres, why = decide(d, p)
    grid = header[6:-1]
    full = load_rows(os.path.join(d, "full"), [(pt[0], full_row(header, pt)) for pt, _ in res if pt[0] in why])
    missing = [n for n in why if n not in full]
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    cols = ["point", "scene", "rays", "machine", "res"] + grid + ["baseline", "change_from", "fidelity", "unreliable"]
    for c, _, _ in paired.FIGS:
        cols += [c, c + "_change_pct", c + "_change_err_pt"]
    w.writerow(cols)
    n = 0
    for pt, j in res:
        b = base.get(pt[0])
        if b is None:
            continue
        # where the change comes from: the point's own stage, and the
        # baseline's run of that stage
        if pt[0] in why:
            if pt[0] not in full or b[0][0] not in full:
                continue
            a, r, src = full[b[0][0]], full[pt[0]], "full"
        elif pt[0] in more:
            if pt[0] not in mres or b[0][0] not in mres:
                continue
            a, r, src = mres[b[0][0]], mres[pt[0]], "windowed-more"
        else:
            a, r, src = b[1], j, "windowed-paired"
        flagged_ch = int(bool(r.get("unreliable")) or bool(a.get("unreliable")))
        row = pt[:5] + pt[6:-1] + [b[0][0], src, r.get("fidelity", "full"), flagged_ch]
        for fig in paired.FIGS:
            c, key, _ = fig
            v = rtsim_runs.figure(r, c)
            if pt[0] == b[0][0]:
                ch, err = (0.0, 0.0) if v is not None else (None, None)
            elif src == "full":
                ch = rtsim_runs.change_pct(r[key], a[key]) if r.get(key) is not None and a.get(key) is not None else None
                err = None if ch is None else 0.0
            else:
                ch, err, _ = paired.change(a, r, fig)
            row += ["" if v is None else repr(v), "" if ch is None else "%.4f" % ch, "" if err is None else "%.4f" % err]
        w.writerow(row)
        n += 1
    path = os.path.join(d, "changes.csv")
    rtsim_runs.write_atomic(path, out.getvalue())
    wcpu = sum(cpu(j) for _, j in res)
    mcpu = sum(cpu(j) for j in mres.values())
    fcpu = sum(cpu(j) for j in full.values())
    nmore = sum(1 for x in more if x not in why)
    print("sweep: --accuracy-change %s: %d points passed at windowed, %d with more windows, %d rerun at full "
          "(baselines: %d); CPU %.1f s (windowed %.1f s, more windows %.1f s, full reruns %.1f s)"
          % (pts(p), len(res) - len(why) - nmore, nmore, len(why), sum(1 for x in why if not why[x]),
             wcpu + mcpu + fcpu, wcpu, mcpu, fcpu))
    print("sweep: changes of %d points in %s" % (n, path))
    if missing:
        print("sweep: %d points to rerun at full have no result yet: %s (run the sweep again)"
              % (len(missing), " ".join([pt[0] for pt, _ in res if pt[0] in missing][:5])), file=sys.stderr)
        return 1
    return 0


def main():
    steps = {"plan-more": plan_more, "plan-full": plan_full, "final": final}
    if len(sys.argv) != 4 or sys.argv[1] not in steps:
        die("usage: python3 scripts/accuracy_change.py plan-more|plan-full|final DIR P (scripts/sweep runs it)")
    try:
        p = float(sys.argv[3])
    except ValueError:
        p = 0.0
    if not 0 < p <= 100:
        die("--accuracy-change %s: expected percentage points in (0, 100]" % sys.argv[3])
    return steps[sys.argv[1]](sys.argv[2], p)


if __name__ == "__main__":
    # a reader that stops early (`| head`) ends this quietly, as it does a C tool
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    sys.exit(main())
