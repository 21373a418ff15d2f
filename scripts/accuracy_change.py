#!/usr/bin/env python3
"""accuracy_change.py — the two steps of `scripts/sweep --accuracy-change P`
after its windowed points are merged (docs/sweep.md "Changes to a given
accuracy", docs/fidelity.md "Paired estimates").

    python3 scripts/accuracy_change.py plan-full DIR P   DIR/full/jobs.tsv: the points to rerun at full
    python3 scripts/accuracy_change.py final DIR P       DIR/changes.csv and the summary

DIR is a scripts/sweep folder whose points ran at --fidelity windowed. Each
point's change against its group's baseline and the change's 95% half-width
are scripts/paired.py's. A point is rerun at full when the half-width of
any figure's change (MRPS, DRAM MB, mJ/frame) exceeds P percentage points or
the change is flagged (either point unreliable, or its run failed); its group's baseline is
then rerun too, once. The reruns are a sweep of their own in DIR/full (the
same points, the arguments after `--` without --fidelity, --windows,
--sample-rate and --jobs), run by scripts/sweep like any other, so an
interrupted sweep resumes there too. A rerun point's change is full against
full (exact: half-width 0); the others keep their paired windowed change
against the windowed baseline; a baseline's change is 0.

DIR/changes.csv, one row per point in jobs.tsv order: point, scene, rays,
machine, res, the swept keys, baseline, change_from (`windowed-paired` or
`full`), fidelity (of the figures in the row), unreliable, then for mrps,
dram_mb and energy_mj the figure (DRAM in MB), its change in percent and
the change's half-width in percentage points. No timing column: the same
results give the same bytes. Standard library only.
"""
import csv
import io
import json
import os
import signal
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import paired  # noqa: E402
import rtsim_runs  # noqa: E402

# rtsim arguments that choose or shape a cheaper level: dropped for the full reruns
LEVEL_ARGS = ("--fidelity", "--accuracy", "--windows", "--sample-rate", "--jobs")


def die(msg, code=2):
    print("sweep: " + msg, file=sys.stderr)
    sys.exit(code)


def full_args(field):
    """The args field of a windowed point's jobs.tsv row without the level's options."""
    out, skip = [], False
    for w in ([] if field == "-" else field.split()):
        if skip:
            skip = False
        elif w.split("=", 1)[0] in LEVEL_ARGS:
            skip = "=" not in w
        else:
            out.append(w)
    return out


def pts(p):
    return ("%g" % p) + "pt"


def decide(d, p):
    """(header, results, baselines, why): why maps each point to rerun at
    full to its reason ("" for a baseline rerun for its group's points)."""
    header, res = paired.load(d)
    base = paired.groups(header, res, rtsim_runs.sweep_conf(d, "baseline") or None)
    why = {}
    for pt, j in res:
        b = base.get(pt[0])
        if b is None or b[0][0] == pt[0]:
            continue
        if j.get("unreliable") or b[1].get("unreliable") or j.get("run_failed") or b[1].get("run_failed"):
            why[pt[0]] = "flagged"
            continue
        over = []
        for fig in paired.FIGS:
            ch, err, _ = paired.change(b[1], j, fig)
            if err is not None and err > p:
                over.append("%s +-%.3fpt" % (fig[0], err))
        if over:
            why[pt[0]] = ", ".join(over)
    for name in list(why):
        why.setdefault(base[name][0][0], "")
    return header, res, base, why


def full_row(header, pt):
    """The jobs.tsv row of point pt (a windowed row) at full fidelity."""
    grid = header[6:-1]
    fixed = [] if pt[5] == "-" else [kv for kv in pt[5].split(";") if kv]
    sets = ["%s=%s" % (k, v) for k, v in zip(grid, pt[6:-1])] + fixed
    extra = " ".join(full_args(pt[-1])) or "-"
    name = rtsim_runs.sweep_point_name(pt[1], pt[2], pt[3], pt[4], extra, sets)
    return [name] + pt[1:-1] + [extra]


def plan_full(d, p):
    header, res, base, why = decide(d, p)
    rows = [full_row(header, pt) for pt, _ in res if pt[0] in why]
    fd = os.path.join(d, "full")
    for sub in ("results", "logs"):
        os.makedirs(os.path.join(fd, sub), exist_ok=True)
    rtsim_runs.write_jobs(fd, "\n".join("\t".join(r) for r in [header] + rows) + "\n")
    with open(os.path.join(d, "sweep.conf")) as f:
        rtsim_runs.write_atomic(os.path.join(fd, "sweep.conf"), f.read())
    nbase = sum(1 for n in why if not why[n])
    print("sweep: --accuracy-change %s: %d of %d points within %s at windowed, %d to rerun at full "
          "(%d over %s or flagged, baselines: %d)" % (pts(p), len(res) - len(why), len(res), pts(p), len(why),
                                                     len(why) - nbase, pts(p), nbase))
    for pt, _ in res:
        if why.get(pt[0]):
            print("sweep:   %s: %s" % (pt[0], why[pt[0]]))
    return 0


def cpu(j):
    r = j.get("run", {})
    v = r.get("sim_cpu_s")
    return v if v is not None else (r.get("host_cpu_s") or 0.0)


def final(d, p):
    header, res, base, why = decide(d, p)
    grid = header[6:-1]
    full = {}
    fd = os.path.join(d, "full")
    for pt, _ in res:
        if pt[0] in why:
            path = os.path.join(fd, "results", full_row(header, pt)[0] + ".json")
            if os.path.exists(path):
                with open(path) as f:
                    full[pt[0]] = json.load(f)
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
        if pt[0] in why:
            if pt[0] not in full or b[0][0] not in full:
                continue
            a, r, src = full[b[0][0]], full[pt[0]], "full"
        else:
            a, r, src = b[1], j, "windowed-paired"
        flagged = int(bool(r.get("unreliable")) or bool(a.get("unreliable")))
        row = pt[:5] + pt[6:-1] + [b[0][0], src, r.get("fidelity", "full"), flagged]
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
    fcpu = sum(cpu(j) for j in full.values())
    print("sweep: --accuracy-change %s: %d points passed at windowed, %d rerun at full (baselines: %d); "
          "CPU %.1f s (windowed %.1f s, full reruns %.1f s)"
          % (pts(p), len(res) - len(why), len(why), sum(1 for x in why if not why[x]), wcpu + fcpu, wcpu, fcpu))
    print("sweep: changes of %d points in %s" % (n, path))
    if missing:
        print("sweep: %d points to rerun at full have no result yet: %s (run the sweep again)"
              % (len(missing), " ".join([pt[0] for pt, _ in res if pt[0] in missing][:5])), file=sys.stderr)
        return 1
    return 0


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in ("plan-full", "final"):
        die("usage: python3 scripts/accuracy_change.py plan-full|final DIR P (scripts/sweep runs it)")
    try:
        p = float(sys.argv[3])
    except ValueError:
        p = 0.0
    if not 0 < p <= 100:
        die("--accuracy-change %s: expected percentage points in (0, 100]" % sys.argv[3])
    return (plan_full if sys.argv[1] == "plan-full" else final)(sys.argv[2], p)


if __name__ == "__main__":
    # a reader that stops early (`| head`) ends this quietly, as it does a C tool
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    sys.exit(main())
