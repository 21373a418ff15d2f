#!/usr/bin/env bash
# Accelerator model speed (docs/accel.md "Speed"): simulated cycles and rays per host second
# of the full model (scheduler, 4 TRVs, IST, node L1s, L2, primitive cache,
# LPDDR3) on the built-in interior scene, BVH2 and MBVH4, primary and diffuse,
# VCD off and on, and diffuse with the fixed-latency memory fidelity. Host time is the run alone (rtsim's "host" line: no scene
# loading or BVH build), median of RUNS (5) runs, one core.
#   bash bench/accel.sh [BUILD_DIR]
# Targets (docs/accel.md "Speed"): >= 2 M simulated cycles per host second with VCD
# off; VCD on at most 3x slower; --series at most 5% slower (20% with 10x
# finer rows). The CSV's reference_median_s is the target time (cycles / 2e6
# s, 3 x the VCD-off median, or 1.05 / 1.2 x the median without --series),
# so ratio >= 1 = target met
# (and, in rows with the cycles target, ratio x 2e6 = simulated cycles/s).
# Writes BUILD_DIR/bench/accel.csv and prints a table.
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/common.bash
bench_setup accel 5 "${1:-build}"

# run NAME ARGS... -> sets med (s), cycles, rays
run() {
  local name=$1; shift
  : >"$tmp/times"
  for _ in $(seq "$runs"); do
    "$bin" "$@" >"$tmp/out"
    host_cpu <"$tmp/out" >>"$tmp/times"
  done
  med=$(median <"$tmp/times")
  cycles=$(awk '/^cycles/ { print $2 }' "$tmp/out")
  rays=$(awk '/^rays/ { print $2 }' "$tmp/out")
}

printf '%-40s %10s %8s %10s %12s %12s %8s\n' benchmark cycles rays "host (s)" "Mcycles/s" "Krays/s" "target" >&2
row() { # name med cycles rays reference
  local mc kr ratio
  mc=$(awk -v c="$3" -v s="$2" 'BEGIN { printf "%.2f", c / s / 1e6 }')
  kr=$(awk -v r="$4" -v s="$2" 'BEGIN { printf "%.1f", r / s / 1e3 }')
  ratio=$(awk -v o="$2" -v r="$5" 'BEGIN { printf "%.2f", r / o }')
  printf '%-40s %10s %8s %10.3f %12s %12s %7sx\n' "$1" "$3" "$4" "$2" "$mc" "$kr" "$ratio" >&2
  echo "$1,$2,$5,$ratio" >>"$csv"
}

for m in bvh2 mbvh4; do
  run "interior_320x180_${m}_primary" interior --res 320x180 --machine "$m" --rays primary
  off=$med
  row "interior_320x180_${m}_primary" "$med" "$cycles" "$rays" "$(awk -v c="$cycles" 'BEGIN { print c / 2e6 }')"
  run "interior_320x180_${m}_primary_vcd" interior --res 320x180 --machine "$m" --rays primary --vcd "$tmp/w.vcd"
  row "interior_320x180_${m}_primary_vcd" "$med" "$cycles" "$rays" "$(awk -v o="$off" 'BEGIN { print 3 * o }')"
  run "interior_160x90_${m}_diffuse" interior --res 160x90 --machine "$m" --rays diffuse
  row "interior_160x90_${m}_diffuse" "$med" "$cycles" "$rays" "$(awk -v c="$cycles" 'BEGIN { print c / 2e6 }')"
  diffuse=$med
  # interval statistics (--series): the default rows within 5% of the same
  # run without them, 10x finer rows within 20%
  for n in 10000 1000; do
    run "interior_160x90_${m}_diffuse_series$n" interior --res 160x90 --machine "$m" --rays diffuse \
      --series "$tmp/s.csv" --series-interval "$n"
    row "interior_160x90_${m}_diffuse_series$n" "$med" "$cycles" "$rays" "$(awk -v o="$diffuse" -v n="$n" 'BEGIN { print (n >= 10000 ? 1.05 : 1.2) * o }')"
  done
  # the same with the fixed-latency memory fidelity: the LPDDR3 model's share
  run "interior_160x90_${m}_diffuse_fixedmem" interior --res 160x90 --machine "$m" --rays diffuse --set memory.model=fixed
  row "interior_160x90_${m}_diffuse_fixedmem" "$med" "$cycles" "$rays" "$(awk -v c="$cycles" 'BEGIN { print c / 2e6 }')"
done
mv "$csv" "$out/accel.csv"
echo "accel bench: $out/accel.csv (ratio >= 1: at least 2 M cycles/s, or VCD within 3x)" >&2
