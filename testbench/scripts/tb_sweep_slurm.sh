#!/usr/bin/env bash
# tb_sweep_slurm — scripts/sweep --slurm on a real one-node Slurm cluster (the
# project's local-slurm tool: Debian's slurm-wlm and munge, installed when
# missing, root only). A sweep submitted as a job array plus a dependent merge
# job merges into the same CSV as the local GNU parallel run; a resubmission
# after losing two results runs exactly those two (sbatch --wait) and merges
# the same CSV again; --accuracy-change with --slurm --wait runs its arrays
# (windowed, then full; or windowed, then more windows) and writes the local
# run's changes.csv, and so do its stages as jobs without --wait, each
# submitting the next. SKIPs, saying why, when no
# cluster can be had. It runs in the release variant only (the Slurm path is
# scripts, the same under ASan). Cost: ~7 s to start the cluster (+ the first
# apt-get install), ~60 s of jobs.
set -u
bin=${RTSIM_BIN:?}/rtsim
tmp=${RTSIM_TMP:-/tmp}/tb_sweep_slurm
rm -rf "$tmp"; mkdir -p "$tmp"
cd "$(dirname "$0")/../.."
sweep=$PWD/scripts/sweep

. testbench/cli_lib.sh

skip() { echo "SKIP sweep_slurm: $*"; exit 0; }
[ -z "${RTSIM_TB_SANITIZED:-}" ] || skip "release variant only (the Slurm path is the same scripts)"
[ "$(id -u)" = 0 ] || skip "local-slurm needs root (it starts munged, slurmctld and slurmd)"
# The tool: $LOCAL_SLURM, else tools/local-slurm in the shared folder beside the
# repository (../shared) or beside the folder of worktrees (../../shared).
tool=${LOCAL_SLURM:-}
for c in ../shared/tools/local-slurm ../../shared/tools/local-slurm; do
  [ -n "$tool" ] || { [ -x "$c" ] && tool=$c; }
done
[ -n "$tool" ] && [ -x "$tool" ] || skip "no local-slurm tool (set LOCAL_SLURM=path/to/local-slurm)"

# One run of this test at a time on the machine: local-slurm's cluster is one
# per machine, and a run that started it stops it at its end, under any other
# run still waiting for its jobs (seen with two checkouts testing at once: the
# other run's sbatch --wait hung until the program timeout). The lock sits
# beside local-slurm's own folder.
exec 9> "$(dirname "$(mktemp -u)")/rtsim-tb-sweep-slurm.lock"
flock -w 600 9 || skip "another run of this test held the Slurm lock for 10 minutes"
# A cluster that already runs (SLURM_CONF given, or local-slurm's own) is used
# as it is; otherwise this test starts one and stops it at the end.
started=0
if [ -n "${SLURM_CONF:-}" ] && timeout 20 sinfo -h > /dev/null 2>&1; then
  :
elif conf=$(dirname "$(mktemp -u)")/local-slurm/slurm.conf && [ -f "$conf" ] &&
     SLURM_CONF=$conf timeout 20 sinfo -h -o '%t' 2>/dev/null | grep -qE 'idle|mix|alloc'; then
  export SLURM_CONF=$conf
else
  if ! env_line=$(timeout 600 "$tool" start 2> "$tmp/start.err"); then
    skip "local-slurm start failed: $(tail -n 2 "$tmp/start.err" | tr '\n' ' ')"
  fi
  eval "$env_line"
  started=1
  trap '"$tool" stop > /dev/null 2>&1' EXIT
fi
command -v sbatch > /dev/null || skip "sbatch not found after local-slurm start"

grid=(--set-grid node_l1.size=4096,16384 --machines bvh2,mbvh4 --res 32x18 --rtsim "$bin")

# The reference: the same grid on local cores through GNU parallel.
"$sweep" "${grid[@]}" --out "$tmp/local" > "$tmp/local.out" 2>&1
check sweep_slurm_local_reference test -s "$tmp/local/results.csv"

# Submit: two array tasks for four points (each task runs two) and a merge job
# after the array; then wait for the merge job to leave the queue.
out=$(SWEEP_SLURM_TASKS=2 "$sweep" "${grid[@]}" --out "$tmp/cluster" --slurm 2>&1); rc=$?
check sweep_slurm_submit_exit_0 test $rc -eq 0
merge_job=$(sed -n 's/.* and merge job \([0-9]*\) .*/\1/p' <<< "$out")
check sweep_slurm_merge_job_id test -n "$merge_job"
for _ in $(seq 1 300); do
  [ -n "$merge_job" ] && squeue -h -j "$merge_job" 2> /dev/null | grep -q . || break
  sleep 1
done
check sweep_slurm_array_task_logs test "$(ls "$tmp/cluster/logs" | grep -c '^slurm-[0-9]*_[12]\.out$')" -eq 2
check sweep_slurm_merge_job_log grep -q "merged 4 of 4 points" "$tmp/cluster/logs/slurm-merge-$merge_job.out"
check sweep_slurm_csv_equals_local cmp "$tmp/cluster/results.csv" "$tmp/local/results.csv"

