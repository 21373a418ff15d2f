#!/usr/bin/env bash
# tb_accel_reliability — rtsim's model-side reliability (docs/accel.md,
# "Machines that cannot run"), one case per failure example there: valid
# runs are not reported as failures
# (deadlock bound derived from sched.shade_latency, watchdog counting node
# visits and triangle tests, FIFO auto-sizing above the deadlock-free
# minima, the livelock guard), machines that cannot run are refused at
# start-up naming the key and its bound, ranges are reported as the user set
# them and written once, and the run-time estimate and --progress lines.
set -u
bin=${RTSIM_BIN:?}/rtsim
tmp=${RTSIM_TMP:-/tmp}/tb_accel_reliability
rm -rf "$tmp"; mkdir -p "$tmp"

. "$(dirname "$0")/../cli_lib.sh"

# a shading latency of 200,000 cycles (range 0..1,000,000) is no deadlock:
# the detector's window is derived from it (it was a fixed 100,000)
expect rel_shade_latency_200000_runs 0 "rays" -- "$bin" interior --res 8x4 --rays diffuse --set sched.shade_latency=200000
# the top of ist.latency's documented range runs; prim.hit_latency is not
# blamed on ist.latency
expect rel_ist_latency_256_runs 0 "rays" -- "$bin" interior --res 8x4 --set ist.latency=256
expect rel_prim_hit_latency_1000_runs 0 "rays" -- "$bin" interior --res 8x4 --set prim.hit_latency=1000
expect rel_ist_latency_257_named 2 "ist.latency = 257 is out of range (allowed 1..256)" -- "$bin" interior --res 8x4 --set ist.latency=257
# --help-module sched: one watchdog default, the schema's
out=$("$bin" --help-module sched 2>&1)
if [ "$(echo "$out" | grep -c '2000000')" = 1 ] && ! echo "$out" | grep -q 'default 1000000'; then
  pass rel_help_module_one_watchdog_default
else fail rel_help_module_one_watchdog_default "$(echo "$out" | grep -i watchdog | tr '\n' ' ')"; fi

# a leaf of 70,000 overlapping triangles: 2.36 M cycles without a ray
# completing, but triangle tests all along, so no "livelock"
awk 'BEGIN { print "v -1 -1 0"; print "v 1 -1 0"; print "v 0 1 0"; for (i = 0; i < 70000; i++) print "f 1 2 3" }' > "$tmp/leaf.obj"
out=$("$bin" "$tmp/leaf.obj" --res 8x4 2>&1); rc=$?
if [ $rc -eq 0 ] && echo "$out" | grep -q '^rays        32 ' && echo "$out" | grep -q '^cycles      2[0-9]\{6\}$'; then
  pass rel_overlapping_leaf_completes
else fail rel_overlapping_leaf_completes "exit $rc: $(echo "$out" | head -3 | tr '\n' ' ')"; fi

# FIFO auto-sizing from an 8x4 frame never writes a machine below its
# deadlock-free minima, so it runs at 64x36 (it deadlocked with
# fifo.ray_trv_loop <= 4)
"$bin" interior --res 8x4 --quiet --autosize-fifos "$tmp/sized.ini"
loop=$(sed -n 's/^ray_trv_loop *= *//p' "$tmp/sized.ini")
if [ -n "$loop" ] && [ "$loop" -ge 24 ]; then pass rel_autosize_loop_at_minimum
else fail rel_autosize_loop_at_minimum "ray_trv_loop = '$loop' (minimum 24 = trv.slots 32 - 9 stages + 1)"; fi
expect rel_autosized_machine_runs_larger_frame 0 "rays" -- "$bin" interior --res 64x36 --machine "$tmp/sized.ini"

