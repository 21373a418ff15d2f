#!/usr/bin/env bash
# Kernel speed against SystemC 2.3.4 (docs/kernel.md "Benchmarks").
#   bash bench/kernel.sh [BUILD_DIR]
# Runs each workload with our kernel (bench/kernel_ours.c) and with SystemC
# (bench/kernel_systemc.cpp) alternately, RUNS times each (default 5), and
# reports the medians of the simulation wall times (the programs time their
# simulation only, not process start-up) and ratio = SystemC / ours.
# Workloads (sizes fixed here; KERNEL_BENCH_SCALE=0.1 shrinks them all for
# a quick check): a ping-pong 10 M tokens (SystemC SC_METHOD, and a_thread
# with SC_THREAD, both against our method version), b 8-stage pipeline
# 10 M cycles, c 1000 self-re-triggering processes 10 M events, d = b with
# VCD tracing (each VCD goes to BUILD_DIR/bench/tmp and is deleted).
# Output: a readable table on stdout and BUILD_DIR/bench/kernel.csv.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
runs=${RUNS:-5}
scale=${KERNEL_BENCH_SCALE:-1}
ours=$build/bench/kernel_ours
ref=$build/bench/kernel_systemc
make -s BUILD="$build" "$ours" "$ref" >&2 # incremental: rebuilds stale programs
tmp=$build/bench/tmp
mkdir -p "$tmp"
n10m=$(awk -v s="$scale" 'BEGIN { printf "%d", 10000000 * s }')

median() { sort -g | awk '{ v[NR] = $1 } END { if (NR % 2) print v[(NR + 1) / 2]; else printf "%.6f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

# run_case NAME OURS_WORKLOAD REF_WORKLOAD N UNIT_LABEL
csv=$build/bench/kernel.csv
rows=()
printf '%-10s %12s %14s %8s %12s %12s\n' benchmark "ours (s)" "SystemC (s)" ratio "ours ns/op" "SC ns/op"
run_case() {
  local name=$1 ow=$2 rw=$3 n=$4
  local o_times=() r_times=() o_chk="" r_chk=""
  for ((i = 0; i < runs; i++)); do
    local ovcd="" rvcd=""
    if [ "$ow" = d ]; then ovcd=$tmp/ours.vcd; rvcd=$tmp/systemc; fi
    read -r t c < <("$ours" "$ow" "$n" $ovcd)
    o_times+=("$t"); o_chk=$c
    rm -f "$tmp/ours.vcd"
    # (d) writes hundreds of MB (SystemC several GB): let the kernel write them
    # back now, not during the next program's timed run
    if [ -n "$ovcd" ]; then sync; fi
    read -r t c < <("$ref" "$rw" "$n" $rvcd 2>/dev/null | tail -n 1)
    r_times+=("$t"); r_chk=$c
    rm -f "$tmp/systemc.vcd"
    if [ -n "$rvcd" ]; then sync; fi
  done
  local om rm_ ratio
  om=$(printf '%s\n' "${o_times[@]}" | median)
  rm_=$(printf '%s\n' "${r_times[@]}" | median)
  ratio=$(awk -v o="$om" -v r="$rm_" 'BEGIN { printf "%.2f", r / o }')
  printf '%-10s %12s %14s %7sx %12.1f %12.1f\n' "$name" "$om" "$rm_" "$ratio" \
    "$(awk -v t="$om" -v n="$n" 'BEGIN { print t / n * 1e9 }')" \
    "$(awk -v t="$rm_" -v n="$n" 'BEGIN { print t / n * 1e9 }')"
  if [ "$name" != c ] && [ "$o_chk" != "$r_chk" ]; then
    echo "  note: checksums differ (ours $o_chk, SystemC $r_chk)" >&2
  fi
  rows+=("$name,$om,$rm_,$ratio")
}
run_case a a a "$n10m"
run_case a_thread a a_thread "$n10m"
run_case b b b "$n10m"
run_case c c c "$n10m"
run_case d d d "$n10m"
{
  echo "benchmark,ours_median_s,reference_median_s,ratio"
  printf '%s\n' "${rows[@]}"
} >"$csv.tmp"
mv "$csv.tmp" "$csv"
rmdir "$tmp" 2>/dev/null || true
echo "medians of $runs runs; ratio = SystemC / ours (targets: >= 5 on a, b, c; >= 10 on d); $csv"
