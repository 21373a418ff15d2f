#!/usr/bin/env bash
# Renders the small preview PNGs of the built-in scenes into docs/images/
# (committed; referenced by docs/tracer-io.md and README). Uses
# scripts/rt_preview.c, which goes through the tracer I/O API.
#   scripts/render-previews.sh [BUILD_DIR]
# Arguments:
#   BUILD_DIR   the build to make and use scripts/rt_preview from (default build)
#   -h, --help  this text
set -euo pipefail
case ${1:-} in -h|--help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 0 ;; esac
cd "$(dirname "$0")/.."
build=${1:-build}
make -s "$build/scripts/rt_preview"
mkdir -p docs/images
for s in interior hairball city forest; do
  "$build/scripts/rt_preview" "$s" "docs/images/builtin-$s.png" --res 320x180
done
# One diffuse path-traced frame (4 bounces, averaged over 16 seeds) of the interior.
"$build/scripts/rt_preview" interior docs/images/builtin-interior-path16.png --res 320x180 --path --spp 16
ls -l docs/images/builtin-*.png >&2
