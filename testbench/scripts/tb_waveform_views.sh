#!/usr/bin/env bash
# tb_waveform_views — every GTKWave view in waveforms/*.gtkw opens in a real
# GTKWave with all of its traces. GTKWave drops a trace it cannot find in the
# dump without a word (a vector named without its bit range, a renamed
# variable), which the vcd2fst round trip of tb_kernel_vcd cannot see, so each
# view is loaded here into GTKWave under Xvfb and GTKWave's Tcl interface
# (--script) lists what it displays. Per view:
#   - the dump is made by the rtsim command written in the view's header
#     (window, filter and machine as documented; only the output path and,
#     under the sanitizers, the frame size differ);
#   - gtkw_<view>_traces: every trace the view names is displayed, none is missing;
#   - gtkw_<view>_labels: each trace's label is its unit and variable ("trv0 state",
#     the dotted name with spaces, see waveforms/accel_overview.gtkw), and no
#     two traces share a label;
#   - gtkw_<view>_window: the view opens on a useful window (at least 50 cycles of
#     the default 500 MHz clock, inside the dump), not GTKWave's 0..5 ns.
# Also: accel_overview on a bvh2 dump (it claims both machines), and a control
# that the check fails when it should (the overview with its bit ranges
# removed, as the views were first written: the vectors must be reported
# missing). SKIPs, saying why, without gtkwave or an X server (Xvfb, or
# $DISPLAY when xvfb-run is absent).
set -u
bin=${RTSIM_BIN:?}/rtsim
root=$(cd "$(dirname "$0")/../.." && pwd)
tmp=${RTSIM_TMP:-/tmp}/tb_waveform_views
rm -rf "$tmp"; mkdir -p "$tmp"

. "$(dirname "$0")/../cli_lib.sh"

if ! command -v gtkwave >/dev/null 2>&1; then
  echo "SKIP waveform_views: gtkwave not installed (Debian package gtkwave)"; exit 0
fi
# The views' window is measured in pixels: the X screen holds their [size].
if command -v xvfb-run >/dev/null 2>&1; then
  xrun=(xvfb-run -a -s "-screen 0 1600x1000x24")
elif [ -n "${DISPLAY:-}" ]; then
  xrun=()
else
  echo "SKIP waveform_views: no X server (install Debian package xvfb, or set DISPLAY)"; exit 0
fi

# Prints, for every trace of the displayed view, "TRACE <flags> <label>", then
# "SIG <name>" for each displayed signal (full name with bit range, in order),
# then "WINDOW <start> <end> <max>" in the dump's time unit, and quits.
# GTKWave is given it by a name relative to $tmp (the cases run there): its
# Tcl reads a path with a non-ASCII letter in the wrong encoding and cannot
# find the file.
cat >"$tmp/list.tcl" <<'EOF'
set n [gtkwave::getTotalNumTraces]
for {set i 0} {$i < $n} {incr i} {
  puts "TRACE [gtkwave::getTraceFlagsFromIndex $i] [gtkwave::getTraceNameFromIndex $i]"
}
foreach s [gtkwave::getDisplayedSignals] { puts "SIG $s" }
puts "WINDOW [gtkwave::getWindowStartTime] [gtkwave::getWindowEndTime] [gtkwave::getMaxTime]"
gtkwave::/File/Quit
EOF

# expected_traces VIEW: the traces the view names, one a line, as GTKWave
# lists displayed signals (the name after an alias "+{label} ").
expected_traces() {
  sed -n -e '/^\[/d' -e '/^[@*#-]/d' -e '/^$/d' -e 's/^+{[^}]*} *//' -e p "$1"
}

