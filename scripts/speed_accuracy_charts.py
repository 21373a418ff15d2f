"""speed_accuracy_charts — the charts of scripts/speed-accuracy, from its rows.

Two kinds, PNG and SVG, with gnuplot:
  * DIR/speed-accuracy-<figure>.png: one panel per level, the speedup (CPU,
    log) against the true error (log, from 0.01%): filled blue points are
    reliable, open red ones flagged; the panel's title gives the median
    speedup and the range of the reliable points' true errors. One panel
    per level keeps the levels' clouds apart; the log error axis keeps
    0.1% and 10% errors both readable (a linear axis piled the good points
    on the y axis).
  * DIR/speed-accuracy-calibration.png: each reliable point's estimated
    error against its true error, log-log, the three figures of merit in
    three colours, with the line y = x: a point under the line is outside
    its estimate (the count must be zero), a point far above it is a wide
    estimate. A calibrated 95% interval puts most points 1.5-5x above the
    line (|error| of a normal variable averages 0.8 sigma, the half-width is
    1.96 sigma).
Standard library only (gnuplot does the drawing)."""
import math
import os

from gnuplot_text import quoted

FLOOR = 0.01   # % : true errors below it are drawn at it (a log axis has no 0)


def _median(v):
    v = sorted(v)
    return v[len(v) // 2] if v else float("nan")


def _defined(x, key):
    """A row's true error of the figure, or None where the full model's
    value is 0 (rtsim_runs.change_pct: the change is undefined, written empty)."""
    v = x["true_err_" + key]
    return None if v in ("", None) else float(v)


def draw(tool, out, runs, rows, levels, figures, res, gnuplot):
    """rows: speed-accuracy's rows (dicts); figures: (key, label, stat);
    gnuplot: rtsim_runs.gnuplot. Returns the files written."""
    outs, script = [], []
    n = len(levels)
    cols = min(n, 3)
    nrows = int(math.ceil(n / cols))
    for key, label, _ in figures:
        dat = os.path.join(runs, "chart-%s.dat" % key)
        with open(dat, "w") as f:
            for lv in levels:
                for flag in (0, 1):
                    for x in rows:
                        if x["level"] == lv and int(x["unreliable"]) == flag and _defined(x, key) is not None:
                            f.write("%.4f %s\n" % (max(float(x["true_err_" + key]), FLOOR), x["speedup"]))
                    f.write("\n\n")
        ymax = max([float(x["speedup"]) for x in rows] + [2.0]) * 1.5
        xmax = max([_defined(x, key) for x in rows if _defined(x, key) is not None] + [10.0]) * 1.5
        width = max(640, 420 * cols)   # the title needs the room with one panel
        for term, ext in (("pngcairo size %d,%d" % (width, 330 * nrows), "png"),
                          ("svg size %d,%d" % (width, 330 * nrows), "svg")):
            o = os.path.join(out, "speed-accuracy-%s.%s" % (key, ext))
            outs.append(o)
            s = ['set terminal %s\nset output %s\n' % (term, quoted(o + ".tmp")),
                 'set multiplot layout %d,%d title "rtsim fidelity levels: %s, %s (filled: reliable, open: flagged)"\n'
                 % (nrows, cols, label, res),
                 "set logscale xy\nset grid\nset xrange [%g:%g]\nset yrange [0.3:%g]\n" % (FLOOR, xmax, ymax),
                 'set xlabel "true error (%, log)"\nset ylabel "speedup vs full (CPU)"\nset key off\n']
            for i, lv in enumerate(levels):
                pr = [x for x in rows if x["level"] == lv]
                ok = [_defined(x, key) for x in pr if not int(x["unreliable"]) and _defined(x, key) is not None]
                rng = "%.2g-%.2g%%" % (min(ok), max(ok)) if ok else "none reliable"
                s.append('set title "%s: median %.2fx; reliable errors %s"\n'
                         % (lv, _median([float(x["speedup"]) for x in pr]), rng))
                s.append('plot %s index %d using 1:2 with points pt 7 lc rgb "#1f77b4", '
                         '%s index %d using 1:2 with points pt 6 lc rgb "#d62728"\n'
                         % (quoted(dat), 2 * i, quoted(dat), 2 * i + 1))
            s.append("unset multiplot\nunset output\n")
            script.append("".join(s))
    # calibration: estimate against true error, reliable points
    dat = os.path.join(runs, "chart-calibration.dat")
    vals = []
    with open(dat, "w") as f:
        for key, _, _ in figures:
            for x in rows:
                if not int(x["unreliable"]) and _defined(x, key) is not None:
                    t, e = max(float(x["true_err_" + key]), FLOOR), max(float(x["est_err_" + key]), FLOOR)
                    vals += [t, e]
                    f.write("%.4f %.4f\n" % (t, e))
            f.write("\n\n")
    if vals:
        hi = max(vals) * 1.5
        colours = ["#1f77b4", "#2ca02c", "#ff7f0e"]
        for term, ext in (("pngcairo size 640,560", "png"), ("svg size 640,560", "svg")):
            o = os.path.join(out, "speed-accuracy-calibration.%s" % ext)
            outs.append(o)
            plots = ", ".join('%s index %d using 1:2 with points pt 7 lc rgb "%s" title "%s"'
                              % (quoted(dat), i, colours[i % 3], figures[i][1]) for i in range(len(figures)))
            script.append('set terminal %s\nset output %s\nset logscale xy\nset grid\n'
                          'set xrange [%g:%g]\nset yrange [%g:%g]\n'
                          'set xlabel "true error vs full model (%%, log)"\nset ylabel "estimated error (%%, log)"\n'
                          'set title "rtsim fidelity: calibration of the estimates (%s, reliable points)"\n'
                          'set key bottom right box opaque\n'
                          'plot x with lines lc rgb "#000000" dt 2 title "y = x (under it: outside the estimate)", %s\n'
                          "unset output\n" % (term, quoted(o + ".tmp"), FLOOR, hi, FLOOR, hi, res, plots))
    gnuplot(tool, "".join(script), outs)
    return outs
