#!/usr/bin/env python3
"""sweep_merge.py — merges a sweep's results into one CSV and draws charts.

    python3 scripts/sweep_merge.py DIR        (what `scripts/sweep merge DIR` runs)

Reads DIR/jobs.tsv (the points, written by scripts/sweep) and DIR/sweep.conf
(extra `stat KEY` columns), and every finished point's DIR/results/NAME.json
(rtsim --json). Writes DIR/results.csv: one row per finished point, in the
order of jobs.tsv, so the same finished points always give the same bytes
whatever order they ran in. Then draws, with gnuplot, each figure of merit
against each swept (--set-grid) key: DIR/charts/FIGURE-vs-KEY.png and .svg.

Figures of merit are those the JSON has: MRPS and DRAM MB always; mJ/frame,
MRPS/mm2, area and power once rtsim reports them (the energy model, docs/energy.md);
the missing ones are named, not charted. Exit status: 0 when every point has
a result, 1 when some have none (the CSV then holds the finished ones), 2 on
bad input (no jobs.tsv).
"""
import csv
import io
import json
import math
import os
import re
import shutil
import subprocess
import signal
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rtsim_runs  # noqa: E402
from gnuplot_text import quoted  # noqa: E402

# (CSV column, JSON key, divisor, chart label): the figures of merit of
# scripts/rtsim_runs.py (the experiment scripts' one table of them), in the
# order of the paper's Table 2 (MRPS, mJ/frame, MRPS/mm2, DRAM MB), then area
# and power. A figure whose JSON key no result has gets no column.
FIGURES = [(key, stat, divisor, label) for key, _, stat, divisor, label in rtsim_runs.FIGURES]
# Always-present context columns (not charted).
CONTEXT = [("rays_traced", "rays"), ("cycles", "cycles"), ("run_failed", "run_failed")]


def die(msg, code=2):
    print(f"sweep: {msg}", file=sys.stderr)
    sys.exit(code)


def write_atomic(path, text):
    tmp = f"{path}.tmp.{os.getpid()}"
    with open(tmp, "w", newline="") as f:
        f.write(text)
    os.replace(tmp, path)


def fmt(v):
    """A JSON value as CSV text: floats by repr (exact and stable), the rest by str."""
    if v is None:
        return ""
    if isinstance(v, bool):
        return str(int(v))
    return repr(v) if isinstance(v, float) else str(v)


def figure(j, fig):
    """The figure of merit fig of result j, in the figure's unit, or None."""
    return rtsim_runs.figure(j, fig[0])


def as_number(s):
    try:
        x = float(s)
        return x if math.isfinite(x) else None
    except ValueError:
        return None


def safe(s):
    return re.sub(r"[^A-Za-z0-9._-]", "_", s)


