#!/usr/bin/env bash
# tb_accel_cli — rtsim's command line (docs/design.md "Command-line conventions"):
# help/version/--help-module, the summary and JSON (cycles, rays, mrps,
# dram_bytes with units and descriptions), VCD with scopes per unit, a window
# and a filter, the heatmap, FIFO auto-sizing (the written machine loads back
# and runs with the same results), determinism, and bad input: unknown or
# out-of-range --set keys, bad options/values/scenes -> a message naming the
# key or value and the allowed range, exit 2, no output file left behind;
# a machine that could deadlock -> refused at start-up, exit 2; index-addressed
# node caches (same frame as byte addressing at 4-wide, whole 96 B nodes
# moved at 3-wide, a mixed hierarchy refused).
set -u
bin=${RTSIM_BIN:?}/rtsim
tmp=${RTSIM_TMP:-/tmp}/tb_accel_cli
rm -rf "$tmp"; mkdir -p "$tmp"

. "$(dirname "$0")/../cli_lib.sh"

# a small mesh (a bumpy 12x12 grid of quads and a floating box: 300 triangles)
# keeps each run fast, also under the sanitizers; its view is the "auto" one
awk 'BEGIN {
  n = 12
  for (j = 0; j <= n; j++) for (i = 0; i <= n; i++) printf "v %d %g %d\n", i, ((i * 7 + j * 3) % 5) * 0.2, j
  for (j = 0; j < n; j++) for (i = 0; i < n; i++) {
    a = j * (n + 1) + i + 1; b = a + 1; c = a + n + 1; d = c + 1
    printf "f %d %d %d\nf %d %d %d\n", a, b, d, a, d, c
  }
  base = (n + 1) * (n + 1)
  for (k = 0; k < 8; k++) printf "v %g %g %g\n", 4 + 3 * (k % 2), 2 + 2 * (int(k / 2) % 2), 4 + 3 * int(k / 4)
  split("1 2 4 3 5 6 8 7 1 2 6 5 3 4 8 7 1 3 7 5 2 4 8 6", q, " ")
  for (f = 0; f < 6; f++) {
    v1 = base + q[4 * f + 1]; v2 = base + q[4 * f + 2]; v3 = base + q[4 * f + 3]; v4 = base + q[4 * f + 4]
    printf "f %d %d %d %d\n", v1, v2, v3, v4
  }
}' > "$tmp/small.obj"
scene=$tmp/small.obj
small=("$scene" --res 24x16 --quiet)
expect accel_cli_help 0 "usage: rtsim" -- "$bin" --help
expect accel_cli_help_range 0 "(0 < R <= 1; default 1/16 sampled, 1/8 windowed)" -- "$bin" --help
expect accel_cli_version 0 "git" -- "$bin" --version
expect accel_cli_help_module_trv 0 "stack_depth" -- "$bin" --help-module trv
expect accel_cli_help_module_ist 0 "flops_per_test" -- "$bin" --help-module ist
expect accel_cli_help_module_cache_section 0 "mshrs" -- "$bin" --help-module node_l1
expect accel_cli_help_module_memory_unit 0 "mshr" -- "$bin" --help-module cache
expect accel_cli_help_module_unknown 2 "no such module" -- "$bin" --help-module nosuch
expect accel_cli_bad_option 2 "usage" -- "$bin" --bogus
expect accel_cli_bad_rays 2 "--rays sideways: allowed values are primary, diffuse" -- "$bin" --rays sideways
expect accel_cli_bad_res 2 "0x5" -- "$bin" interior --res 0x5
expect accel_cli_bad_bounces 2 "allowed range 0..64" -- "$bin" --bounces 99
expect accel_cli_bad_scene 2 "nosuchscene" -- "$bin" nosuchscene
expect accel_cli_json_folder_missing 2 "folder $tmp/missing does not exist" -- "$bin" interior --res 8x4 --json "$tmp/missing/out.json"
expect accel_cli_vcd_is_folder 2 "is a folder" -- "$bin" interior --res 8x4 --vcd "$tmp"
# a path past PATH_MAX whose cut folder exists ($tmp/./././...) passed the check
long_path="$tmp/$(printf './%.0s' $(seq 2100))out.json"
expect accel_cli_json_path_too_long 2 "path longer than 4039 characters" -- "$bin" interior --res 8x4 --json "$long_path"
expect accel_cli_unknown_key 2 "trv.nosuch" -- "$bin" "${small[@]}" --set trv.nosuch=3
expect accel_cli_key_range 2 "allowed 1..64" -- "$bin" "${small[@]}" --set trv.count=0
expect accel_cli_key_type 2 "trv.slots" -- "$bin" "${small[@]}" --set trv.slots=many
expect accel_cli_bad_machine 2 "nosuchmachine" -- "$bin" "${small[@]}" --machine nosuchmachine
expect accel_cli_bad_window 2 "--vcd-window 9:3" -- "$bin" "${small[@]}" --vcd "$tmp/x.vcd" --vcd-window 9:3
expect accel_cli_bad_heatmap 2 "must end in .png or .exr" -- "$bin" "${small[@]}" --heatmap "$tmp/h.txt"
check accel_cli_no_partial_outputs test ! -e "$tmp/x.vcd" -a ! -e "$tmp/h.txt"

