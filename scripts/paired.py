#!/usr/bin/env python3
"""paired.py — paired estimates of a sweep: each point's change against a
baseline point, with its own 95% interval (docs/fidelity.md "Paired
estimates").

    python3 scripts/paired.py DIR [--baseline KEY=VALUE[,KEY=VALUE..]] [--against FULLDIR]

DIR is a scripts/sweep folder (DIR/jobs.tsv, DIR/results/*.json). Points that
share scene, ray type, resolution and fixed arguments form a group; within a
group the baseline is the first point in jobs.tsv order. With --baseline
the baseline is the point whose keys match it, and the machine and swept
keys it does not name split the groups further: --baseline
node_l1.size=8192 compares each machine's sizes with its own 8 KB point,
--baseline machine=bvh2,node_l1.size=8192 every point with one. Writes DIR/paired.csv: per point and figure
of merit (MRPS, DRAM MB, mJ/frame) the value, its change against the
baseline in percent, and the change's 95% half-width in percentage points;
`unreliable` is 1 when either point is flagged.
With --against FULLDIR (the same sweep at full fidelity) it adds the full
model's change and the difference.

Why paired: at the windowed level every machine of a sweep runs the same
windows (their positions depend on the frame and the plan only), so the
windows' sampling errors of two machines are strongly correlated and cancel
in the change. The change's relative error is the difference of the two
relative errors; its random part is taken from the differences of the two
runs' window residuals, paired with their neighbours in the image as each
run's own interval is (collapsed strata, fidelity/estimator.c
fid_pairs_sumsq, Student t with as many degrees of freedom as pairs). The
lattice's and the start correction's errors pair the same way: both runs
took the same lattice pixels (16 interleaved groups) and the same windows'
warm-ups, so the differences of their residuals carry what does not
cancel (paired_other); runs that do not carry those residuals get them in
quadrature as if independent. The bias bounds
(cold fills and the floor, one-sided: both runs err the same way) as the
larger of the two. Points whose windows differ (another plan, or a full
run) get the plain sum of their two error estimates: no pairing.
Standard library only.
"""
import csv
import io
import json
import math
import os
import signal
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rtsim_runs  # noqa: E402

FIGS = [("mrps", "mrps", "error_estimate.mrps"), ("dram_mb", "dram_bytes", "error_estimate.dram_mb"),
        ("energy_mj", "energy_mj", "error_estimate.energy_mj")]

# two-sided 95% quantiles of Student's t, 1..30 degrees of freedom (as
# fidelity/estimator.c fid_t95)
T95 = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145, 2.131,
       2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042]


def die(msg):
    rtsim_runs.die("paired", msg)


def t95(dof):
    if dof < 1:
        return T95[0]
    return T95[dof - 1] if dof <= 30 else (2.000 if dof <= 60 else 1.960)


def pairs_sumsq(r):
    """fidelity/estimator.c fid_pairs_sumsq: (sum of squared pair differences, pairs)."""
    m = len(r)
    if m < 2:
        return 0.0, 0
    np_ = m // 2 + m % 2
    s = 0.0
    for q in range(np_):
        a = 2 * q if 2 * q < m - 1 else m - 2
        s += (r[a] - r[a + 1]) ** 2
    return s, np_


def window_plan(j):
    """What makes two runs' windows the same: level, count, sizes."""
    if j.get("fidelity") != "windowed" or not j.get("window.paired_windows"):
        return None
    return (j.get("window.count"), j.get("window.pixels"), j.get("window.warm_pixels"), j.get("window.lattice_pixels"))