def main():
    if len(sys.argv) != 2:
        die("usage: scripts/sweep merge DIR")
    d = sys.argv[1]
    jobs_path = os.path.join(d, "jobs.tsv")
    if not os.path.isfile(jobs_path):
        die(f"{jobs_path} not found (run scripts/sweep first)")
    with open(jobs_path) as f:
        rows = [line.rstrip("\n").split("\t") for line in f if line.strip()]
    header, points = rows[0], rows[1:]
    if header[:6] != ["name", "scene", "rays", "machine", "res", "set"] or header[-1] != "args":
        die(f"{jobs_path}:1: not a sweep job list (header {header!r})")
    grid = header[6:-1]
    stats = []
    conf = os.path.join(d, "sweep.conf")
    if os.path.isfile(conf):
        for line in open(conf):
            parts = line.split()
            if len(parts) == 2 and parts[0] == "stat":
                stats.append(parts[1])

    results, missing = [], []
    for n, p in enumerate(points, start=2):
        if len(p) != len(header):
            die(f"{jobs_path}:{n}: {len(p)} fields, the header has {len(header)}")
        path = os.path.join(d, "results", p[0] + ".json")
        if not os.path.exists(path):
            missing.append(p[0])
            continue
        try:
            with open(path) as f:
                results.append((p, json.load(f)))
        except (OSError, ValueError) as e:
            die(f"{path}: unreadable result ({e}); delete it to rerun the point", 1)

    if points and not results:
        # Not one point has a result: rtsim failed (or never started) on
        # every one. Say so with the first point's error rather than report
        # figures of merit "missing from rtsim's JSON".
        first = points[0][0]
        log = os.path.join(d, "logs", first + ".log")
        print(f"sweep: rtsim failed on all {len(points)} points, no result to merge; "
              f"the first point's error ({log}):", file=sys.stderr)
        try:
            with open(log, errors="replace") as f:
                lines = f.read().splitlines()[-5:]
            print("\n".join("  " + line for line in lines) if lines else "  (its log is empty)", file=sys.stderr)
        except OSError:
            print("  (no log: the point's job did not start rtsim; see the messages above)", file=sys.stderr)
        return 1

    present = [fig for fig in FIGURES if any(fig[1] in j for _, j in results)]
    absent = [fig[0] for fig in FIGURES if fig not in present]

    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(["point", "scene", "rays", "machine", "res"] + grid + ["set", "args"]
               + [c for c, _ in CONTEXT] + [fig[0] for fig in present] + stats)
    for p, j in results:
        ctx = [fmt(j.get(k)) for _, k in CONTEXT]
        figs = [fmt(figure(j, fig)) for fig in present]
        w.writerow(p[0:5] + p[6:-1] + ["" if p[5] == "-" else p[5], "" if p[-1] == "-" else p[-1]]
                   + ctx + figs + [fmt(j.get(s)) for s in stats])
    csv_path = os.path.join(d, "results.csv")
    write_atomic(csv_path, out.getvalue())
    print(f"sweep: merged {len(results)} of {len(points)} points into {csv_path}")
    print("sweep: figures of merit: " + ", ".join(fig[0] for fig in present)
          + ("; not in rtsim's JSON (no column, no chart): " + ", ".join(absent) if absent else ""))
    failed = [p[0] for p, j in results if j.get("run_failed")]
    if failed:
        print(f"sweep: {len(failed)} of {len(results)} points failed (deadlock, livelock or stack overflow; "
              "run_failed = 1 in the CSV, left out of the charts): "
              + " ".join(failed[:5]) + (" ..." if len(failed) > 5 else ""))

    # A failed run's figures (MRPS 0...) are no measurement: not charted.
    draw_charts(d, header, grid, [(p, j) for p, j in results if not j.get("run_failed")], present)
    write_report(d, header, grid, results, present, len(points))
    write_paired_if_windowed(d, results)
    if missing:
        print(f"sweep: {len(missing)} of {len(points)} points have no result yet: " + " ".join(missing[:5])
              + (" ..." if len(missing) > 5 else "") + " (run the sweep again to do them)",
              file=sys.stderr)
        return 1
    return 0


def write_paired_if_windowed(d, results):
    """DIR/paired.csv (scripts/paired.py: each point's change against its
    group's baseline with a paired interval) when some point ran windowed."""
    if not any(j.get("fidelity") == "windowed" for _, j in results):
        return
    import paired
    path, rows = paired.write_paired(d, rtsim_runs.sweep_conf(d, "baseline") or None)
    print(f"sweep: paired changes of {len(rows)} points against their baselines in {path}")


