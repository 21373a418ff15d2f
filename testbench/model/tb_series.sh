#!/usr/bin/env bash
# tb_series — rtsim --series (docs/results.md "Interval statistics"): the
# rows of a run add up to its totals (rays, busy cycles, cache hits, DRAM
# bytes, dynamic energy per unit, mean rays in flight); the results are the
# same with and without a series (full and every cheaper level that
# simulates cycles); windowed marks its warm-ups and windows; the interval
# sets the rows; bad options exit 2 naming the option; an interrupted run
# leaves no series behind.
set -u
bin=${RTSIM_BIN:?}/rtsim
tmp=${RTSIM_TMP:-/tmp}/tb_series
rm -rf "$tmp"; mkdir -p "$tmp"
. "$(dirname "$0")/../cli_lib.sh"

# sums CSV JSON: the rows add up to the run's totals
sums() {
  python3 - "$1" "$2" <<'PY'
import csv, json, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
d = json.load(open(sys.argv[2]))
assert rows, "no rows"
close = lambda a, b: math.isclose(a, b, rel_tol=1e-7, abs_tol=1e-9)
S = lambda k: sum(float(r[k]) for r in rows)
W = lambda k, w: sum(float(r[k] or 0) * float(r[w]) for r in rows)
# rows tile [0, cycles) without gaps
end = 0
for r in rows:
    assert int(r["cycle_begin"]) == end, "gap at %s" % r["cycle_begin"]
    assert int(r["cycles"]) == int(r["cycle_end"]) - int(r["cycle_begin"]) > 0
    end = int(r["cycle_end"])
assert end == d["cycles"], "last row ends at %d, frame at %d" % (end, d["cycles"])
assert S("rays_completed") == d["rays"], "rays"
assert S("rays_admitted") == d["sched.admitted"], "admitted"
assert close(W("rays_in_flight_mean", "cycles") / d["cycles"], d["rays_in_flight_mean"]), "in flight"
ntrv = sum(1 for k in rows[0] if k.startswith("trv") and k[3:4].isdigit())
for i in range(ntrv):
    assert close(W("trv%d_utilization" % i, "cycles"), d["trv%d.busy_cycles" % i]), "trv%d busy" % i
assert close(W("ist_utilization", "cycles"), d["ist.busy_cycles"]), "ist busy"
l1 = sum(d["node_l1_%d.accesses" % i] for i in range(ntrv))
l1h = sum(d["node_l1_%d.hits" % i] for i in range(ntrv))
assert S("node_l1_accesses") == l1 and close(W("node_l1_hit_rate", "node_l1_accesses"), l1h), "node L1"
for c in ("node_l2", "prim"):
    assert S(c + "_accesses") == d[c + ".accesses"], c
    assert close(W(c + "_hit_rate", c + "_accesses"), d[c + ".hits"]), c + " hits"
assert S("dram_bytes") == d["dram_bytes"], "DRAM bytes"
assert close(W("dram_bandwidth_gbs", "cycles") / d["cycles"], d["dram_bandwidth_gbs"]), "DRAM bandwidth"
clock_hz = d["cycles"] / (d["rays"] / (d["mrps"] * 1e6))
for u in ("trv", "ist", "stack", "cache", "fifo", "dram"):
    mj = W("power_%s_mw" % u, "cycles") / clock_hz
    assert close(mj, d["energy.%s_dynamic_mj" % u]), "%s: %g mJ from the rows, %g in the JSON" % (u, mj, d["energy.%s_dynamic_mj" % u])
PY
}

run=(interior --res 48x27 --rays diffuse --bounces 2 --quiet)
"$bin" "${run[@]}" --json "$tmp/plain.json" >/dev/null 2>&1
"$bin" "${run[@]}" --json "$tmp/s.json" --series "$tmp/s.csv" --series-interval 700 >/dev/null 2>&1
check series_rows_sum_to_totals sums "$tmp/s.csv" "$tmp/s.json"
check series_results_unchanged same_results "$tmp/plain.json" "$tmp/s.json"
rows=$(($(wc -l <"$tmp/s.csv") - 1)); cyc=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1] + '/s.json'))['cycles'])" "$tmp")
check series_interval_sets_rows test "$rows" -eq $(((cyc + 699) / 700))
check series_header_units_documented python3 - "$tmp/s.csv" "$(dirname "$0")/../../docs/results.md" <<'PY'
import re, sys
head = open(sys.argv[1]).readline().strip().split(",")
doc = open(sys.argv[2]).read()
missing = [c for c in head if not re.search(r"`%s`" % re.sub(r"\d+", "<i>", c) if re.match(r"trv\d+_", c) else r"`%s`" % c, doc)]
sys.exit(1 if missing else 0)
PY

# the same on BVH2 with the fixed-latency memory: no DRAM model, empty DRAM columns
"$bin" interior --res 32x18 --machine bvh2 --set memory.model=fixed --quiet --json "$tmp/f.json" \
  --series "$tmp/f.csv" --series-interval 500 >/dev/null 2>&1