def paired_other(ja, jb, col):
    """The lattice's and the start correction's errors of the change, paired
    like the windows': both runs took the same lattice pixels and the same
    windows' warm-ups, so the differences of their residuals (each set's
    squares sum to its variance, relative to the frame's figure) carry what
    does not cancel; Student t with the groups' and the windows' degrees of
    freedom. None when a run does not carry them."""
    g, w = ja.get("window.lattice_groups"), ja.get("window.start_windows")
    n = int(ja.get("window.paired_windows") or 0)
    if not g or not w or g != jb.get("window.lattice_groups") or w != jb.get("window.start_windows"):
        return None
    g, w = int(g), int(w)
    lat = sum((jb["window.lat_resid.%s.%d" % (col, i)] - ja["window.lat_resid.%s.%d" % (col, i)]) ** 2
              for i in range(g))
    start = sum((jb["window.start_resid.%s.%d" % (col, q)] - ja["window.start_resid.%s.%d" % (col, q)]) ** 2
                for q in range(n))
    return math.hypot(t95(g - 1) * math.sqrt(lat), t95(max(w - 1, 1)) * math.sqrt(start))


def change_parts(ja, jb, fig):
    """The parts of change(): (change %, ratio b/a, windows' term, other
    term, bias bound, paired?), the terms relative to the baseline's figure:
    the half-width is 100 ratio (hypot(windows, other) + bias) points; the
    windows' term alone shrinks with more windows (1 / sqrt(windows)). An
    unpaired change has its whole relative half-width as `other` (windows'
    term 0, bias 0). None for the change when a figure is missing."""
    col, key, est = fig
    a, b = ja.get(key), jb.get(key)
    if not a or b is None:
        return None, None, 0.0, 0.0, 0.0, False
    ratio = b / a
    pa, pb = window_plan(ja), window_plan(jb)
    if pa is None or pa != pb:
        return rtsim_runs.change_pct(b, a), ratio, 0.0, (ja.get(est, 0) + jb.get(est, 0)) / 100, 0.0, False
    n = int(ja["window.paired_windows"])
    d = [jb["window.resid.%s.%d" % (col, q)] - ja["window.resid.%s.%d" % (col, q)] for q in range(n)]
    s, np_ = pairs_sumsq(d)
    other = paired_other(ja, jb, col)
    if other is None:   # runs without the residuals below: as if independent
        other = math.hypot(ja["window.other_err." + col], jb["window.other_err." + col]) / 100
    bias = max(ja["window.bias_err." + col], jb["window.bias_err." + col]) / 100
    return rtsim_runs.change_pct(b, a), ratio, t95(np_) * math.sqrt(s), other, bias, True


def change(ja, jb, fig):
    """(change %, half-width in points, paired?) of figure fig of jb against ja."""
    ch, ratio, win, other, bias, paired = change_parts(ja, jb, fig)
    if ch is None:
        return None, None, False
    return ch, 100 * ratio * (math.hypot(win, other) + bias), paired


def load(d):
    jobs = os.path.join(d, "jobs.tsv")
    if not os.path.isfile(jobs):
        die("%s not found (a scripts/sweep folder)" % jobs)
    with open(jobs) as f:
        rows = [line.rstrip("\n").split("\t") for line in f if line.strip()]
    header, points = rows[0], rows[1:]
    if header[:6] != ["name", "scene", "rays", "machine", "res", "set"] or header[-1] != "args":
        die("%s:1: not a sweep job list" % jobs)
    res = []
    for p in points:
        path = os.path.join(d, "results", p[0] + ".json")
        if os.path.exists(path):
            with open(path) as f:
                res.append((p, json.load(f)))
    return header, res


def parse_baseline(text):
    if not text:
        return {}
    out = {}
    for kv in text.split(","):
        if "=" not in kv:
            die("--baseline %s: expected KEY=VALUE[,KEY=VALUE..]" % text)
        k, v = kv.split("=", 1)
        out[k] = v
    return out


def groups(header, res, baseline=None):
    """The baseline (jobs.tsv row, JSON) of each point's group: {point name:
    (row, JSON)}; points whose group has no baseline (--baseline matches none
    of it) are left out."""
    grid = header[6:-1]
    col = {n: i for i, n in enumerate(header)}
    want = parse_baseline(baseline)
    for k in want:
        if k not in col or k in ("name", "scene", "rays", "res", "set", "args"):
            die("--baseline %s: allowed keys machine%s" % (k, "".join(", " + g for g in grid)))
    # a group shares scene, rays, resolution and fixed arguments, and (with
    # --baseline) the machine and swept keys --baseline does not name: with
    # --baseline node_l1.size=8192 each machine gets its own baseline
    free = [k for k in ["machine"] + grid if want and k not in want]
    group = lambda p: tuple(p[col[k]] for k in ["scene", "rays", "res", "set", "args"] + free)
    base = {}
    for p, j in res:
        g = group(p)
        match = all(p[col[k]] == v for k, v in want.items())
        if g not in base and (match if want else True):
            base[g] = (p, j)
    return {p[0]: base[group(p)] for p, _ in res if group(p) in base}