# machines that cannot run are refused at start-up, naming the key and bound
expect rel_node_l1_smaller_than_node 2 "node_l1.size = 64 holds 2 line(s) of node_l1.line = 32 B, but one BVH node of 128 B touches up to 4 lines, which must all be present at once: node_l1.size must be >= 128" -- \
  "$bin" interior --res 8x4 --set node_l1.size=64 --set node_l1.line=32 --set node_l1.ways=2
expect rel_trv_loop_below_minimum 2 "fifo.ray_trv_loop = 4 (--set fifo.ray_trv_loop=4) can deadlock a TRV: with trv.slots = 32 and a 9-stage pipeline it must be >= trv.slots - stages + 1 = 24" -- \
  "$bin" interior --res 8x4 --set fifo.ray_trv_loop=4
expect rel_leaf_return_below_minimum 2 "fifo.ray_leaf + fifo.ray_return = 4 + 4 can deadlock the TRV-IST loop" -- \
  "$bin" interior --res 8x4 --set fifo.ray_leaf=4 --set fifo.ray_return=4
expect rel_ways_power_of_two 2 "node_l1.ways = 3 is not a power of two (allowed 1..64, power of two)" -- \
  "$bin" interior --res 8x4 --set node_l1.ways=3
expect rel_node_over_eight_lines 2 "node_l1.line = 16: one BVH node of 224 B touches up to 14 lines, more than the 8 one access may touch: node_l1.line must be >= 32" -- \
  "$bin" interior --res 8x4 --set machine.branching=7 --set node_l1.line=16 --set node_l2.line=16
expect rel_direct_mapped_multiline 2 "node_l1.ways = 1: one BVH node of 128 B touches up to 2 lines" -- \
  "$bin" interior --res 8x4 --set node_l1.line=64 --set node_l1.ways=1
expect rel_node_l1_too_small_for_slots 2 "the trv.slots = 32 rays of a TRV may each wait for a node" -- \
  "$bin" interior --res 8x4 --set node_l1.size=2K --set node_l1.ways=1

# rays that thrash a node L1 (80 rays, 2 ways, a 261-stage TRV pipeline:
# found by tb_accel_random_configs, seed 7) take turns once the watchdog is
# half-way, and the run completes saying so
out=$("$bin" hairball --rays diffuse --res 3x4 --bounces 2 --seed 398 \
  --set machine.clock_mhz=7.61158 \
  --set machine.branching=2 \
  --set node_l1.size=32768 \
  --set node_l1.line=256 \
  --set node_l1.ways=2 \
  --set node_l1.banks=1 \
  --set node_l1.ports=3 \
  --set node_l1.mshrs=16 \
  --set node_l1.mshr_merge=1 \
  --set node_l1.hit_latency=230 \
  --set node_l2.size=8388608 \
  --set node_l2.line=256 \
  --set node_l2.ways=4 \
  --set node_l2.banks=8 \
  --set node_l2.ports=2 \
  --set node_l2.mshrs=6 \
  --set node_l2.mshr_merge=4 \
  --set node_l2.hit_latency=1 \
  --set prim.size=2097152 \
  --set prim.line=2048 \
  --set prim.ways=32 \
  --set prim.banks=4 \
  --set prim.ports=1 \
  --set prim.mshrs=47 \
  --set prim.mshr_merge=12 \
  --set prim.hit_latency=8 \
  --set memory.model=fixed \
  --set memory.fixed_latency=1 \
  --set memory.fixed_bandwidth_gbs=0 \
  --set memory.max_outstanding=8834 \
  --set fifo.mem_l1_miss=122 \
  --set fifo.mem_l1_fill=259 \
  --set fifo.mem_l2_req=65536 \
  --set fifo.mem_l2_resp=84 \
  --set fifo.mem_l2_miss=26 \
  --set fifo.mem_l2_fill=24937 \
  --set fifo.mem_prim_miss=3 \
  --set fifo.mem_prim_fill=65536 \
  --set fifo.mem_req=1003 \
  --set fifo.mem_resp=176 \
  --set fifo.mem_dram_req=30226 \
  --set fifo.mem_dram_resp=39168 \
  --set fifo.mem_latency=10 \
  --set trv.count=1 \
  --set trv.slots=80 \
  --set trv.stack_depth=103 \
  --set trv.stack_banks=2 \
  --set trv.distance_stack=off \
  --set trv.stages_box=26 \
  --set trv.stages_stack=1 \
  --set trv.stages_next=3 \
  --set trv.box_flops=1 \
  --set ist.latency=4 \
  --set ist.flops_per_test=2 \
  --set sched.admit_per_cycle=2 \
  --set sched.shade_latency=25 \
  --set sched.watchdog_cycles=15470 \
  --set fifo.ray_new=4 \
  --set fifo.ray_leaf=7 \
  --set fifo.ray_return=61711 \
  --set fifo.ray_done=65536 \
  --set fifo.ray_trv_loop=1840 \
  --set fifo.ray_ist_loop=5 \
  --set fifo.ray_latency=1 \
  --set energy.enabled=false 2>&1); rc=$?   # 2-way, 256-byte lines: no SRAM figure
