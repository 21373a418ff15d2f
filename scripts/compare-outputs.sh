#!/usr/bin/env bash
# compare-outputs.sh — runs the same set of commands with two builds of the
# tools and reports every output that differs. Used to show that a change
# which must not change results (a refactoring, a speed round, a merge)
# leaves every output byte-identical.
#
#   scripts/compare-outputs.sh BIN_A BIN_B [WORK_DIR]
# Arguments:
#   BIN_A, BIN_B  the two folders of tools to compare
#   WORK_DIR      where the outputs go (default a new temporary folder)
#   -h, --help    this text
#
# BIN_A and BIN_B are folders holding rtsim, rttrace and rtdram (for example
# a build of the old commit in a git worktree and build/bin). The set covers
# every built-in scene, both machines, both ray types, LPDDR3 and fixed
# memory, the fidelity levels and --accuracy, VCD and heatmaps, rttrace JSON
# and logs, rtdram JSON and command traces (about 50 runs at small
# resolutions, a minute or two).
#
# What is compared: summaries on stdout, JSON, VCD, heatmaps, trace logs and
# command traces, byte for byte, except what measures the host rather than
# the model: the summary's "host", "workers" and "time" lines and build times (and the
# run folder in paths); JSON fields of host time and speed
# (names ending in _s, or holding wall, cpu, host or per_s); the JSON's `run`
# provenance object (command line, date, times); the commit in rttrace's
# "tool" field; the VCD's $date block.
# Prints one line per run (same/DIFF) and ends with "N same, N differ";
# exits 1 when anything differs.
set -uo pipefail
case ${1:-} in -h|--help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 0 ;; esac
[ $# -ge 2 ] || { awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 2; }
bin_a=$(cd "$1" && pwd) || exit 2
bin_b=$(cd "$2" && pwd) || exit 2
work=${3:-$(mktemp -d)}
mkdir -p "$work"
for t in rtsim rttrace rtdram; do
  for b in "$bin_a" "$bin_b"; do
    [ -x "$b/$t" ] || { echo "compare-outputs: $b/$t not found" >&2; exit 2; }
  done
done

# JSON without host-dependent fields, keys sorted, one per line.
normalize_json() {
  python3 - "$1" <<'EOF'
import json, re, sys
volatile = re.compile(r'(_s$|wall|cpu|host|per_s|^run$)')
def clean(o):
    if isinstance(o, dict):
        return {k: clean(v) for k, v in o.items() if not volatile.search(k)}
    if isinstance(o, list):
        return [clean(v) for v in o]
    if isinstance(o, str):  # rttrace's "tool" names the commit it was built from
        return re.sub(r"\(git [0-9a-f]+\)", "(git)", o)
    return o
with open(sys.argv[1]) as f:
    try:
        print(json.dumps(clean(json.load(f)), indent=1, sort_keys=True))
    except BrokenPipeError:  # cmp stops reading at the first difference
        pass
EOF
}
normalize() { # file -> normalized text on stdout
  case "$1" in
    *.json) normalize_json "$1" ;;
    *.vcd) sed '/^\$date/,/\$end/d' "$1" ;;
    *.txt) if head -c 1 "$1" | grep -q '{'; then normalize_json "$1"; return; fi   # rtdram --json
           grep -vE '^(host|time|workers) ' "$1" | sed -E -e "s#$work/[ab]/#OUT/#g" \
               -e 's/built in [0-9.]+ s/built in T s/' ;;
    *) cat "$1" ;;
  esac
}

