#!/usr/bin/env bash
# tb_accel_skip_equiv — the simulation speed-ups must not change any result:
# rtsim's whole --json output (every statistic: cycles, per-unit counters, cache
# and DRAM statistics, command counts, energy) with idle skipping (the default:
# units and the LPDDR3 controller sleep and catch up lazily, the DRAM port
# wakes only for completions) equals the exhaustive reference mode (every unit
# stepped every cycle on both clocks, the controller scanning every DRAM cycle),
# for both machines, LPDDR3 and the fixed-latency memory, diffuse rays, the
# default memory side and a stressed one (one-entry DRAM response FIFO, few
# MSHRs and outstanding requests: back-pressure and refused bursts). Except, in
# the stressed runs, the caches' blocked_* counters: they count refused retries
# of an upper level's request, and a unit that sleeps while refused retries less
# often than one stepped every cycle (so on main before the speed-ups too). No
# stored reference: the two modes must agree with each other. Small frames
# (smaller under the sanitizers) keep it to seconds.
set -u
bin=${RTSIM_BIN:?}/rtsim
tmp=${RTSIM_TMP:-/tmp}/tb_accel_skip_equiv
rm -rf "$tmp"; mkdir -p "$tmp"

. "$(dirname "$0")/../cli_lib.sh"

res=32x18
[ -n "${RTSIM_TB_SANITIZED:-}" ] && res=16x9
stress=(--set node_l1.mshrs=2 --set node_l2.mshrs=2 --set prim.mshrs=2 --set fifo.mem_dram_req=2
        --set fifo.mem_dram_resp=1 --set fifo.mem_req=2 --set fifo.mem_resp=2 --set memory.max_outstanding=3)

# run NAME ARGS...: default and --exhaustive JSON must agree key by key (all
# keys, or all but those matching $ignore)
run() {
  local name=$1; shift
  if ! "$bin" "$@" --quiet --json "$tmp/$name.skip.json" >"$tmp/$name.skip.out" 2>&1; then
    fail "$name" "rtsim failed: $(head -3 "$tmp/$name.skip.out" | tr '\n' ' ')"; return
  fi
  if ! "$bin" "$@" --quiet --exhaustive --json "$tmp/$name.exh.json" >"$tmp/$name.exh.out" 2>&1; then
    fail "$name" "rtsim --exhaustive failed: $(head -3 "$tmp/$name.exh.out" | tr '\n' ' ')"; return
  fi
  local why
  if why=$(python3 - "$tmp/$name.skip.json" "$tmp/$name.exh.json" "$ignore" <<'PY'
import json, re, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
skip = re.compile(sys.argv[3]) if sys.argv[3] else None
keys = sorted(set(a) | set(b))
# "run": provenance (command line, host times), not results (docs/results.md)
bad = [k for k in keys if not (skip and skip.search(k)) and k != "run" and a.get(k) != b.get(k)]
if len(keys) < 100 or bad:
    print("%d keys; differ: %s" % (len(keys), ", ".join("%s %s vs %s" % (k, a.get(k), b.get(k)) for k in bad[:3])))
    sys.exit(1)
PY
  ); then
    pass "$name"
  else
    fail "$name" "$why"
  fi
}

for m in bvh2 mbvh4; do
  ignore=''
  run "accel_skip_equiv_${m}_lpddr3_diffuse" interior --res "$res" --machine "$m" --rays diffuse
  run "accel_skip_equiv_${m}_fixed_diffuse" city --res "$res" --machine "$m" --rays diffuse --set memory.model=fixed
  ignore='\.blocked_'
  run "accel_skip_equiv_${m}_lpddr3_diffuse_stressed" hairball --res "$res" --machine "$m" --rays diffuse "${stress[@]}"
done
# the statistics the comparison covers include the DRAM commands (not vacuous)
if grep -q '"dram.cmd_rd": [1-9]' "$tmp/accel_skip_equiv_mbvh4_lpddr3_diffuse.skip.json" 2>/dev/null; then
  pass accel_skip_equiv_covers_dram_commands
else
  fail accel_skip_equiv_covers_dram_commands "no dram.cmd_rd > 0 in the JSON"
fi