def write_paired(d, baseline=None, against=None):
    """Writes DIR/paired.csv; returns its path and the rows (dicts)."""
    header, res = load(d)
    grid = header[6:-1]
    col = {n: i for i, n in enumerate(header)}
    base = groups(header, res, baseline)
    full = {}
    if against:
        _, fres = load(against)
        full = {tuple(p[1:-1]): j for p, j in fres}   # args (the fidelity) left out
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    cols = ["point", "scene", "rays", "machine", "res"] + grid + ["baseline", "fidelity", "unreliable"]
    for c, _, _ in FIGS:
        cols += [c, c + "_change_pct", c + "_change_err_pt", c + "_paired"]
        if against:
            cols += [c + "_full_change_pct", c + "_change_off_pt"]
    w.writerow(cols)
    rows = []
    for p, j in res:
        b = base.get(p[0])
        if b is None:
            continue
        # a change is as reliable as its less reliable point
        flagged = int(bool(j.get("unreliable")) or bool(b[1].get("unreliable")))
        row = [p[0], p[1], p[2], p[3], p[4]] + [p[col[g]] for g in grid] + [b[0][0], j.get("fidelity", "full"), flagged]
        rec = {"point": p[0], "baseline": b[0][0], "unreliable": flagged}
        for fig in FIGS:
            c, key, _ = fig
            ch, err, paired = change(b[1], j, fig)
            row += [j.get(key), "" if ch is None else "%.4f" % ch, "" if err is None else "%.4f" % err, int(paired)]
            rec[c] = (ch, err)
            if against:
                fj, fb = full.get(tuple(p[1:-1])), full.get(tuple(b[0][1:-1]))
                fch = (rtsim_runs.change_pct(fj[key], fb[key])
                       if fj and fb and fj.get(key) is not None and fb.get(key) is not None else None)
                row += ["" if fch is None else "%.4f" % fch,
                        "" if fch is None or ch is None else "%.4f" % (ch - fch)]
                rec[c + "_full"] = fch
        w.writerow(row)
        rows.append(rec)
    path = os.path.join(d, "paired.csv")
    rtsim_runs.write_atomic(path, out.getvalue())
    return path, rows


def main():
    ap = rtsim_runs.arg_parser("scripts/paired.py", __doc__)
    ap.add_argument("dir", metavar="DIR", help="a scripts/sweep folder (DIR/jobs.tsv, DIR/results/*.json)")
    ap.add_argument("--baseline", metavar="KEY=VALUE[,KEY=VALUE..]",
                    help="the baseline of each group: the point whose keys match (machine or a swept key); "
                    "default: the first point of each group in jobs.tsv order")
    ap.add_argument("--against", metavar="FULLDIR",
                    help="the same sweep at full fidelity: adds the full model's change and the difference")
    a = ap.parse_args()
    path, rows = write_paired(a.dir, a.baseline, a.against)
    print("paired: %d points against their baselines in %s" % (len(rows), path))
    if a.against:
        worst = max((abs(r[c][0] - r[c + "_full"]) for r in rows for c, _, _ in FIGS
                     if r[c][0] is not None and r.get(c + "_full") is not None), default=0.0)
        outside = sum(1 for r in rows for c, _, _ in FIGS
                      if r[c][0] is not None and r.get(c + "_full") is not None and abs(r[c][0] - r[c + "_full"]) > r[c][1])
        print("paired: worst |change - full's change| %.3f points; %d changes outside their interval" % (worst, outside))
    return 0


if __name__ == "__main__":
    # a reader that stops early (`| head`) ends this quietly, as it does a C tool
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    sys.exit(main())
