#!/usr/bin/env bash
# tb_sensitivity — scripts/sensitivity on a tiny case (interior, 8x8,
# primary rays): every unpublished parameter varied to half and double on
# both machines (the run for ist.latency=32, double the default 16, exists;
# a variant the validator refuses is reported as such),
# the CSV has a row per parameter, variant and figure, the Markdown table
# names every parameter and says whether a conclusion flips, and gnuplot
# wrote a tornado chart per figure.
set -u
tmp=${RTSIM_TMP:-/tmp}/tb_sensitivity
rm -rf "$tmp"; mkdir -p "$tmp"
cd "$(dirname "$0")/../.."
. testbench/cli_lib.sh
if [ -n "${RTSIM_TB_SANITIZED:-}" ]; then
  echo "SKIP sensitivity: 62 model runs; the release build covers the script"; exit 0
fi
if ! command -v gnuplot >/dev/null; then
  echo "SKIP sensitivity: gnuplot is not installed (scripts/debian-packages.txt lists it)"; exit 0
fi
scripts/sensitivity --bin "${RTSIM_BIN:?}/rtsim" --scenes interior --rays primary --res 8x8 --jobs 2 \
  --out "$tmp/out" >"$tmp/log" 2>&1
check sensitivity_runs test $? -eq 0
n=$(tail -n +2 "$tmp/out/sensitivity.csv" | wc -l)
# every variant but one (15 parameters): halving the TRV loop FIFO puts it
# below its deadlock-free minimum, which the validator refuses (reported, not
# a row); the other ray FIFOs are varied apart from it and measured at half
check sensitivity_csv_rows test "$n" -eq $(((15 * 2 - 1) * 4))
check sensitivity_refused_reported grep -q "TRV loop FIFO depth at half: fifo.ray_trv_loop" "$tmp/out/sensitivity.md"
check sensitivity_md_names_params sh -c 'for p in "L1 MSHRs" "IST latency" "ray FIFO depths" "TRV loop FIFO depth" "shade latency"; do grep -q "| $p |" "$1/out/sensitivity.md" || exit 1; done' _ "$tmp"
check sensitivity_md_flip_verdict grep -qE 'flip' "$tmp/out/sensitivity.md"
h=$(printf 'ist.latency=32' | sha1sum | cut -c1-12)
check sensitivity_ist_double_run test -s "$tmp/out/runs/interior_primary_mbvh4_8x8_$h.json"
h=$(printf 'node_l1.mshrs=4' | sha1sum | cut -c1-12)
check sensitivity_l1_mshr_half_run test -s "$tmp/out/runs/interior_primary_mbvh4_8x8_$h.json"
pngs=$(ls "$tmp/out"/tornado-*.png 2>/dev/null | wc -l)
check sensitivity_tornado_charts test "$pngs" -eq 8
check sensitivity_png_is_png sh -c 'head -c 8 "$1/out/tornado-change-mrps.png" | grep -q PNG' _ "$tmp"
expect sensitivity_bad_rays 2 "allowed primary, diffuse" -- scripts/sensitivity --bin "$RTSIM_BIN/rtsim" --rays shadow
