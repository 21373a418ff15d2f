#!/usr/bin/env bash
# tb_sweep — scripts/sweep (docs/sweep.md) with the real rtsim and GNU parallel:
# the grid becomes one job per point with a stable name, the merged CSV holds
# exactly rtsim's figures, charts are drawn for the figures the JSON has and
# the missing ones are named; a sweep killed (SIGKILL to its whole process
# group, in the middle of a point) resumes without redoing finished points and
# its merged CSV equals that of an uninterrupted run; bad input stops the
# sweep with exit 2; the Slurm array script covers every pending point once.
# The run on a real Slurm cluster is tb_sweep_slurm.sh.
set -u
bin=${RTSIM_BIN:?}/rtsim
tmp=${RTSIM_TMP:-/tmp}/tb_sweep
rm -rf "$tmp"; mkdir -p "$tmp"
cd "$(dirname "$0")/../.."
sweep=$PWD/scripts/sweep

. testbench/cli_lib.sh

# Six points, small enough for the sanitizer build: 2 machines x 3 node L1 sizes.
grid=(--set-grid node_l1.size=4096,8192,16384 --machines bvh2,mbvh4 --res 32x18 --rtsim "$bin")

# --- bad usage: exit 2 with a message naming the option, nothing planned
expect sweep_usage_no_equals 2 "expected KEY=V1,V2" -- "$sweep" --set-grid trv.count --out "$tmp/u"
expect sweep_usage_empty_item 2 "empty item" -- "$sweep" --set-grid trv.count=1,,2 --out "$tmp/u"
expect sweep_usage_unknown_option 2 "unknown option '--bogus'" -- "$sweep" --bogus
expect sweep_usage_bad_jobs 2 "--jobs 0" -- "$sweep" --jobs 0 --out "$tmp/u"
expect sweep_usage_key_twice 2 "trv.count is both --set and --set-grid" -- \
  "$sweep" --set trv.count=2 --set-grid trv.count=1,2 --out "$tmp/u"
expect sweep_usage_no_rtsim 2 "not found or not executable" -- "$sweep" --rtsim "$tmp/nosuch" --out "$tmp/u"
check sweep_usage_nothing_written test ! -e "$tmp/u/jobs.tsv"

# --- planning: the grid's cross product, names independent of option order
"$sweep" "${grid[@]}" --set-grid trv.count=2,4 --out "$tmp/plan1" --plan > /dev/null
"$sweep" --set-grid trv.count=2,4 --machines bvh2,mbvh4 --res 32x18 --rtsim "$bin" \
  --set-grid node_l1.size=4096,8192,16384 --out "$tmp/plan2" --plan > /dev/null
n1=$(tail -n +2 "$tmp/plan1/jobs.tsv" | wc -l)
check sweep_plan_cross_product test "$n1" -eq 12
check sweep_plan_stable_names cmp -s <(tail -n +2 "$tmp/plan1/jobs.tsv" | cut -f1 | sort) \
                                     <(tail -n +2 "$tmp/plan2/jobs.tsv" | cut -f1 | sort)

# --- an uninterrupted run on all cores
out=$("$sweep" "${grid[@]}" --out "$tmp/full" 2>&1); rc=$?
check sweep_full_exit_0 test $rc -eq 0
check sweep_full_six_results test "$(ls "$tmp/full/results" | grep -c '\.json$')" -eq 6
header="point,scene,rays,machine,res,node_l1.size,set,args,rays_traced,cycles,run_failed,mrps,energy_mj,mrps_per_mm2,dram_mb,area_mm2,power_mw"
check sweep_csv_header test "$(head -n 1 "$tmp/full/results.csv")" = "$header"
check sweep_csv_six_rows test "$(tail -n +2 "$tmp/full/results.csv" | wc -l)" -eq 6
# every row carries exactly its point's JSON figures (MRPS as is, DRAM bytes / 1e6)
if python3 - "$tmp/full" <<'PY'
import csv, json, sys
d = sys.argv[1]
for row in csv.DictReader(open(d + "/results.csv")):
    j = json.load(open(f"{d}/results/{row['point']}.json"))
    assert float(row["mrps"]) == j["mrps"], row
    assert float(row["dram_mb"]) == j["dram_bytes"] / 1e6, row
    for k in ("energy_mj", "mrps_per_mm2", "area_mm2", "power_mw"):
        assert float(row[k]) == j[k], (k, row)
    assert int(row["cycles"]) == j["cycles"] and int(row["rays_traced"]) == j["rays"], row
    assert row["res"] == "32x18" and row["machine"] in ("bvh2", "mbvh4"), row