# Resume on the cluster: two results lost, resubmitted with --wait, exactly
# those two run and the merged CSV is the same again.
rm -f "$tmp/cluster/results.csv"
lost=("$tmp/cluster/results/"*.json)   # an array, not ls | xargs: the path may hold spaces
rm -f "${lost[@]:0:2}"
out=$("$sweep" "${grid[@]}" --out "$tmp/cluster" --slurm --wait 2>&1); rc=$?
check sweep_slurm_wait_exit_0 test $rc -eq 0
check sweep_slurm_resume_two_to_run grep -q "4 points in .*, 2 to run" <<< "$out"
check sweep_slurm_resume_array_of_two grep -qx '#SBATCH --array=1-2' "$tmp/cluster/sweep.sbatch"
check sweep_slurm_resume_csv_equals_local cmp "$tmp/cluster/results.csv" "$tmp/local/results.csv"

# --accuracy-change with --slurm --wait: the windowed array, then an array of
# the points to rerun at full (all of them at 0.001pt), and the same
# changes.csv as the local run (tb_sweep_accuracy_change.sh tests the rule).
acc=(--set-grid node_l1.size=4096,65536 --scenes interior --rays diffuse --machines mbvh4 --res 640x360
     --set node_l2.size=32K --set prim.size=32K --rtsim "$bin" --accuracy-change 0.001pt --
     --bounces 1 --sample-rate 0.3 --jobs 1)
"$sweep" --jobs 1 --out "$tmp/acc-local" "${acc[@]}" > "$tmp/acc-local.out" 2>&1
out=$("$sweep" --out "$tmp/acc-cluster" --slurm --wait "${acc[@]}" 2>&1); rc=$?
check sweep_slurm_accuracy_change_exit_0 test $rc -eq 0
check sweep_slurm_accuracy_change_two_arrays test "$(grep -c '^sweep: submitting .*sweep.sbatch and waiting' <<< "$out")" -eq 2
check sweep_slurm_accuracy_change_reruns grep -q "0 points passed at windowed, 0 with more windows, 2 rerun at full" <<< "$out"
check sweep_slurm_accuracy_change_csv_equals_local cmp "$tmp/acc-cluster/changes.csv" "$tmp/acc-local/changes.csv"
# ... and with P just under the point's half-width: the point and its
# baseline rerun with more windows as one array of their own (DIR/more), the
# windowed results reused, nothing at full; the same changes.csv as locally
p=$(python3 - "$tmp/acc-local/paired.csv" <<'PY'
import csv, sys
r = list(csv.DictReader(open(sys.argv[1])))[1]
print("%.6fpt" % (0.98 * max(float(r[f + "_change_err_pt"]) for f in ("mrps", "dram_mb", "energy_mj"))))
PY
)
"$sweep" --jobs 1 --out "$tmp/acc-local" "${acc[@]/0.001pt/$p}" > "$tmp/acc-local-more.out" 2>&1
out=$("$sweep" --out "$tmp/acc-cluster" --slurm --wait "${acc[@]/0.001pt/$p}" 2>&1); rc=$?
check sweep_slurm_accuracy_change_more_exit_0 test $rc -eq 0
check sweep_slurm_accuracy_change_more_one_array test "$(grep '^sweep: submitting' <<< "$out")" = \
  "sweep: submitting $tmp/acc-cluster/more/sweep.sbatch and waiting for it"
check sweep_slurm_accuracy_change_more_reruns grep -q "0 points passed at windowed, 2 with more windows, 0 rerun at full" <<< "$out"
check sweep_slurm_accuracy_change_more_csv_equals_local cmp "$tmp/acc-cluster/changes.csv" "$tmp/acc-local/changes.csv"
# ... and without --wait: the windowed array and a job after it that decides
# (the same point and baseline with more windows), submits their array and
# the next stage's job after it; once the last job has left the queue, the
# same changes.csv as locally
out=$("$sweep" --out "$tmp/acc-jobs" --slurm "${acc[@]/0.001pt/$p}" 2>&1); rc=$?
check sweep_slurm_accuracy_change_jobs_exit_0 test $rc -eq 0
check sweep_slurm_accuracy_change_jobs_submitted grep -q "^sweep: submitted array job [0-9]* (2 points in .*) and the --accuracy-change job [0-9]* (more, after it)" <<< "$out"
for _ in $(seq 1 300); do
  squeue -h -o %j 2> /dev/null | grep -q '^rtsim-sweep' || break
  sleep 1
done
check sweep_slurm_accuracy_change_jobs_more_array grep -q "^sweep: submitted array job [0-9]* (2 points in .*/more) and the --accuracy-change job [0-9]* (full, after it)" "$tmp/acc-jobs/logs/"slurm-accuracy-more-*.out
check sweep_slurm_accuracy_change_jobs_reruns grep -q "0 points passed at windowed, 2 with more windows, 0 rerun at full" "$tmp/acc-jobs/logs/"slurm-accuracy-full-*.out
check sweep_slurm_accuracy_change_jobs_csv_equals_local cmp "$tmp/acc-jobs/changes.csv" "$tmp/acc-local/changes.csv"
[ $started = 0 ] || echo "# stopped the cluster this test started" >&2