# check_view CASE VIEW VCD: the three checks above.
check_view() {
  local name=$1 view=$2 vcd=$3 out
  out=$(cd "$tmp" && timeout 120 "${xrun[@]}" gtkwave -S list.tcl "$vcd" "$view" 2>&1)
  if echo "$out" | grep -q "Could not initialize GTK"; then
    echo "SKIP ${name}: no X server could be started (GTKWave: Could not initialize GTK)"; return
  fi
  if echo "$out" | grep -q "^xvfb-run: error"; then
    echo "SKIP ${name}: no X server could be started ($(echo "$out" | grep -m1 '^xvfb-run: error'))"; return
  fi
  echo "$out" >"$tmp/$name.gtkwave.out"
  local why
  why=$(python3 - "$tmp/$name.gtkwave.out" <(expected_traces "$view") <<'PY'
import re, sys
lines = open(sys.argv[1]).read().splitlines()
expected = [l for l in open(sys.argv[2]).read().splitlines() if l]
sigs = [l[4:] for l in lines if l.startswith("SIG ")]
missing = [e for e in expected if e not in sigs]
if not expected:
    print("traces: the view names no trace")
elif missing or len(sigs) != len(expected):
    print("traces: %d of %d displayed; missing: %s" % (len(sigs), len(expected), ", ".join(missing[:6])))
else:
    print("traces: ok")
# labels of the displayed signals: traces that are neither comments (0x200)
# nor the extra height of an analog trace (0x20000), in display order
labels = []
for l in lines:
    m = re.match(r"TRACE (\d+) ?(.*)$", l)
    if m and not int(m.group(1)) & 0x20200:
        labels.append(m.group(2))
bad = []
if len(labels) != len(sigs):
    bad.append("%d labels for %d signals" % (len(labels), len(sigs)))
else:
    for s, lab in zip(sigs, labels):
        want = re.sub(r"\[\d+:\d+\]$", "", s).replace(".", " ")
        if lab != want:
            bad.append("%s labelled '%s', expected '%s'" % (s, lab, want))
dup = sorted({x for x in labels if labels.count(x) > 1})
if dup:
    bad.append("labels shared by several traces: " + ", ".join(dup))
print("labels: " + ("; ".join(bad[:4]) if bad else "ok"))
w = [l.split()[1:] for l in lines if l.startswith("WINDOW ")]
if not w:
    print("window: GTKWave reported none (%s)" % " / ".join(lines[-3:]))
else:
    a, b, mx = (int(x) for x in w[0])
    # 50 cycles of the default 500 MHz clock in the VCD's 1 ns unit
    if b - a < 100 or a < 0 or a >= mx:
        print("window: %d..%d ns of a %d ns dump (want >= 100 ns inside it)" % (a, b, mx))
    else:
        print("window: ok")
PY
)
  local part msg
  for part in traces labels window; do
    msg=$(echo "$why" | sed -n "s/^$part: //p")
    if [ "$msg" = ok ]; then pass "${name}_$part"; else fail "${name}_$part" "${msg:-no result}"; fi
  done
}

# make_dump VIEW VCD [EXTRA ARGS...]: runs the view's documented dump command
# writing VCD; returns non-zero (after a FAIL line) when it cannot.
make_dump() {
  local view=$1 vcd=$2; shift 2
  local -a args=()
  mapfile -t args < <(python3 "$root/scripts/gtkw_dump_args.py" "$view" 2>/dev/null)
  if [ ${#args[@]} -eq 0 ]; then
    fail "$(basename "$view" .gtkw)_dump" "no 'build/bin/rtsim ...' dump command in the view's header"; return 1
  fi
  local i
  for i in "${!args[@]}"; do
    [ "${args[$i]}" = waveforms/rtsim.vcd ] && args[i]=$vcd
    # a smaller frame under the sanitizers (the window's cycles are still run)
    [ -n "${RTSIM_TB_SANITIZED:-}" ] && [ "${args[$i]}" = 64x36 ] && args[i]=32x18
  done
  if ! "$bin" "${args[@]}" "$@" --quiet >"$tmp/dump.out" 2>&1 || [ ! -s "$vcd" ]; then
    fail "$(basename "$view" .gtkw)_dump" "rtsim ${args[*]} failed: $(head -3 "$tmp/dump.out" | tr '\n' ' ')"; return 1
  fi
}

nviews=0
for view in "$root"/waveforms/*.gtkw; do
  [ -f "$view" ] || continue
  nviews=$((nviews + 1))
  v=$(basename "$view" .gtkw)
  make_dump "$view" "$tmp/$v.vcd" || continue
  check_view "gtkw_$v" "$view" "$tmp/$v.vcd"
done
check "gtkw_views_found" [ "$nviews" -ge 2 ]

# The overview on the other machine's dump.
ov=$root/waveforms/accel_overview.gtkw
if make_dump "$ov" "$tmp/overview_bvh2.vcd" --machine bvh2; then
  check_view "gtkw_accel_overview_on_bvh2" "$ov" "$tmp/overview_bvh2.vcd"
fi

# Control: the overview without bit ranges (how the views were first written)
# must lose its vectors, and this test must notice.
sed -e 's/\[[0-9]*:[0-9]*\]$//' "$ov" >"$tmp/no_ranges.gtkw"
if [ -s "$tmp/accel_overview.vcd" ]; then
  out=$(cd "$tmp" && timeout 120 "${xrun[@]}" gtkwave -S list.tcl "$tmp/accel_overview.vcd" \
        "$tmp/no_ranges.gtkw" 2>&1)
  if echo "$out" | grep -q -e "Could not initialize GTK" -e "^xvfb-run: error"; then
    echo "SKIP gtkw_control_dropped_vectors: no X server could be started"
  else
    nsig=$(echo "$out" | grep -c '^SIG ')
    nexp=$(expected_traces "$tmp/no_ranges.gtkw" | grep -c .)
    nvec=$(expected_traces "$ov" | grep -c '\]$')
    if [ "$nvec" -gt 0 ] && [ "$nsig" -eq $((nexp - nvec)) ]; then pass gtkw_control_dropped_vectors
    else fail gtkw_control_dropped_vectors "without bit ranges GTKWave showed $nsig of $nexp traces, expected $((nexp - nvec)) (the $nvec vectors dropped)"; fi
  fi
fi
