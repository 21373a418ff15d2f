#!/usr/bin/env bash
# accel_table.sh — BVH2 vs MBVH4 on scenes and ray types (paper Table 2's
# directions): MRPS, DRAM traffic, cache hit rates, from rtsim's JSON statistics.
#   scripts/accel_table.sh [BUILD_DIR] [RES] [SCENE...]
# Arguments:
#   BUILD_DIR   the build whose bin/rtsim runs (default build)
#   RES         resolution WxH of every run (default 1280x720)
#   SCENE...    built-in names or scene files (default the four built-in scenes)
#   -h, --help  this text
# RAYS="primary" in the environment limits the ray types (default primary
# and diffuse). Prints a Markdown table on stdout; the JSON of every run
# stays in BUILD_DIR/accel_table/.
set -euo pipefail
case ${1:-} in -h|--help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 0 ;; esac
cd "$(dirname "$0")/.."
build=${1:-build}
res=${2:-1280x720}
shift $(( $# >= 2 ? 2 : $# ))
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(interior hairball city forest)
bin=$build/bin/rtsim
out=$build/accel_table
mkdir -p "$out"
echo "| scene | rays | machine | rays traced | cycles | MRPS | DRAM MB | DRAM GB/s | node L1 hit | node L2 hit | prim hit | host s |"
echo "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for s in "${scenes[@]}"; do
  for r in ${RAYS:-primary diffuse}; do
    for m in bvh2 mbvh4; do
      j=$out/$(basename "$s")_${r}_${m}_$res.json
      t0=$(date +%s.%N)
      "$bin" "$s" --res "$res" --machine "$m" --rays "$r" --quiet --json "$j"
      t1=$(date +%s.%N)
      python3 - "$j" "$s" "$r" "$m" "$t0" "$t1" <<'PY'
import json, os, sys
d = json.load(open(sys.argv[1]))
s, r, m, t0, t1 = sys.argv[2:7]
g = lambda k: d.get(k, 0) or 0
print(f"| {os.path.basename(s)} | {r} | {m} | {g('rays')} | {g('cycles')} | {g('mrps'):.2f} | {g('dram_bytes')/1e6:.2f} | "
      f"{g('dram_bandwidth_gbs'):.2f} | {100*g('node_l1.hit_rate'):.1f}% | {100*g('node_l2.hit_rate'):.1f}% | "
      f"{100*g('prim.hit_rate'):.1f}% | {float(t1)-float(t0):.1f} |")
PY
    done
  done
done
