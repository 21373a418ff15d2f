"""report_html.py — the parts of rtsim's HTML report pages (scripts/report
for a run, scripts/sweep_merge.py for a sweep): inline SVG charts (lines,
bars, scatter with a Pareto front), tables and the page around them.

Python standard library only; a page is one self-contained file (no network,
no external style or script). Every chart is an <svg class="chart"> with an
id; the page's small inline script checks, once loaded, that every chart was
laid out with its marks and writes the outcome into #selfcheck (and any
script error into #errors), which the headless-browser test reads back.
"""
import html
import math
import os
import tempfile

PALETTE = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#7f7f7f"]


def esc(s):
    return html.escape(str(s), quote=True)


def fmt(v, digits=4):
    """A number for a table: integers exact, reals to `digits` significant digits."""
    if v is None:
        return ""
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, int):
        return "{:,}".format(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            return "n/a"
        if v != 0 and (abs(v) >= 1e7 or abs(v) < 1e-3):
            return "%.*g" % (digits, v)
        return "%.*g" % (digits, v) if abs(v) < 10 ** digits else "{:,.0f}".format(v)
    return str(v)


def nice_ticks(lo, hi, n=5):
    """About n round tick values covering [lo, hi]."""
    if not (math.isfinite(lo) and math.isfinite(hi)) or hi <= lo:
        hi = lo + 1.0
    raw = (hi - lo) / max(n, 1)
    mag = 10 ** math.floor(math.log10(raw))
    step = next(m * mag for m in (1, 2, 2.5, 5, 10) if m * mag >= raw)
    first = math.floor(lo / step) * step
    ticks, t = [], first
    while t <= hi + step * 1e-9:
        ticks.append(round(t, 12))
        t += step
    if ticks[-1] < hi:
        ticks.append(ticks[-1] + step)
    return ticks


def tick_label(v):
    if v == 0:
        return "0"
    a = abs(v)
    if a >= 1e6 or a < 1e-2:
        return "%.3g" % v
    return ("%.6f" % v).rstrip("0").rstrip(".")


def line_chart(cid, title, xlabel, ylabel, series, bands=(), hlines=(), width=760, height=270, ymin=0.0, ymax=None,
               xticks=None, markers=False, logx=False):
    """series: [(name, xs, ys)] (None in ys: a gap); bands: [(x0, x1, label)]
    shaded; hlines: [(y, label)] dashed reference lines; xticks: [(x, label)]
    instead of numeric ticks; markers: a dot on every point; logx: log2 x axis."""
    if logx:
        series = [(n, [math.log2(x) for x in xs], ys) for n, xs, ys in series]
        xticks = [(math.log2(x), lab) for x, lab in xticks] if xticks else None
    ml, mt, mb = 64, 30, 44
    mr = min(max(150, 40 + 6 * max([len(str(n)) for n, _, _ in series] + [0])), width // 2)
    height = max(height, mt + mb + 16 * len(series) + 10)
    pw, ph = width - ml - mr, height - mt - mb
    xs_all = [x for _, xs, _ in series for x in xs]
    ys_all = [y for _, _, ys in series for y in ys if y is not None] + [y for y, _ in hlines]
    x0, x1 = (min(xs_all), max(xs_all)) if xs_all else (0.0, 1.0)
    if x1 <= x0:
        x1 = x0 + 1.0
    y0 = ymin if ymin is not None else (min(ys_all) if ys_all else 0.0)
    y1 = ymax if ymax is not None else (max(ys_all) if ys_all else 1.0)
    if y1 <= y0:
        y1 = y0 + 1.0
    yt = nice_ticks(y0, y1)
    y0, y1 = min(yt[0], y0), max(yt[-1], y1)
    if xticks:
        x0, x1 = min([x0] + [t for t, _ in xticks]), max([x1] + [t for t, _ in xticks])
        pad = (x1 - x0) * 0.05 or 0.5
        x0, x1 = x0 - pad, x1 + pad
    xt = [t for t in nice_ticks(x0, x1, 6) if x0 <= t <= x1] if not xticks else [t for t, _ in xticks]
    xtl = dict(xticks) if xticks else {}
    X = lambda x: ml + (x - x0) / (x1 - x0) * pw
    Y = lambda y: mt + ph - (y - y0) / (y1 - y0) * ph
    o = ['<svg class="chart" id="%s" xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d" '
         'role="img" aria-label="%s">' % (esc(cid), width, height, width, height, esc(title))]
    o.append('<text x="%d" y="18" class="ct">%s</text>' % (ml, esc(title)))
    for b0, b1, lab in bands:
        o.append('<rect class="band" x="%.1f" y="%d" width="%.1f" height="%d"><title>%s</title></rect>'
                 % (X(b0), mt, max(X(b1) - X(b0), 0.5), ph, esc(lab)))
    for t in yt:
        o.append('<line class="grid" x1="%d" x2="%d" y1="%.1f" y2="%.1f"/>' % (ml, ml + pw, Y(t), Y(t)))
        o.append('<text class="yl" x="%d" y="%.1f">%s</text>' % (ml - 6, Y(t) + 4, tick_label(t)))
    for t in xt:
        o.append('<line class="tick" x1="%.1f" x2="%.1f" y1="%d" y2="%d"/>' % (X(t), X(t), mt + ph, mt + ph + 4))
        o.append('<text class="xl" x="%.1f" y="%d">%s</text>' % (X(t), mt + ph + 16, esc(xtl.get(t, tick_label(t)))))
    o.append('<rect class="frame" x="%d" y="%d" width="%d" height="%d"/>' % (ml, mt, pw, ph))
    for y, lab in hlines:
        o.append('<line class="ref" x1="%d" x2="%d" y1="%.1f" y2="%.1f"/><text class="refl" x="%d" y="%.1f">%s</text>'
                 % (ml, ml + pw, Y(y), Y(y), ml + pw - 4, Y(y) - 4, esc(lab)))
    for i, (name, xs, ys) in enumerate(series):
        col = PALETTE[i % len(PALETTE)]
        parts, pen = [], False
        for x, y in zip(xs, ys):
            if y is None:
                pen = False
                continue
            parts.append("%s%.1f,%.1f" % ("L" if pen else "M", X(x), Y(y)))
            pen = True
        o.append('<path class="series" d="%s" stroke="%s"><title>%s</title></path>' % (" ".join(parts) or "M0,0", col, esc(name)))
        if markers:
            for x, y in zip(xs, ys):
                if y is not None:
                    o.append('<circle cx="%.1f" cy="%.1f" r="3" fill="%s"><title>%s: %s</title></circle>'
                             % (X(x), Y(y), col, esc(name), fmt(y)))
        ly = mt + 12 + 16 * i
        o.append('<line x1="%d" x2="%d" y1="%d" y2="%d" stroke="%s" stroke-width="3"/>'
                 '<text class="lg" x="%d" y="%d">%s</text>' % (ml + pw + 10, ml + pw + 26, ly - 4, ly - 4, col,
                                                             ml + pw + 30, ly, esc(name)))
    o.append('<text class="al" x="%.1f" y="%d">%s</text>' % (ml + pw / 2, height - 6, esc(xlabel)))
    o.append('<text class="al" transform="translate(14,%.1f) rotate(-90)">%s</text>' % (mt + ph / 2, esc(ylabel)))
    o.append("</svg>")
    return "\n".join(o)


def bar_chart(cid, title, unit, items, width=760, bar_h=20, parts=None):
    """items: [(label, value)] or, with parts=[names], [(label, [v1, v2, ...])]
    stacked; horizontal bars with the value at the end."""
    ml, mr, mt = 130, 120, 30
    n = len(items)
    height = mt + n * (bar_h + 8) + (26 if parts else 8)
    pw = width - ml - mr
    tot = [sum(v) if isinstance(v, (list, tuple)) else v for _, v in items]
    vmax = max([t for t in tot if t is not None and math.isfinite(t)] + [0]) or 1.0
    o = ['<svg class="chart" id="%s" xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d" '
         'role="img" aria-label="%s">' % (esc(cid), width, height, width, height, esc(title))]
    o.append('<text x="%d" y="18" class="ct">%s</text>' % (ml, esc(title)))
    for i, (lab, v) in enumerate(items):
        y = mt + i * (bar_h + 8)
        o.append('<text class="yl" x="%d" y="%d">%s</text>' % (ml - 6, y + bar_h - 5, esc(lab)))
        vals = v if isinstance(v, (list, tuple)) else [v]
        x = ml
        for k, part in enumerate(vals):
            w = (part or 0) / vmax * pw
            col = PALETTE[k % len(PALETTE)] if parts else PALETTE[0]
            o.append('<rect class="bar" x="%.1f" y="%d" width="%.1f" height="%d" fill="%s"><title>%s%s: %s %s</title></rect>'
                     % (x, y, max(w, 0.0), bar_h, col, esc(lab), (" " + esc(parts[k])) if parts else "", fmt(part), esc(unit)))
            x += w
        o.append('<text class="lg" x="%.1f" y="%d">%s %s</text>' % (x + 6, y + bar_h - 5, fmt(tot[i]), esc(unit)))
    if parts:
        y = mt + n * (bar_h + 8) + 14
        for k, p in enumerate(parts):
            o.append('<rect x="%d" y="%d" width="12" height="10" fill="%s"/><text class="lg" x="%d" y="%d">%s</text>'
                     % (ml + 110 * k, y - 9, PALETTE[k % len(PALETTE)], ml + 110 * k + 16, y, esc(p)))
    o.append("</svg>")
    return "\n".join(o)


def pareto_front(points):
    """Indices of the points no other point beats: higher x is better, lower y
    is better (e.g. MRPS/mm2 against mJ/frame)."""
    front = []
    for i, (x, y) in enumerate(points):
        if not any((x2 >= x and y2 <= y) and (x2 > x or y2 < y) for j, (x2, y2) in enumerate(points) if j != i):
            front.append(i)
    return front


def scatter_chart(cid, title, xlabel, ylabel, pts, front=(), width=760, height=340):
    """pts: [(x, y, label)]; the points of `front` (indices) are marked and
    joined by a line."""
    ml, mr, mt, mb = 64, 30, 30, 44
    pw, ph = width - ml - mr, height - mt - mb
    xs = [p[0] for p in pts] or [0, 1]
    ys = [p[1] for p in pts] or [0, 1]
    xt, yt = nice_ticks(min(xs), max(xs)), nice_ticks(min(ys), max(ys))
    x0, x1, y0, y1 = xt[0], xt[-1], yt[0], yt[-1]
    X = lambda x: ml + (x - x0) / ((x1 - x0) or 1) * pw
    Y = lambda y: mt + ph - (y - y0) / ((y1 - y0) or 1) * ph
    o = ['<svg class="chart" id="%s" xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d" '
         'role="img" aria-label="%s">' % (esc(cid), width, height, width, height, esc(title))]
    o.append('<text x="%d" y="18" class="ct">%s</text>' % (ml, esc(title)))
    for t in yt:
        o.append('<line class="grid" x1="%d" x2="%d" y1="%.1f" y2="%.1f"/><text class="yl" x="%d" y="%.1f">%s</text>'
                 % (ml, ml + pw, Y(t), Y(t), ml - 6, Y(t) + 4, tick_label(t)))
    for t in xt:
        o.append('<line class="tick" x1="%.1f" x2="%.1f" y1="%d" y2="%d"/><text class="xl" x="%.1f" y="%d">%s</text>'
                 % (X(t), X(t), mt + ph, mt + ph + 4, X(t), mt + ph + 16, tick_label(t)))
    o.append('<rect class="frame" x="%d" y="%d" width="%d" height="%d"/>' % (ml, mt, pw, ph))
    fr = sorted(front, key=lambda i: pts[i][0])
    if len(fr) > 1:
        o.append('<path class="front" d="%s"/>' % " ".join("%s%.1f,%.1f" % ("L" if k else "M", X(pts[i][0]), Y(pts[i][1]))
                                                             for k, i in enumerate(fr)))
    for i, (x, y, lab) in enumerate(pts):
        on = i in front
        o.append('<circle class="%s" cx="%.1f" cy="%.1f" r="%d"><title>%s: %s, %s%s</title></circle>'
                 % ("pf" if on else "pt", X(x), Y(y), 6 if on else 4, esc(lab), fmt(x), fmt(y), " (Pareto front)" if on else ""))
    o.append('<text class="al" x="%.1f" y="%d">%s</text>' % (ml + pw / 2, height - 6, esc(xlabel)))
    o.append('<text class="al" transform="translate(14,%.1f) rotate(-90)">%s</text>' % (mt + ph / 2, esc(ylabel)))
    o.append("</svg>")
    return "\n".join(o)


def table(rows, head=None, cls="kv"):
    o = ['<table class="%s">' % cls]
    if head:
        o.append("<tr>" + "".join("<th>%s</th>" % esc(h) for h in head) + "</tr>")
    for r in rows:
        o.append("<tr>" + "".join("<td>%s</td>" % c for c in r) + "</tr>")
    o.append("</table>")
    return "\n".join(o)


STYLE = """
body{font:14px/1.45 system-ui,-apple-system,'Segoe UI',sans-serif;margin:24px auto;max-width:980px;color:#222;padding:0 12px}
h1{font-size:22px;margin:0 0 4px}h2{font-size:17px;border-bottom:1px solid #ccc;padding-bottom:3px;margin-top:28px}
.sub{color:#555;margin:0 0 12px}table{border-collapse:collapse;margin:8px 0}td,th{padding:3px 10px;border-bottom:1px solid #eee;
text-align:left;vertical-align:top}th{background:#f4f4f4}table.kv td:first-child{color:#555;white-space:nowrap}
td.num,th.num{text-align:right}code{font-size:12px;background:#f6f6f6;padding:1px 3px;word-break:break-all}
.flag{color:#b00;font-weight:600}.ok{color:#070}.note{color:#555;font-size:13px}.bottleneck{background:#fff8e6;
border-left:4px solid #e8a500;padding:8px 12px;margin:10px 0}
svg.chart{display:block;margin:10px 0;font-size:11px;background:#fff}svg .ct{font-size:13px;font-weight:600}
svg .grid{stroke:#e6e6e6}svg .tick{stroke:#888}svg .frame{fill:none;stroke:#888}svg .yl{text-anchor:end;fill:#444}
svg .xl{text-anchor:middle;fill:#444}svg .al{text-anchor:middle;fill:#333}svg .lg{fill:#333}
svg .series{fill:none;stroke-width:1.6}svg .band{fill:#ffe9a8;opacity:.55}svg .ref{stroke:#b00;stroke-dasharray:5 4}
svg .refl{text-anchor:end;fill:#b00}svg .pt{fill:#9bb7d4;stroke:#1f77b4}svg .pf{fill:#d62728;stroke:#600}
svg .front{fill:none;stroke:#d62728;stroke-width:1.5;stroke-dasharray:4 3}img.heatmap{max-width:100%;image-rendering:pixelated;border:1px solid #ccc}
"""

SELFCHECK = """
<div id="errors" hidden></div><div id="selfcheck" hidden></div>
<script>
window.addEventListener('error', function (e) {
  var d = document.getElementById('errors'); d.hidden = false;
  d.setAttribute('data-count', String(1 + Number(d.getAttribute('data-count') || 0)));
  d.textContent += 'error: ' + e.message + '\\n';
});
window.addEventListener('load', function () {
  var bad = [], charts = document.querySelectorAll('svg.chart');
  charts.forEach(function (s) {
    var r = s.getBoundingClientRect(), marks = s.querySelectorAll('path,rect,circle').length;
    if (!(r.width > 0 && r.height > 0 && marks > 1)) bad.push(s.id);
  });
  var c = document.getElementById('selfcheck');
  c.setAttribute('data-charts', String(charts.length));
  c.setAttribute('data-ids', Array.prototype.map.call(charts, function (s) { return s.id; }).join(' '));
  c.setAttribute('data-bad', bad.join(' '));
  c.setAttribute('data-ok', bad.length ? '0' : '1');
});
</script>
"""


def page(title, subtitle, body):
    return ('<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">\n<title>%s</title>\n'
            '<meta name="viewport" content="width=device-width,initial-scale=1">\n<style>%s</style></head>\n<body>\n'
            '<h1>%s</h1><p class="sub">%s</p>\n%s\n%s</body></html>\n'
            % (esc(title), STYLE, esc(title), subtitle, body, SELFCHECK))


def write_atomic(path, text):
    """Writes text to path through a temporary file in the same folder,
    renamed when complete ('-' writes to stdout)."""
    if path == "-":
        import sys
        sys.stdout.write(text)
        return
    d = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", dir=d)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