# the default scene is the built-in interior: one run of it
expect accel_cli_default_scene 0 "scene       interior" -- "$bin" --res 8x4

# a run: summary lines and JSON
out=$("$bin" "$scene" --res 24x16 --machine mbvh4 --json "$tmp/a.json" 2>&1); rc=$?
if [ $rc -eq 0 ] && echo "$out" | grep -q '^MRPS' && echo "$out" | grep -q '^caches' && echo "$out" | grep -q '^DRAM' \
   && echo "$out" | grep -q '^utilization' && echo "$out" | grep -q '^in flight'; then pass accel_cli_summary
else fail accel_cli_summary "rc $rc: $(echo "$out" | head -3 | tr '\n' ' ')"; fi
if python3 - "$tmp/a.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
for k in ("cycles", "rays", "mrps", "dram_bytes"):
    assert k in d, k
    assert k in d["_units"] and k in d["_descriptions"], k
assert d["rays"] == 24 * 16, d["rays"]
assert d["cycles"] > 0 and d["mrps"] > 0
assert any(k.startswith("trv0.") for k in d), "per-unit stats"
assert all(k in d["_units"] for k in d if not k.startswith("_") and k != "run" and isinstance(d[k], (int, float))), "every stat has a unit"
PY
then pass accel_cli_json; else fail accel_cli_json "missing fields or units"; fi

# determinism: the same run twice gives the same JSON
"$bin" "$scene" --res 24x16 --machine mbvh4 --rays diffuse --json "$tmp/d1.json" --quiet
"$bin" "$scene" --res 24x16 --machine mbvh4 --rays diffuse --json "$tmp/d2.json" --quiet
check accel_cli_deterministic same_results "$tmp/d1.json" "$tmp/d2.json"

# --exhaustive (no idle skipping) gives the same frame cycles
c_skip=$("$bin" "$scene" --res 24x16 --machine bvh2 --rays diffuse --set memory.model=fixed | awk '/^cycles/ { print $2 }')
c_exh=$("$bin" "$scene" --res 24x16 --machine bvh2 --rays diffuse --set memory.model=fixed --exhaustive | awk '/^cycles/ { print $2 }')
check accel_cli_exhaustive_same_cycles test -n "$c_skip" -a "$c_skip" = "$c_exh"

# VCD: scopes per unit, window and filter
"$bin" "$scene" --res 16x8 --quiet --vcd "$tmp/w.vcd" --vcd-window 100:400
if grep -q '^\$scope module trv0 \$end' "$tmp/w.vcd" && grep -q 'state' "$tmp/w.vcd" && grep -q 'issue_ray' "$tmp/w.vcd" \
   && grep -q 'occupancy' "$tmp/w.vcd" && grep -q '^#' "$tmp/w.vcd" \
   && [ -z "$(awk '/^#/ { t = substr($1, 2) + 0; if (t < 200 || t > 800) print t }' "$tmp/w.vcd")" ]; then
  pass accel_cli_vcd_scopes_window
