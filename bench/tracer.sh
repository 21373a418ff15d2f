#!/usr/bin/env bash
# Tracer benchmarks against the reference tools (docs/tracer-bvh.md,
# docs/tracer-io.md), single-threaded, medians of RUNS (default 5) runs:
#   - scene loading vs Assimp (bench/tracer/loader.sh, rows merged here);
#   - BVH build time and traversal (primary and diffuse rays: 4 bounces,
#     seed 1, the same rays for both) vs Embree 3, on sponza-ravenbridge
#     (view hall) and hairball-furball from ../shared/scenes when present,
#     else on the built-in scenes.
#   bash bench/tracer.sh [BUILD_DIR]
# Writes BUILD_DIR/bench/tracer.csv (benchmark,ours_median_s,reference_median_s,ratio;
# ratio = reference/ours: > 1 means we are faster, >= 0.333 meets "within 3x")
# and prints a readable table.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
runs=${RUNS:-5}
res=${RES:-640x360}
bin=$build/bench/tracer_trace
if [ ! -x "$bin" ]; then make -s BUILD="$build" "$bin" >&2; fi
mkdir -p "$build/bench"
out=$build/bench/tracer.csv
tmp=$(mktemp "$out.XXXXXX")
trap 'rm -f "$tmp"' EXIT
echo "benchmark,ours_median_s,reference_median_s,ratio" >"$tmp"

if ! bash bench/tracer/loader.sh "$build" >>"$tmp"; then
  echo "tracer bench: the loader bench (bench/tracer/loader.sh) failed; its rows are missing" >&2
fi

scenes=${RTSIM_SCENES:-}
for d in ../shared/scenes ../../shared/scenes; do
  if [ -z "$scenes" ] && [ -f "$d/README.md" ]; then scenes=$d; fi
done
cases=()   # label|scene|view|width
if [ -n "$scenes" ] && [ -f "$scenes/sponza-ravenbridge/stk_ravenbridge_mansion.ply.gz" ]; then
  cases+=("sponza_277k|$scenes/sponza-ravenbridge/stk_ravenbridge_mansion.ply.gz|hall|4")
  cases+=("sponza_277k|$scenes/sponza-ravenbridge/stk_ravenbridge_mansion.ply.gz|hall|2")
fi
if [ -n "$scenes" ] && [ -f "$scenes/hairball-furball/furBall_A_tubes3.ply.gz" ]; then
  cases+=("furball_2733k|$scenes/hairball-furball/furBall_A_tubes3.ply.gz|front|4")
fi
if [ ${#cases[@]} -eq 0 ]; then
  echo "tracer bench: ../shared/scenes absent (set RTSIM_SCENES); timing the built-in scenes" >&2
  for s in interior hairball city forest; do cases+=("$s|$s||4"); done
fi

printf '\n%-34s %12s %12s %8s %14s %14s\n' benchmark "ours (s)" "Embree (s)" ratio "ours Mrays/s" "Embree Mrays/s" >&2
for c in "${cases[@]}"; do
  IFS='|' read -r label scene view width <<<"$c"
  args=("$scene" --runs "$runs" --res "$res" --width "$width")
  [ -n "$view" ] && args+=(--view "$view")
  while read -r what ours ref n; do
    case $what in
      build)
        [ "$width" = 4 ] || continue   # the build barely depends on the width: report it once
        name="bvh_build_${label}" ;;
      primary|diffuse) name="trace_${what}_${label}${view:+_$view}_w${width}" ;;
      *) continue ;;
    esac
    ratio=$(awk -v o="$ours" -v r="$ref" 'BEGIN { printf "%.3f", r / o }')
    if [ "$what" = build ]; then
      printf '%-34s %12.4f %12.4f %7sx %14s %14s\n' "$name" "$ours" "$ref" "$ratio" "-" "-" >&2
    else
      mo=$(awk -v o="$ours" -v n="$n" 'BEGIN { printf "%.2f", n / o / 1e6 }')
      mr=$(awk -v o="$ref" -v n="$n" 'BEGIN { printf "%.2f", n / o / 1e6 }')
      printf '%-34s %12.4f %12.4f %7sx %14s %14s\n' "$name" "$ours" "$ref" "$ratio" "$mo" "$mr" >&2
    fi
    echo "$name,$ours,$ref,$ratio" >>"$tmp"
  done < <("$bin" "${args[@]}" 2>/dev/null)
done
mv "$tmp" "$out"
trap - EXIT
echo "wrote $out" >&2