check series_fixed_memory_sums sums "$tmp/f.csv" "$tmp/f.json"
check series_fixed_memory_no_row_hits python3 -c "
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1] + '/f.csv')))
sys.exit(0 if rows and all(r['dram_row_hit_rate'] == '' and r['dram_queue_mean'] == '' for r in rows) else 1)" "$tmp"

# cheaper levels: same figures with and without, rows labelled; the
# pieces' scratch folder (in TMPDIR) is removed
mkdir -p "$tmp/scratch"
for lvl in fixed-mem sampled windowed; do
  "$bin" interior --res 96x54 --rays diffuse --fidelity "$lvl" --jobs 2 --quiet --json "$tmp/$lvl-a.json" >/dev/null 2>&1
  TMPDIR="$tmp/scratch" "$bin" interior --res 96x54 --rays diffuse --fidelity "$lvl" --jobs 2 --quiet \
    --json "$tmp/$lvl-b.json" --series "$tmp/$lvl.csv" --series-interval 2000 >/dev/null 2>&1
  check "series_${lvl}_results_unchanged" same_results "$tmp/$lvl-a.json" "$tmp/$lvl-b.json"
done
# the same rows whatever the number of worker processes (pieces joined in piece order)
for lvl in sampled windowed; do
  TMPDIR="$tmp/scratch" "$bin" interior --res 96x54 --rays diffuse --fidelity "$lvl" --jobs 1 --quiet \
    --series "$tmp/$lvl-j1.csv" --series-interval 2000 >/dev/null 2>&1
  check "series_${lvl}_same_rows_any_jobs" cmp -s "$tmp/$lvl.csv" "$tmp/$lvl-j1.csv"
done
check series_fixed_mem_one_frame python3 -c "
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1] + '/fixed-mem.csv')))
sys.exit(0 if rows and {r['phase'] for r in rows} == {'frame'} and {r['piece'] for r in rows} == {'0'} else 1)" "$tmp"
check series_sampled_groups python3 -c "
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1] + '/sampled.csv')))
d = json.load(open(sys.argv[1] + '/sampled-b.json'))
groups = {r['piece'] for r in rows}
ok = rows and {r['phase'] for r in rows} == {'group'} and len(groups) > 1
ok = ok and sum(int(r['rays_completed']) for r in rows) == d['sample.rays']
sys.exit(0 if ok else 1)" "$tmp"
check series_windowed_windows_marked python3 -c "
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1] + '/windowed.csv')))
d = json.load(open(sys.argv[1] + '/windowed-b.json'))
wins = {int(r['piece']) for r in rows if r['phase'] == 'window'}
ok = rows and {r['phase'] for r in rows} <= {'warm-up', 'window'} and wins == set(range(int(d['window.count'])))
# each window's rows follow its warm-up's without a gap
for w in wins:
    rs = [r for r in rows if int(r['piece']) == w]
    ok = ok and all(int(a['cycle_end']) == int(b['cycle_begin']) for a, b in zip(rs, rs[1:]))
    ok = ok and rs[-1]['phase'] == 'window'
sys.exit(0 if ok else 1)" "$tmp"
check series_no_scratch_left test -z "$(ls -A "$tmp/scratch")"

# bad input: exit 2 naming the option and the range or the reason
expect series_interval_zero 2 "--series-interval 0: allowed range 1.." -- "$bin" interior --series "$tmp/x.csv" --series-interval 0
expect series_interval_alone 2 "--series-interval: only with --series" -- "$bin" interior --series-interval 10
expect series_functional_refused 2 "--series needs a level that simulates cycles" -- \
  "$bin" interior --fidelity functional --series "$tmp/x.csv"
expect series_accuracy_refused 2 "--series needs a level that simulates cycles" -- \
  "$bin" interior --accuracy 5% --series "$tmp/x.csv"
expect series_bad_path 2 "--series $tmp/no/such/dir/x.csv" -- "$bin" interior --res 8x8 --series "$tmp/no/such/dir/x.csv"
expect series_same_file_as_json 2 "--series" -- "$bin" interior --res 8x8 --json "$tmp/same" --series "$tmp/same"
check series_bad_input_leaves_nothing test ! -e "$tmp/x.csv"

# interrupted: the JSON says partial, no series file is left (not even a temporary)
"$bin" interior --res 320x180 --rays diffuse --quiet --json "$tmp/int.json" --series "$tmp/int.csv" \
  --series-interval 1000 >/dev/null 2>&1 &
pid=$!
sleep 1
kill -INT "$pid" 2>/dev/null
wait "$pid"
rc=$?
if [ "$rc" -eq 0 ]; then
  echo "SKIP series_interrupted_leaves_none: the run ended before the signal"
else
  check series_interrupted_leaves_none sh -c '[ "$1" -eq 130 ] && [ ! -e "$2/int.csv" ] && ! ls "$2" | grep -q "int.csv." && grep -q "\"partial\": true" "$2/int.json"' _ "$rc" "$tmp"
fi