else fail accel_cli_vcd_scopes_window "scopes or window wrong"; fi
# the ray in each pipeline stage: a ray issued at cycle c is in stage k at
# cycle c + k (TRV 0: box1..next1 after fetch1 = issue; IST: test2..); and
# tracing changes no result
"$bin" "$scene" --res 16x8 --machine mbvh4 --quiet --vcd "$tmp/s.vcd" --json "$tmp/s_vcd.json"
"$bin" "$scene" --res 16x8 --machine mbvh4 --quiet --json "$tmp/s_novcd.json"
if python3 - "$tmp/s.vcd" "$tmp/s_vcd.json" "$tmp/s_novcd.json" <<'PY'
import json, re, sys
vcd, with_vcd, without = sys.argv[1:4]
ids, scope, names = {}, [], {}
changes = {}  # id -> [(time, value)]
t = 0
for line in open(vcd):
    w = line.split()
    if not w:
        continue
    if w[0] == '$scope':
        scope.append(w[2])
    elif w[0] == '$upscope':
        scope.pop()
    elif w[0] == '$var':
        names['.'.join(scope + [w[4]])] = w[3]
    elif w[0].startswith('#'):
        t = int(w[0][1:])
    elif w[0].startswith('b'):
        changes.setdefault(w[1], []).append((t, int(w[0][1:], 2) if 'x' not in w[0] else None))
def at(name, time):
    v = None
    for (tt, vv) in changes.get(names[name], []):
        if tt > time:
            break
        v = vv
    return v
period = 2  # ns per 500 MHz cycle ($timescale 1ns)
none = 0xFFFFFFFF
checked = 0
for unit in ('trv0', 'ist'):
    stages = sorted(n for n in names if n.startswith(unit + '.stage.'))
    if not stages:
        sys.exit('no stage variables for ' + unit)
    for (tt, ray) in changes.get(names[unit + '.issue_ray'], []):
        if ray is None or ray == none:
            continue
        for k, st in enumerate(stages, 1):
            got = at(st, tt + k * period)
            if got != ray:
                sys.exit('%s: ray %d issued at %d ns, %s holds %s at %d ns' % (unit, ray, tt, st, got, tt + k * period))
            checked += 1
if checked < 100:
    sys.exit('only %d stage checks' % checked)
a, b = json.load(open(with_vcd)), json.load(open(without))
strip = lambda d: {k: v for k, v in d.items() if not k.startswith('host') and k != 'run'}
if strip(a) != strip(b):
    sys.exit('statistics differ with the VCD on')
PY
then pass accel_cli_vcd_ray_in_each_stage
else fail accel_cli_vcd_ray_in_each_stage "stage variables wrong (see above)"; fi
"$bin" "$scene" --res 16x8 --quiet --vcd "$tmp/f.vcd" --vcd-filter 'trv0.*'
if grep -q 'module trv0' "$tmp/f.vcd" && ! grep -q 'module trv1' "$tmp/f.vcd" && ! grep -q 'module ist' "$tmp/f.vcd"; then
  pass accel_cli_vcd_filter
else fail accel_cli_vcd_filter "filter not applied"; fi

# heatmap
"$bin" "$scene" --res 32x18 --quiet --heatmap "$tmp/h.png"
check accel_cli_heatmap test -s "$tmp/h.png"

# FIFO auto-sizing: the written machine loads back and gives the same frame
"$bin" "$scene" --res 24x16 --quiet --machine mbvh4 --autosize-fifos "$tmp/sized.ini" --json "$tmp/s1.json"
if [ -s "$tmp/sized.ini" ] && grep -q '^ray_new *= *[0-9]' "$tmp/sized.ini" && grep -q '^mem_req *= *[0-9]' "$tmp/sized.ini" \
   && ! grep -q '^ray_trv_loop *= *32$' "$tmp/sized.ini"; then pass accel_cli_autosize_written
else fail accel_cli_autosize_written "sized.ini missing keys or unchanged"; fi
out=$("$bin" "$scene" --res 24x16 --quiet --machine "$tmp/sized.ini" --json "$tmp/s2.json" 2>&1); rc=$?
if [ $rc -eq 0 ] && python3 -c "import json,sys; a=json.load(open(sys.argv[1] + '/s1.json')); b=json.load(open(sys.argv[1] + '/s2.json')); sys.exit(0 if a['rays']==b['rays'] else 1)" "$tmp"; then
  pass accel_cli_autosize_reload