def write_report(d, header, grid, results, present, npoints):
    """DIR/report.html (scripts/report_html.py): the figures of merit against
    each swept key, one line per combination of what else varies, the
    Pareto front of MRPS/mm2 (higher is better) against mJ/frame (lower is
    better) over all points, and every point's figures in a table."""
    import report_html as R
    ok = [(p, j) for p, j in results if not j.get("run_failed")]
    dims = ["scene", "rays", "machine"] + grid
    col = {name: header.index(name) for name in dims}
    varying = [k for k in dims if len({p[col[k]] for p, _ in ok}) > 1]
    body = []
    commits = sorted({"%s%s" % (j.get("run", {}).get("commit"), " (dirty)" if j.get("run", {}).get("dirty") else "")
                      for _, j in results})
    levels = sorted({str(j.get("fidelity", "full")) for _, j in results})
    summary = [["points", "%d of %d done%s" % (len(results), npoints, (", %d failed (not charted)" % (len(results) - len(ok)))
                                              if len(ok) < len(results) else "")]]
    for k in dims:
        vals = []
        for p, _ in results:
            if p[col[k]] not in vals:
                vals.append(p[col[k]])
        summary.append([R.esc(k) + (" (swept)" if k in grid else ""), R.esc(", ".join(vals))])
    fixed = sorted({p[5] for p, _ in results if p[5] != "-"})
    summary.append(["fixed --set", R.esc("; ".join(fixed) or "none")])
    summary.append(["fidelity", R.esc(", ".join(levels))])
    summary.append(["built from commit", R.esc(", ".join(commits))])
    body.append('<h2 id="sweep">Sweep</h2>' + R.table(summary))
    # Pareto front
    fr_pts = [(p, j) for p, j in ok if j.get("mrps_per_mm2") is not None and j.get("energy_mj") is not None]
    label = lambda p: " ".join([p[col["scene"]], p[col["rays"]], p[col["machine"]]] + ["%s=%s" % (k, p[col[k]]) for k in grid])
    front = []
    if fr_pts:
        xy = [(j["mrps_per_mm2"], j["energy_mj"]) for _, j in fr_pts]
        front = R.pareto_front(xy)
        body.append('<h2 id="pareto">Pareto front: MRPS/mm² against mJ/frame</h2><p class="note">Red: the points no other '
                    'point beats on both (more MRPS/mm², fewer mJ/frame). Points of different scenes and ray types are '
                    'not comparable; each is drawn all the same.</p>')
        body.append(R.scatter_chart("chart-pareto", "MRPS/mm² (higher is better) against mJ/frame (lower is better)",
                                    "MRPS/mm²", "mJ/frame", [(x, y, label(p)) for (p, _), (x, y) in zip(fr_pts, xy)], front))
        body.append(R.table([[R.esc(label(fr_pts[i][0])), R.fmt(xy[i][0]), R.fmt(xy[i][1]), R.fmt(fr_pts[i][1].get("mrps"))]
                             for i in sorted(front, key=lambda i: -xy[i][0])], ["point on the front", "MRPS/mm²", "mJ/frame", "MRPS"]))
    # figures against each swept key
    for key in grid:
        values = []
        for p, _ in ok:
            if p[col[key]] not in values:
                values.append(p[col[key]])
        nums = [as_number(v) for v in values]
        numeric = all(x is not None for x in nums)
        logx = numeric and min(nums) > 0 and max(nums) / min(nums) >= 8
        others = [k for k in varying if k != key]
        body.append('<h2 id="vs-%s">Against %s</h2>' % (R.esc(safe(key)), R.esc(key)))
        for fig in present:
            series = {}
            for p, j in ok:
                y = figure(j, fig)
                if y is None:
                    continue
                lab = " ".join(f"{k}={p[col[k]]}" if k in grid else p[col[k]] for k in others) or "all"
                x = as_number(p[col[key]]) if numeric else values.index(p[col[key]])
                series.setdefault(lab, []).append((x, y))
            if not series:
                continue
            lines = []
            for lab, pts in series.items():
                pts.sort()
                lines.append((lab, [x for x, _ in pts], [y for _, y in pts]))
            ticks = [(x if numeric else i, v) for i, (v, x) in enumerate(zip(values, nums))]
            body.append(R.line_chart("chart-%s-vs-%s" % (fig[0], safe(key)), "%s against %s" % (fig[3], key), key, fig[3],
                                     lines, xticks=ticks, markers=True, logx=logx))
    # every point
    heads = ["point"] + dims + [fig[0] for fig in present]
    trs = []
    for p, j in results:
        on = any(fr_pts[i][0] is p for i in front)
        trs.append([R.esc(p[0]) + (' <b class="flag">front</b>' if on else "") + (' <span class="flag">failed</span>' if j.get("run_failed") else "")]
                   + [R.esc(p[col[k]]) for k in dims] + ['<span class="num">%s</span>' % R.fmt(figure(j, fig)) for fig in present])
    body.append('<h2 id="points">Points</h2>' + R.table(trs, heads, cls="points"))
    path = os.path.join(d, "report.html")
    R.write_atomic(path, R.page("rtsim sweep: %s" % os.path.basename(os.path.abspath(d)), "%d points · results.csv beside "
                                "this page" % len(results), "\n".join(body)))
    print(f"sweep: report page {path}")