if [ $rc -eq 0 ] && echo "$out" | grep -q '^guard       livelock guard engaged at cycle'; then pass rel_livelock_guard_completes
else fail rel_livelock_guard_completes "exit $rc: $(echo "$out" | head -3 | tr '\n' ' ')"; fi

# the run-time estimate (always with --progress; unasked past
# announce_seconds) and progress lines when stderr is not a terminal
err=$("$bin" interior --res 32x18 --quiet --progress 2>&1 >/dev/null)
if echo "$err" | grep -q '^rtsim: estimate: ~576 rays, ~[0-9.e+]* simulated cycles, ~[0-9]* s of host time (primary)$'; then
  pass rel_estimate_with_progress
else fail rel_estimate_with_progress "$err"; fi
mkdir -p "$tmp/data"; cp -r "$(dirname "$0")/../../model/data/." "$tmp/data/"
sed -i 's/^announce_seconds.*/announce_seconds = 0.000001/; s/^progress_seconds.*/progress_seconds = 0.000001/' "$tmp/data/estimate.ini"
err=$(RTSIM_DATA_DIR="$tmp/data" "$bin" interior --res 32x18 --quiet 2>&1 >/dev/null)
if echo "$err" | grep -q '^rtsim: estimate: .*; --progress prints progress lines$' && ! echo "$err" | grep -q 'progress: cycle'; then
  pass rel_estimate_announced_unasked
else fail rel_estimate_announced_unasked "$err"; fi
err=$(RTSIM_DATA_DIR="$tmp/data" "$bin" interior --res 64x36 --rays diffuse --quiet --progress 2>&1 >/dev/null)
if echo "$err" | grep -q '^rtsim: progress: cycle [0-9]* (~[0-9]*% of the estimate), [0-9]* rays done, [0-9]*/2304 primaries admitted, [0-9]* s$'; then
  pass rel_progress_lines_without_terminal
else fail rel_progress_lines_without_terminal "$err"; fi
# a broken estimate file (read by config/ini_file.h) is a warning naming
# file:line, the key and the allowed values; the run goes on
sed -i 's/^overhead.*/overhead = -1/' "$tmp/data/estimate.ini"
line=$(grep -n '^overhead' "$tmp/data/estimate.ini" | cut -d: -f1)
err=$(RTSIM_DATA_DIR="$tmp/data" "$bin" interior --res 8x4 --quiet 2>&1 >/dev/null); rc=$?
if [ $rc -eq 0 ] && echo "$err" | grep -qF "rtsim: warning: no run-time estimate: $tmp/data/estimate.ini:$line: overhead = '-1' invalid, allowed a number > 0"; then
  pass rel_estimate_bad_file_warns
else fail rel_estimate_bad_file_warns "exit $rc: $err"; fi
rm -rf "$tmp"