else fail accel_cli_autosize_reload "rc $rc: $out"; fi

# a FIFO below its deadlock-free minimum is refused at start-up (exit 2,
# naming the key and the minimum) instead of deadlocking at run time
expect accel_cli_deadlock_fifo_refused 2 "fifo.ray_trv_loop = 1 (--set fifo.ray_trv_loop=1) can deadlock a TRV" -- \
  "$bin" "$scene" --res 32x32 --quiet --set fifo.ray_trv_loop=1
# a failed run says so in the summary and the JSON (a completed run says
# run_failed 0): here rays overflow a one-entry stack
out=$("$bin" "$scene" --res 16x16 --set trv.stack_depth=1 --json "$tmp/dl.json" 2>/dev/null)
if echo "$out" | grep -q "^status      FAILED: [0-9]* rays overflowed their stack" &&
   python3 -c "import json,sys; d=json.load(open(sys.argv[1] + '/dl.json')); a=json.load(open(sys.argv[1] + '/s1.json')); sys.exit(0 if d['run_failed']==1 and a['run_failed']==0 else 1)" "$tmp"; then
  pass accel_cli_failed_run_marked
else fail accel_cli_failed_run_marked "summary/JSON do not mark the failed run: $(echo "$out" | head -5 | tr '\n' ' ')"; fi
# a stack too small for the scene: exit 1 naming the key
expect accel_cli_stack_too_small 1 "trv.stack_depth" -- "$bin" "$scene" --res 16x16 --quiet --set trv.stack_depth=1

# index-addressed node caches (docs/energy.md "Branching factors 2..8"):
# both node caches or neither; a bad value names the allowed ones
expect accel_cli_index_mixed_refused 2 "node_l1.addressing = index (--set node_l1.addressing=index) but node_l2.addressing = byte" -- \
  "$bin" "${small[@]}" --set node_l1.addressing=index
expect accel_cli_index_bad_value 2 "node_l2.addressing = 'word' is not one of byte|index" -- \
  "$bin" "${small[@]}" --set node_l2.addressing=word
index=(--set node_l1.addressing=index --set node_l2.addressing=index)
# a 4-wide node is a 128 B power of two: index addressing is byte addressing
# with 128 B lines, the same frame to the last statistic and joule
"$bin" "${small[@]}" --rays diffuse --json "$tmp/ix4b.json"
"$bin" "${small[@]}" --rays diffuse "${index[@]}" --json "$tmp/ix4i.json"
if python3 - "$tmp/ix4b.json" "$tmp/ix4i.json" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
a.pop("run"), b.pop("run")
sys.exit(0 if a == b and a["node_l2.fills"] > 0 else 1)
PY
then pass accel_cli_index_width4_same_as_byte
else fail accel_cli_index_width4_same_as_byte "results differ"; fi
# 3-wide: every miss moves one 96 B node, L1 -> L2 -> DRAM, and the DRAM's
# bytes are the node L2's and the primitive cache's fills, in 32 B bursts
"$bin" "${small[@]}" --rays diffuse --set machine.branching=3 "${index[@]}" --json "$tmp/ix3.json" 2>"$tmp/ix3.err"
if python3 - "$tmp/ix3.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
l1 = [k[:-len(".fills")] for k in d if k.startswith("node_l1_") and k.endswith(".fills")]
ok = d["run_failed"] == 0 and d["node_l2.fills"] > 0 and len(l1) == 4
ok = ok and all(d[u + ".bytes_filled"] == 96 * d[u + ".fills"] and d[u + ".bank_conflicts"] == 0 for u in l1)
ok = ok and d["node_l2.bytes_filled"] == 96 * d["node_l2.miss_lines"] == 96 * d["node_l2.fills"]
ok = ok and d["dram_bytes"] == d["node_l2.bytes_filled"] + d["prim.bytes_filled"] == 32 * d["dram.bursts"]
sys.exit(0 if ok else 1)
PY
then pass accel_cli_index_width3_node_traffic
else fail accel_cli_index_width3_node_traffic "traffic is not whole 96 B nodes: $(head -3 "$tmp/ix3.err")"; fi