PY
then pass sweep_csv_equals_json; else fail sweep_csv_equals_json "a CSV row differs from its JSON"; fi
check sweep_figures_named grep -q "figures of merit: mrps, energy_mj, mrps_per_mm2, dram_mb, area_mm2, power_mw" <<< "$out"
check sweep_chart_png test "$(head -c 4 "$tmp/full/charts/mrps-vs-node_l1.size.png" | tail -c 3)" = PNG
check sweep_chart_svg grep -q '<svg' "$tmp/full/charts/dram_mb-vs-node_l1.size.svg"
check sweep_chart_energy test -s "$tmp/full/charts/energy_mj-vs-node_l1.size.png"
# the report page: a chart per figure and swept key, the Pareto front of
# MRPS/mm2 (higher) against mJ/frame (lower) marked exactly on the points no
# other point beats (tb_report renders the page in Chromium)
if python3 - "$tmp/full" <<'PY'
import csv, re, sys
d = sys.argv[1]
page = open(d + "/report.html").read()
for f in ("mrps", "energy_mj", "mrps_per_mm2", "dram_mb", "area_mm2", "power_mw"):
    assert 'id="chart-%s-vs-node_l1.size"' % f in page, f
assert 'id="chart-pareto"' in page
rows = list(csv.DictReader(open(d + "/results.csv")))
pts = [(float(r["mrps_per_mm2"]), float(r["energy_mj"]), r["point"]) for r in rows]
front = {n for x, y, n in pts if not any(x2 >= x and y2 <= y and (x2 > x or y2 < y) for x2, y2, _ in pts)}
marked = set(re.findall(r"<td>([^<]*) <b class=\"flag\">front</b>", page))
assert front and marked == front, (front, marked)
assert page.count('class="pf"') == len(front)
PY
then pass sweep_report_page_pareto; else fail sweep_report_page_pareto "report.html lacks a chart or marks the wrong front"; fi

