#!/usr/bin/env bash
# Renders the small heatmap PNGs of the built-in scenes into docs/images/
# (committed; shown in docs/tracer-log.md): node visits and triangle tests
# per pixel of the default view's primary rays, MBVH4, 320x180, with rttrace.
#   scripts/render-heatmaps.sh [BUILD_DIR]
# Arguments:
#   BUILD_DIR   the build to make and use rttrace from (default build)
#   -h, --help  this text
set -euo pipefail
case ${1:-} in -h|--help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 0 ;; esac
cd "$(dirname "$0")/.."
build=${1:-build}
make -s "$build/bin/rttrace"
mkdir -p docs/images
for s in interior hairball city forest; do
  "$build/bin/rttrace" "$s" --res 320x180 --bvh mbvh4 --quiet \
    --heatmap-visits "docs/images/heatmap-visits-$s.png" --heatmap-tris "docs/images/heatmap-tris-$s.png"
done
ls -l docs/images/heatmap-*.png >&2
