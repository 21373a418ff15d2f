#!/usr/bin/env bash
# tb_chart_paths — every chart script draws into a folder whose name holds a
# single quote, a double quote, a backslash and spaces (a checkout or output
# folder such as /home/o'brien): the scripts hand file names to gnuplot
# through scripts/gnuplot_text.py, and each chart must come out whole.
set -u
tmp=${RTSIM_TMP:-/tmp}/tb_chart_paths
rm -rf "$tmp"; mkdir -p "$tmp"
cd "$(dirname "$0")/../.."
. testbench/cli_lib.sh
bin=${RTSIM_BIN:?}
if ! command -v gnuplot >/dev/null; then
  echo "SKIP chart_paths: gnuplot is not installed (scripts/debian-packages.txt lists it)"; exit 0
fi
dir="$tmp/o'brien \"charts\" back\\slash"
mkdir -p "$dir"
png() { [ -s "$1" ] && [ "$(head -c 4 "$1" | tail -c 3)" = PNG ]; }

check chart_paths_gnuplot_text python3 -c '
import sys; sys.path.insert(0, "scripts")
from gnuplot_text import quoted
assert quoted("a'"'"'b\\c\"d") == "'"'"'a'"''"'b\\c\"d'"'"'", quoted("a'"'"'b\\c\"d")'

scripts/paper-tables --bin "$bin/rtsim" --scenes interior --res 16x9 --jobs 2 --out "$dir/pt" >"$tmp/pt.log" 2>&1
check chart_paths_paper_tables png "$dir/pt/changes.png"
check chart_paths_paper_tables_svg grep -q "<svg" "$dir/pt/changes.svg"

scripts/branching --bin "$bin/rtsim" --scenes interior --rays primary --res 8x8 --widths 3,4 --jobs 2 \
  --out "$dir/br" >"$tmp/br.log" 2>&1
check chart_paths_branching sh -c 'ls "$1"/branching-*.png | grep -q . && for f in "$1"/branching-*.png; do [ -s "$f" ] || exit 1; done' _ "$dir/br"

scripts/sweep --set-grid node_l1.size=4096,8192 --machines bvh2 --res 16x9 --rtsim "$bin/rtsim" \
  --out "$dir/sw" >"$tmp/sw.log" 2>&1
check chart_paths_sweep sh -c 'ls "$1"/charts/*.png | grep -q . && for f in "$1"/charts/*.png; do [ -s "$f" ] || exit 1; done' _ "$dir/sw"

"$bin/rtsim" interior --res 16x9 --quiet --series "$dir/s.csv" --series-interval 200 >/dev/null 2>&1
scripts/series-chart "$dir/s.csv" -o "$dir/series.png" >"$tmp/se.log" 2>&1
check chart_paths_series_chart png "$dir/series.png"

scripts/speed-accuracy --bin "$bin/rtsim" --scenes interior --rays primary --machines bvh2 --res 32x18 \
  --levels functional --out "$dir/sa" >"$tmp/sa.log" 2>&1
check chart_paths_speed_accuracy sh -c 'ls "$1"/speed-accuracy-*.png | grep -q . && for f in "$1"/speed-accuracy-*.png; do [ -s "$f" ] || exit 1; done' _ "$dir/sa"

scripts/bench-history draw -o "$dir/history.png" >"$tmp/bh.log" 2>&1
check chart_paths_bench_history png "$dir/history.png"