same=0 differ=0
# run NAME TOOL ARGS... ; @OUT@ in ARGS is the run's output folder
run() {
  local name=$1 tool=$2; shift 2
  local side out args a rc_a rc_b
  for side in a b; do
    out="$work/$side/$name"; rm -rf "$out"; mkdir -p "$out"
    args=()
    for a in "$@"; do args+=("${a//@OUT@/$out}"); done
    local bin=$bin_a; [ $side = b ] && bin=$bin_b
    (cd "$out" && "$bin/$tool" "${args[@]}" >stdout.txt 2>stderr.log; echo $? >rc.txt)
  done
  local bad=()
  rc_a=$(cat "$work/a/$name/rc.txt"); rc_b=$(cat "$work/b/$name/rc.txt")
  [ "$rc_a" = "$rc_b" ] || bad+=("exit $rc_a/$rc_b")
  for f in $(cd "$work/a/$name" && ls | grep -v -e '^rc.txt$' -e '^stderr.log$'); do
    if [ ! -e "$work/b/$name/$f" ]; then bad+=("$f missing in B"); continue; fi
    cmp -s <(normalize "$work/a/$name/$f") <(normalize "$work/b/$name/$f") || bad+=("$f")
  done
  for f in $(cd "$work/b/$name" && ls); do
    [ -e "$work/a/$name/$f" ] || bad+=("$f only in B")
  done
  if [ ${#bad[@]} -eq 0 ]; then
    same=$((same + 1)); echo "same    $name"
  else
    differ=$((differ + 1)); echo "DIFF    $name: ${bad[*]}"
  fi
}

for scene in interior hairball city forest; do
  for machine in bvh2 mbvh4; do
    for rays in primary diffuse; do
      res=48x27; [ $rays = diffuse ] && res=24x14
      run "rtsim-$scene-$machine-$rays" rtsim $scene --machine $machine --rays $rays \
          --res $res --json @OUT@/stats.json
    done
  done
  run "rtsim-$scene-fixedmem" rtsim $scene --machine mbvh4 --rays diffuse --res 24x14 \
      --set memory.model=fixed --json @OUT@/stats.json
done
run rtsim-vcd-mbvh4 rtsim interior --machine mbvh4 --res 32x18 --vcd @OUT@/run.vcd --json @OUT@/stats.json
run rtsim-vcd-bvh2 rtsim city --machine bvh2 --res 32x18 --vcd @OUT@/run.vcd --vcd-window 100:3000
run rtsim-heatmap rtsim forest --res 32x18 --heatmap @OUT@/cycles.png --json @OUT@/stats.json
run rtsim-autosize rtsim interior --res 16x9 --autosize-fifos @OUT@/sized.ini
# the fidelity levels (their functional pass, lattice, windows and --accuracy's
# choice) at a size the windowed plan fits
for scene in interior hairball; do
  for machine in bvh2 mbvh4; do
    for level in functional sampled windowed; do
      run "rtsim-$scene-$machine-$level" rtsim $scene --machine $machine --rays diffuse --bounces 2 \
          --res 320x180 --fidelity $level --json @OUT@/stats.json
    done
    run "rtsim-$scene-$machine-accuracy" rtsim $scene --machine $machine --rays diffuse --bounces 2 \
        --res 320x180 --accuracy 5% --json @OUT@/stats.json
  done
done
# --accuracy through windowed's probe, pilot and plan (small caches turn over)
for acc in 5% 10%; do
  run "rtsim-accuracy-$acc" rtsim interior --res 800x450 --rays diffuse --bounces 1 --set node_l2.size=32K \
      --set prim.size=32K --accuracy $acc --json @OUT@/stats.json
done
for scene in interior hairball; do
  for bvh in bvh2 mbvh4; do
    run "rttrace-$scene-$bvh" rttrace $scene --bvh $bvh --rays diffuse --res 32x18 \
        --check-embree --log @OUT@/trace.tlog --json @OUT@/stats.json --image @OUT@/image.png
  done
done
# rtdram: a deterministic mixed trace (strided reads, a few writes)
trace="$work/dram.trace"
awk 'BEGIN { for (i = 0; i < 3000; i++) printf "0x%x %s\n", (i * 4160 + (i % 7) * 64) % 67108864, (i % 5 == 0) ? "W" : "R" }' >"$trace"
run rtdram-json rtdram "$trace" --json --cmd-trace @OUT@/cmds.txt
run rtdram-nCL rtdram "$trace" --json --set timing.nCL=14
echo "$same same, $differ differ"
[ "$differ" -eq 0 ]