def draw_charts(d, header, grid, results, present):
    """One chart per (figure, swept key): the figure against the key's values,
    one line per combination of everything else that varies (scene, rays,
    machine, the other swept keys). Numeric values go on a numeric axis (log2
    when they span a factor of 8 or more), others are categories in grid order."""
    if not grid:
        print("sweep: no --set-grid key, so no charts")
        return
    if not results:
        return
    gnuplot = shutil.which("gnuplot")
    if not gnuplot:
        print("sweep: gnuplot not found (Debian package gnuplot-nox): no charts", file=sys.stderr)
        return
    charts = os.path.join(d, "charts")
    os.makedirs(charts, exist_ok=True)
    # Columns of jobs.tsv that define a series: those with more than one value.
    dims = ["scene", "rays", "machine"] + grid
    col = {name: header.index(name) for name in dims}
    varying = [k for k in dims if len({p[col[k]] for p, _ in results}) > 1]
    script = []
    outputs = []              # (temporary, final): renamed once gnuplot succeeded
    drawn = 0
    for key in grid:
        values = []                                  # grid order, as planned
        for p, _ in results:
            if p[col[key]] not in values:
                values.append(p[col[key]])
        nums = [as_number(v) for v in values]
        numeric = all(x is not None for x in nums)
        others = [k for k in varying if k != key]
        series = {}
        for p, j in results:
            label = " ".join(f"{k}={p[col[k]]}" if k in grid else p[col[k]] for k in others)
            series.setdefault(label or "all", []).append((p[col[key]], j))
        for fig in present:
            base = f"{fig[0]}-vs-{safe(key)}"
            dat = os.path.join(charts, base + ".dat")
            blocks, titles = [], []
            for label, pts in series.items():
                lines = []
                for v, j in pts:
                    y = figure(j, fig)
                    if y is None:
                        continue
                    x = as_number(v) if numeric else values.index(v)
                    lines.append((x, y, v))
                if lines:
                    lines.sort(key=lambda t: t[0])
                    blocks.append("\n".join(f"{x!r} {y!r} \"{v}\"" for x, y, v in lines))
                    titles.append(label)
            if not blocks:
                continue
            write_atomic(dat, f"# {fig[0]} against {key}; one block per series\n"
                         + "\n\n\n".join(blocks) + "\n")
            # The swept values themselves label the x axis (in grid order for
            # categories); a numeric axis with many values keeps gnuplot's tics.
            if not numeric:
                xtics = "set xtics (" + ", ".join(f'"{v}" {i}' for i, v in enumerate(values)) + ")"
            elif len(values) <= 12:
                xtics = "set xtics (" + ", ".join(f'"{v}" {x!r}' for v, x in zip(values, nums)) + ")"
            else:
                xtics = "set xtics autofreq"
            logx = numeric and min(nums) > 0 and max(nums) / min(nums) >= 8
            for term, ext in (("pngcairo size 900,560 noenhanced", "png"),
                              ("svg size 900,560 dynamic noenhanced", "svg")):
                final = os.path.join(charts, f"{base}.{ext}")
                outputs.append((f"{final}.tmp.{os.getpid()}", final))
                script += [f"set terminal {term}",
                           ("output", len(outputs) - 1),
                           f"set title '{fig[3]} against {key}'",
                           f"set xlabel '{key}'", f"set ylabel '{fig[3]}'",
                           "set key outside right top", "set grid",
                           "set logscale x 2" if logx else "unset logscale x",
                           xtics, "set offsets graph 0.05, graph 0.05, graph 0.05, graph 0.05",
                           "plot " + ", ".join(f"{quoted(dat)} index {i} using 1:2 with linespoints "
                                               f"title '{t.replace(chr(39), '')}'"
                                               for i, t in enumerate(titles))]
            drawn += 1
    # charts.gp names the final files (to edit and rerun by hand); gnuplot
    # itself writes temporaries, renamed only when all charts are drawn.
    def text(which):
        return "\n".join(f"set output {quoted(outputs[x[1]][which])}" if isinstance(x, tuple) else x
                         for x in script) + "\n"
    gp = os.path.join(charts, "charts.gp")
    write_atomic(gp, text(1))
    r = subprocess.run([gnuplot], input=text(0), capture_output=True, text=True)
    if r.returncode != 0:
        print(f"sweep: gnuplot failed on {gp}:\n{r.stderr.strip()}", file=sys.stderr)
        for tmp, _ in outputs:
            if os.path.exists(tmp):
                os.remove(tmp)
        return
    for tmp, final in outputs:
        os.replace(tmp, final)
    print(f"sweep: {drawn} charts (PNG and SVG) in {charts}/")


if __name__ == "__main__":
    # a reader that stops early (`| head`) ends this quietly, as it does a C tool
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    sys.exit(main())
