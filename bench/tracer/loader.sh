#!/usr/bin/env bash
# Scene loading: our OBJ/PLY readers vs Assimp on the same uncompressed files
# (docs/tracer-io.md). Invoked by bench/tracer.sh, or alone:
#   bash bench/tracer/loader.sh [BUILD_DIR]
# Inputs from ../shared/scenes (skipped when absent), decompressed into
# BUILD_DIR/bench/scenes/; the sponza stand-in is also converted to OBJ so the
# OBJ readers see a 277K-triangle file. Single-threaded, median of RUNS (5).
# stdout: CSV rows "benchmark,ours_median_s,reference_median_s,ratio"
# (ratio = reference/ours, > 1 means we are faster), no header.
# stderr: a readable table.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
runs=${RUNS:-5}
bin=$build/bench/tracer_loader
if [ ! -x "$bin" ]; then make -s BUILD="$build" "$bin" >&2; fi
scenes=${RTSIM_SCENES:-}
for d in ../shared/scenes ../../shared/scenes; do
  if [ -z "$scenes" ] && [ -f "$d/README.md" ]; then scenes=$d; fi
done
if [ -z "$scenes" ]; then
  echo "loader bench: ../shared/scenes absent (set RTSIM_SCENES); nothing to measure" >&2
  exit 0
fi
work=$build/bench/scenes
mkdir -p "$work"
unpack() { # src.gz dst
  if [ ! -s "$2" ]; then gzip -dc "$1" >"$2.tmp" && mv "$2.tmp" "$2"; fi
}
unpack "$scenes/bunny/stanford-bunny.obj.gz" "$work/bunny.obj"
unpack "$scenes/sponza-ravenbridge/stk_ravenbridge_mansion.ply.gz" "$work/sponza.ply"
unpack "$scenes/hairball-furball/furBall_A_tubes3.ply.gz" "$work/furball.ply"
[ -s "$work/sponza.obj" ] || "$bin" --to-obj "$work/sponza.ply" "$work/sponza.obj"

printf '%-28s %10s %12s %12s %8s\n' benchmark triangles "ours (s)" "Assimp (s)" speedup >&2
for case in "load_obj_bunny_69k:bunny.obj" "load_obj_sponza_277k:sponza.obj" \
            "load_ply_sponza_277k:sponza.ply" "load_ply_furball_2733k:furball.ply"; do
  name=${case%%:*} file=$work/${case#*:}
  read -r ours ref tris tris_ref < <("$bin" "$file" "$runs")
  if [ "$tris" != "$tris_ref" ]; then
    echo "loader bench: $name: triangle counts differ: ours $tris, Assimp $tris_ref" >&2
  fi
  ratio=$(awk -v o="$ours" -v r="$ref" 'BEGIN { printf "%.2f", r / o }')
  printf '%-28s %10s %12s %12s %7sx\n' "$name" "$tris" "$ours" "$ref" "$ratio" >&2
  echo "$name,$ours,$ref,$ratio"
done
