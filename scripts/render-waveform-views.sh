#!/usr/bin/env bash
# Renders a GTKWave screenshot of every view in waveforms/*.gtkw into
# docs/images/waveform-<view>.png (committed; shown in docs/accel.md,
# "Waveforms"). Each view gets the dump its header documents (run by
# scripts/gtkw_dump_args.py), opens in GTKWave under Xvfb at its own [size],
# and the screen is grabbed with xwd once GTKWave has drawn it.
#   scripts/render-waveform-views.sh [BUILD_DIR]
# Arguments:
#   BUILD_DIR   the build whose bin/rtsim makes the dumps (default build)
#   -h, --help  this text
# Needs gtkwave, xvfb and xauth (scripts/debian-packages.txt) and, for the
# grab only, x11-apps (xwd) and imagemagick (convert), installed here on
# demand like afl++ for make fuzz.
set -euo pipefail
case ${1:-} in -h|--help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 0 ;; esac
cd "$(dirname "$0")/.."
root=$PWD

# Inside the X server (started below by xvfb-run): VCD VIEW OUT.png
if [ "${1:-}" = --grab ]; then
  vcd=$2 view=$3 png=$4 work=$(dirname "$4")
  # The Tcl script runs once the view is loaded; it prints a line to wait for.
  echo 'puts "view-loaded"; flush stdout' >"$work/ready.tcl"
  : >"$work/gtkwave.log"
  # from the dump's folder, so that the title shows only its file name
  (cd "$(dirname "$vcd")" && exec gtkwave -S "$work/ready.tcl" "$(basename "$vcd")" "$view") \
    >"$work/gtkwave.log" 2>&1 &
  gtkwave_pid=$!
  for _ in $(seq 300); do
    grep -q view-loaded "$work/gtkwave.log" && xwd -silent -name "GTKWave - $(basename "$vcd")" \
      -out /dev/null 2>/dev/null && break
    sleep 0.1
  done
  sleep 2 # let GTKWave finish drawing the waves
  xwd -silent -root -out "$work/screen.xwd"
  kill "$gtkwave_pid"; wait "$gtkwave_pid" 2>/dev/null || true
  # the window is at the screen's top left at the view's [size]; 64 colours
  # keep the PNG small (GTKWave draws few colours)
  size=$(sed -n 's/^\[size\] \([0-9]*\) \([0-9]*\)$/\1x\2/p' "$view")
  convert "$work/screen.xwd" -crop "${size:-1600x900}+0+0" +repage -colors 64 -strip "$png"
  exit 0
fi

build=${1:-build}
scripts/install-deps.sh gtkwave xvfb xauth x11-apps imagemagick
make -s "$build/bin/rtsim"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p docs/images
for view in waveforms/*.gtkw; do
  v=$(basename "$view" .gtkw)
  mapfile -t args < <(scripts/gtkw_dump_args.py "$view")
  for i in "${!args[@]}"; do [ "${args[$i]}" = waveforms/rtsim.vcd ] && args[i]=$work/rtsim.vcd; done
  "$build/bin/rtsim" "${args[@]}" --quiet
  xvfb-run -a -s "-screen 0 1600x1000x24" "$root/scripts/render-waveform-views.sh" --grab "$work/rtsim.vcd" "$root/$view" "$work/$v.png"
  mv "$work/$v.png" "docs/images/waveform-$v.png"
  rm -f "$work/rtsim.vcd"
done
ls -l docs/images/waveform-*.png >&2
