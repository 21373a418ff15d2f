#!/usr/bin/env bash
# Fidelity levels' speed (docs/fidelity.md): host CPU time of each level
# against the full model on one primary workload (interior 640x360, MBVH4)
# and one diffuse workload (hairball 320x180, MBVH4), and of the windowed
# level (made for large frames) on interior 1280x720, primary and diffuse,
# and there --accuracy 2% (accuracy2: what a fallback to full costs over a
# plain full run, a speedup under 1) and, on diffuse rays, --accuracy 5%
# (accuracy5: where windowed's interval fits), and --accuracy 5% on forest
# 1280x720 diffuse BVH2 (a fallback at 5%: windowed's pilot and sampled's
# groups give up); median of RUNS (3) runs, one core
# (--jobs 1), with the level's true MRPS error against full.
#   bash bench/fidelity.sh [BUILD_DIR]
# CSV (BUILD_DIR/bench/fidelity.csv): benchmark,ours_median_s,reference_median_s,ratio
# where ours = the level's time, reference = the full model's time, ratio =
# speedup (reference / ours); the printed table adds the MRPS error and flag.
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/common.bash
bench_setup fidelity 3 "${1:-build}"

# run ARGS... -> med (host CPU s), mrps, flag (of the last run)
run() {
  : >"$tmp/times"
  for _ in $(seq "$runs"); do
    "$bin" "$@" --json "$tmp/r.json" >"$tmp/out"
    host_cpu <"$tmp/out" >>"$tmp/times"
  done
  med=$(median <"$tmp/times")
  mrps=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["mrps"])' "$tmp/r.json")
  flag=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["unreliable"])' "$tmp/r.json")
}

printf '%-44s %10s %10s %9s %12s %8s\n' benchmark "host (s)" "full (s)" speedup "MRPS error" flagged >&2
for w in "interior_640x360_primary fixed-mem,functional,sampled interior --res 640x360 --rays primary" \
         "hairball_320x180_diffuse fixed-mem,functional,sampled hairball --res 320x180 --rays diffuse" \
         "interior_1280x720_primary windowed,accuracy2 interior --res 1280x720 --rays primary" \
         "interior_1280x720_diffuse windowed,accuracy2,accuracy5 interior --res 1280x720 --rays diffuse" \
         "forest_1280x720_diffuse_bvh2 accuracy5 forest --res 1280x720 --rays diffuse --machine bvh2"; do
  set -- $w
  name=$1 levels=$2; shift 2
  run "$@"
  full=$med full_mrps=$mrps
  for lv in ${levels//,/ }; do
    case $lv in
      accuracy*) run "$@" --accuracy "${lv#accuracy}%" --jobs 1 ;;
      *) run "$@" --fidelity "$lv" --jobs 1 ;;
    esac
    sp=$(awk -v o="$med" -v r="$full" 'BEGIN { printf "%.2f", (o > 0 ? r / o : 0) }')
    er=$(awk -v a="$mrps" -v b="$full_mrps" 'BEGIN { e = (a / b - 1) * 100; printf "%+.1f%%", e }')
    printf '%-44s %10.3f %10.3f %8sx %12s %8s\n' "${name}_$lv" "$med" "$full" "$sp" "$er" "$flag" >&2
    echo "${name}_$lv,$med,$full,$sp" >>"$csv"
  done
done
mv "$csv" "$out/fidelity.csv"
echo "fidelity bench: $out/fidelity.csv (ratio = speedup against the full model)" >&2