# --- a complete sweep run again does nothing and changes nothing
stamp() { stat -c '%n %i %y' "$1"/results/*.json; }
before=$(stamp "$tmp/full")
out=$("$sweep" "${grid[@]}" --out "$tmp/full" 2>&1)
check sweep_rerun_nothing_to_run grep -q "6 points in .*, 0 to run" <<< "$out"
check sweep_rerun_results_untouched test "$before" = "$(stamp "$tmp/full")"

# --- killed in the middle of its third point, then resumed
# The wrapper runs the real rtsim; on its third call it then blocks before
# returning, so the kill lands while that point's complete JSON still has its
# temporary name: that point must not count as done.
cat > "$tmp/rtsim-blocks-third" <<EOF
#!/usr/bin/env bash
n=\$(( \$(cat "$tmp/calls" 2>/dev/null || echo 0) + 1 )); echo \$n > "$tmp/calls"
"$bin" "\$@"; rc=\$?
if [ \$n -eq 3 ]; then touch "$tmp/third-reached"; sleep 300; fi
exit \$rc
EOF
chmod +x "$tmp/rtsim-blocks-third"
setsid bash -c 'echo $$ > "$0"; exec "$@"' "$tmp/pgid" \
  "$sweep" "${grid[@]}" --rtsim "$tmp/rtsim-blocks-third" --jobs 1 --out "$tmp/killed" > "$tmp/killed.out" 2>&1 &
launcher=$!
for _ in $(seq 1 1200); do [ -e "$tmp/third-reached" ] && break; sleep 0.1; done
if [ -e "$tmp/third-reached" ]; then
  kill -KILL -- "-$(cat "$tmp/pgid")"
  wait $launcher 2>/dev/null
  pass sweep_kill_reached_third_point
else
  kill -KILL -- "-$(cat "$tmp/pgid")" 2>/dev/null; wait $launcher 2>/dev/null
  fail sweep_kill_reached_third_point "the third point never started: $(tail -n 3 "$tmp/killed.out" | tr '\n' ' ')"
fi
done_after_kill=$(ls "$tmp/killed/results" | grep -c '\.json$')
check sweep_kill_two_results_only test "$done_after_kill" -eq 2
check sweep_kill_left_a_temporary test "$(ls -A "$tmp/killed/results" | grep -c '\.tmp\.')" -ge 1
check sweep_kill_no_csv_yet test ! -e "$tmp/killed/results.csv"
before=$(stamp "$tmp/killed")
out=$("$sweep" "${grid[@]}" --out "$tmp/killed" 2>&1); rc=$?
check sweep_resume_exit_0 test $rc -eq 0
check sweep_resume_runs_the_rest grep -q "6 points in .*, 4 to run" <<< "$out"
check sweep_resume_kept_finished test "$(comm -23 <(echo "$before") <(stamp "$tmp/killed") | wc -l)" -eq 0
check sweep_resume_no_temporary test "$(ls -A "$tmp/killed/results" | grep -c '\.tmp\.')" -eq 0
check sweep_resume_csv_equals_uninterrupted cmp "$tmp/killed/results.csv" "$tmp/full/results.csv"

# --- bad input: rtsim refuses the key; the sweep stops with exit 2, no results
out=$("$sweep" --set-grid nosuch.key=1,2,3 --res 8x4 --rtsim "$bin" --jobs 1 --out "$tmp/bad" 2>&1); rc=$?
check sweep_bad_key_exit_2 test $rc -eq 2
check sweep_bad_key_message grep -q "bad input: rtsim: --set nosuch.key=1: unknown key nosuch.key" <<< "$out"
check sweep_bad_key_stops_the_rest test "$(grep -c "not run, an earlier point had bad input" <<< "$out")" -eq 2
check sweep_bad_key_no_results test "$(ls -A "$tmp/bad/results" | wc -l)" -eq 0

# --- rtsim fails on every point (here a stand-in that cannot run, exit 3):
# the sweep says so with the first point's error and exits non-zero, instead
# of reporting figures of merit "missing from rtsim's JSON"
printf '#!/bin/sh\necho "rtsim-standin: cannot start: no such device" >&2\nexit 3\n' > "$tmp/broken rtsim"
chmod +x "$tmp/broken rtsim"
out=$("$sweep" --set-grid trv.count=2,4 --res 8x4 --rtsim "$tmp/broken rtsim" --jobs 1 --out "$tmp/allfail" 2>&1); rc=$?
check sweep_all_failed_exit_1 test $rc -eq 1
check sweep_all_failed_says_rtsim_failed grep -q "rtsim failed on all 2 points" <<< "$out"
check sweep_all_failed_first_error grep -q "rtsim-standin: cannot start: no such device" <<< "$out"
check sweep_all_failed_no_figures_line test "$(grep -c "figures of merit" <<< "$out")" -eq 0

# --- the aggregator takes whatever figures the JSON has: results that also
# carry energy_mj and mrps_per_mm2 (as rtsim will) get those columns and charts
mkdir -p "$tmp/energy/results"
"$sweep" --set-grid trv.count=2,4 --rtsim "$bin" --out "$tmp/energy" --plan > /dev/null
i=0
for name in $(tail -n +2 "$tmp/energy/jobs.tsv" | cut -f1); do
  i=$((i + 1))
  printf '{"rays": 100, "cycles": %d, "run_failed": 0, "mrps": %d.5, "dram_bytes": 2000000, "energy_mj": %d.25, "mrps_per_mm2": 7.5}\n' \
    $((1000 * i)) $((10 * i)) "$i" > "$tmp/energy/results/$name.json"
done
out=$("$sweep" merge "$tmp/energy" 2>&1); rc=$?
check sweep_energy_merge_exit_0 test $rc -eq 0
check sweep_energy_columns test "$(head -n 1 "$tmp/energy/results.csv")" = \
  "point,scene,rays,machine,res,trv.count,set,args,rays_traced,cycles,run_failed,mrps,energy_mj,mrps_per_mm2,dram_mb"
check sweep_energy_values grep -q ',4,,,100,2000,0,20.5,2.25,7.5,2.0$' "$tmp/energy/results.csv"
check sweep_energy_chart test -s "$tmp/energy/charts/energy_mj-vs-trv.count.png" -a -s "$tmp/energy/charts/mrps_per_mm2-vs-trv.count.svg"
check sweep_energy_names_the_rest grep -q "no column, no chart): area_mm2, power_mw" <<< "$out"
# a missing point: the CSV holds the others, exit 1, the point is named
rm -f "$tmp/energy/results/$name.json"
expect sweep_merge_incomplete_exit_1 1 "1 of 2 points have no result yet: $name" -- "$sweep" merge "$tmp/energy"
check sweep_merge_incomplete_rows test "$(tail -n +2 "$tmp/energy/results.csv" | wc -l)" -eq 1

# --- the Slurm array script (run here task by task, as Slurm would): with
# fewer tasks than points, every pending point still runs exactly once
out=$(SWEEP_SLURM_TASKS=4 "$sweep" "${grid[@]}" --out "$tmp/array" --slurm-script 2>&1)
script=$tmp/array/sweep.sbatch
check sweep_sbatch_written grep -q "wrote $script" <<< "$out"
check sweep_sbatch_syntax bash -n "$script"
check sweep_sbatch_array_spec grep -qx '#SBATCH --array=1-4' "$script"
for t in 1 2 3 4; do SLURM_ARRAY_TASK_ID=$t bash "$script" > "$tmp/array-task$t.out" 2>&1; done
check sweep_sbatch_each_point_once test "$(cat "$tmp"/array-task*.out | grep -c ': done in ')" -eq 6
"$sweep" merge "$tmp/array" > /dev/null 2>&1
check sweep_sbatch_csv_equals_local cmp "$tmp/array/results.csv" "$tmp/full/results.csv"

# --- a point that fails (a stack too small for the scene: rtsim exits 1 and
# marks its JSON failed) is a result: kept, run_failed = 1 in the CSV, not charted
out=$("$sweep" --set-grid trv.stack_depth=1,64 --res 32x32 --rtsim "$bin" --stat sched.completed \
  --out "$tmp/deadlock" 2>&1); rc=$?
check sweep_deadlock_exit_0 test $rc -eq 0
check sweep_deadlock_kept test "$(ls "$tmp/deadlock/results" | grep -c '\.json$')" -eq 2
check sweep_deadlock_run_failed_column test "$(cut -d, -f6,11 "$tmp/deadlock/results.csv" | sort | tr '\n' ' ')" = "1,1 64,0 trv.stack_depth,run_failed "
check sweep_stat_column test "$(head -n 1 "$tmp/deadlock/results.csv" | cut -d, -f18)" = sched.completed
check sweep_stat_values test "$(tail -n +2 "$tmp/deadlock/results.csv" | cut -d, -f9 | tr '\n' ' ')" = \
  "$(tail -n +2 "$tmp/deadlock/results.csv" | cut -d, -f18 | tr '\n' ' ')"
check sweep_deadlock_named grep -q "1 of 2 points failed" <<< "$out"
check sweep_deadlock_not_charted test "$(grep -c '^[0-9]' "$tmp/deadlock/charts/mrps-vs-trv.stack_depth.dat")" -eq 1
