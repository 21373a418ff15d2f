#!/usr/bin/env bash
# tb_report — scripts/report's page of a run, rendered by a real browser
# (headless Chromium, Debian `chromium`): it loads without a script error,
# every chart is laid out with its marks (the page's own check, read back
# with --dump-dom), it names the fidelity level and the bottleneck, embeds
# the heatmap, loads nothing from the network, marks windowed's windows;
# bad input exits 2 naming the file or option and leaves no page.
set -u
bin=${RTSIM_BIN:?}/rtsim
root=$(cd "$(dirname "$0")/../.." && pwd)
report=$root/scripts/report
tmp=${RTSIM_TMP:-/tmp}/tb_report
rm -rf "$tmp"; mkdir -p "$tmp/home"
. "$(dirname "$0")/../cli_lib.sh"

"$bin" interior --res 64x36 --rays diffuse --bounces 2 --quiet --json "$tmp/run.json" --series "$tmp/run.csv" \
  --series-interval 2000 --heatmap "$tmp/heat.png" >/dev/null 2>&1
"$bin" interior --res 128x72 --rays diffuse --fidelity windowed --jobs 2 --quiet --json "$tmp/win.json" \
  --series "$tmp/win.csv" --series-interval 2000 >/dev/null 2>&1
"$report" "$tmp/run.json" "$tmp/run.csv" --heatmap "$tmp/heat.png" -o "$tmp/run.html" 2>"$tmp/report.err"
check report_written test -s "$tmp/run.html"
"$report" "$tmp/win.json" "$tmp/win.csv" -o "$tmp/win.html" 2>>"$tmp/report.err"
cp "$tmp/run.json" "$tmp/plain.json"
"$report" "$tmp/plain.json" 2>>"$tmp/report.err"   # no series: default output beside the JSON
check report_default_output_beside_json test -s "$tmp/plain.html"

charts="bars-utilization bars-energy bars-area chart-throughput chart-utilization chart-dram chart-dram-queue chart-power chart-inflight chart-hits"
check report_has_sections python3 - "$tmp/run.html" <<'PY'
import re, sys
s = open(sys.argv[1]).read()
need = ['id="fom"', 'id="bottleneck"', 'id="machine"', 'id="provenance"', 'id="units"', 'id="series"', 'id="heatmap"',
        "Fidelity level <b>full</b>", "data:image/png;base64,", "config_hash"]
miss = [n for n in need if n not in s]
# self-contained: nothing fetched (the only URL is the SVG namespace)
urls = set(re.findall(r"(?:src|href)\s*=\s*[\"']?(https?:[^\"' >]*)", s)) | set(re.findall(r"url\(\s*[\"']?https?:", s))
sys.exit(1 if miss or urls else 0)
PY
check report_windowed_marks_windows python3 -c "
import sys; s = open(sys.argv[1] + '/win.html').read()
sys.exit(0 if 'Fidelity level <b>windowed</b>' in s and s.count('class=\"band\"') >= 2 else 1)" "$tmp"

# the browser: Debian's chromium, as the page's reader would open it
chrome=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$chrome" ]; then
  echo "SKIP report_renders_in_chromium: chromium is not installed (scripts/install-deps.sh installs it)"
else
  render() { # page -> DOM after load
    HOME="$tmp/home" timeout 120 "$chrome" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
      --disable-background-networking --disable-component-update --disable-sync --user-data-dir="$(mktemp -d "$tmp/profile.XXXXXX")" \
      --virtual-time-budget=5000 --dump-dom "file://$1" 2>>"$tmp/chromium.err"
  }
  render "$tmp/run.html" >"$tmp/run.dom"
  render "$tmp/win.html" >"$tmp/win.dom"
  check report_renders_in_chromium python3 - "$tmp/run.dom" "$charts" <<'PY'
import re, sys
dom, want = open(sys.argv[1]).read(), sys.argv[2].split()
m = re.search(r'<div id="selfcheck"[^>]*>', dom)
assert m, "the page's check did not run (no selfcheck)"
tag = m.group(0)
attr = dict(re.findall(r'data-([a-z]+)="([^"]*)"', tag))
assert attr.get("ok") == "1", "charts not laid out: %s" % attr.get("bad")
ids = attr.get("ids", "").split()
assert all(w in ids for w in want), "missing charts: %s" % [w for w in want if w not in ids]
assert 'data-count' not in re.search(r'<div id="errors"[^>]*>', dom).group(0), "script errors"
PY
  "$root/scripts/sweep" --set-grid trv.count=2,4 --machines bvh2,mbvh4 --res 16x9 --rtsim "$bin" --jobs 2 \
    --out "$tmp/sweep" >/dev/null 2>&1
  render "$tmp/sweep/report.html" >"$tmp/sweep.dom"
  check report_sweep_page_renders python3 - "$tmp/sweep.dom" <<'PY'
import re, sys
dom = open(sys.argv[1]).read()
tag = re.search(r'<div id="selfcheck"[^>]*>', dom).group(0)
ids = dict(re.findall(r'data-([a-z]+)="([^"]*)"', tag))["ids"].split()
assert 'data-ok="1"' in tag and "chart-pareto" in ids and "chart-mrps-vs-trv.count" in ids, tag
assert "data-count" not in re.search(r'<div id="errors"[^>]*>', dom).group(0)
PY
  check report_windowed_renders python3 -c "
import re, sys; dom = open(sys.argv[1] + '/win.dom').read()
m = re.search(r'<div id=\"selfcheck\"[^>]*data-ok=\"1\"', dom)
sys.exit(0 if m and 'data-count' not in re.search(r'<div id=\"errors\"[^>]*>', dom).group(0) else 1)" "$tmp"
fi

# bad input: exit 2, a message naming the file or option, no page
expect report_missing_json 2 "report: $tmp/none.json: No such file" -- "$report" "$tmp/none.json" -o "$tmp/bad1.html"
echo '{"a": 1}' >"$tmp/other.json"
expect report_not_rtsim_json 2 "not an rtsim --json result" -- "$report" "$tmp/other.json" -o "$tmp/bad2.html"
printf 'a,b\n1,2\n' >"$tmp/other.csv"
expect report_not_series 2 "not an rtsim --series file" -- "$report" "$tmp/run.json" "$tmp/other.csv" -o "$tmp/bad3.html"
expect report_heatmap_not_png 2 "--heatmap $tmp/run.csv: not a PNG image" -- \
  "$report" "$tmp/run.json" --heatmap "$tmp/run.csv" -o "$tmp/bad4.html"
expect report_bad_peak 2 "--dram-peak-gbs abc: expected a bandwidth" -- "$report" "$tmp/run.json" --dram-peak-gbs abc
expect report_no_folder 2 "-o $tmp/no/such/x.html: the folder" -- "$report" "$tmp/run.json" -o "$tmp/no/such/x.html"
check report_bad_input_leaves_nothing sh -c '! ls "$1" | grep -q "^bad"' _ "$tmp"
