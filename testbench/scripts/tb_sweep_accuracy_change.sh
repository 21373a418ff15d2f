#!/usr/bin/env bash
# tb_sweep_accuracy_change — scripts/sweep --accuracy-change P (docs/sweep.md
# "Changes to a given accuracy"): a small windowed sweep (node_l1.size on one
# machine, interior diffuse, one bounce, 640x360 with small L2 and primitive
# caches so that the windows' caches fill and no point is flagged). With
# 50pt no point is rerun and every change is the paired windowed one; with
# 0.001pt every point and the baseline are rerun at full (more windows
# cannot bring a change within it) and the changes equal those of a plain
# full sweep of the same points; with P just under the wider point's
# half-width that point and the baseline are rerun with more windows (the
# same windows' size, whole pairs) and its change is the paired one of those
# two runs, or at full when still over P; with P between the two points'
# half-widths and no room in the frame for more windows, only the wider one
# and the baseline are rerun at full and the other keeps its windowed
# change; the same inputs give the same changes.csv bytes; bad values and
# combinations exit 2 naming the option.
# The Slurm paths (--slurm, with and without --wait) are in tb_sweep_slurm.sh.
set -u
bin=${RTSIM_BIN:?}/rtsim
tmp=${RTSIM_TMP:-/tmp}/tb_sweep_accuracy_change
rm -rf "$tmp"; mkdir -p "$tmp"
cd "$(dirname "$0")/../.."
sweep=$PWD/scripts/sweep
. testbench/cli_lib.sh

# --- bad values and combinations: exit 2, the option named, nothing planned
for v in 0 abc 200pt -1 1% ''; do
  expect "sweep_accuracy_change_bad_value_$(printf %s "${v:-empty}" | tr -c 'A-Za-z0-9' _)" 2 "--accuracy-change $v: expected percentage points in (0, 100]" -- \
    "$sweep" --accuracy-change "$v" --rtsim "$bin" --out "$tmp/u"
done
expect sweep_accuracy_change_no_value 2 "--accuracy-change needs a value" -- "$sweep" --rtsim "$bin" --accuracy-change
expect sweep_accuracy_change_with_fidelity 2 "--accuracy-change picks the levels itself" -- \
  "$sweep" --accuracy-change 1pt --rtsim "$bin" --out "$tmp/u" -- --fidelity=sampled
expect sweep_accuracy_change_with_accuracy 2 "drop --accuracy from the rtsim arguments" -- \
  "$sweep" --accuracy-change 1pt --rtsim "$bin" --out "$tmp/u" -- --accuracy 2%
expect sweep_accuracy_change_with_slurm_script 2 "--accuracy-change with Slurm needs --slurm (its reruns depend on the merged windowed results" -- \
  "$sweep" --accuracy-change 1pt --slurm-script --rtsim "$bin" --out "$tmp/u"
check sweep_accuracy_change_bad_nothing_planned test ! -e "$tmp/u/jobs.tsv"
# the Slurm stages' own entry (scripts/sweep accuracy-stage, run by the jobs)
expect sweep_accuracy_stage_no_sweep_dir 2 "accuracy-stage: $tmp/u/jobs.tsv not found" -- \
  "$sweep" accuracy-stage "$tmp/u" more 1pt
mkdir -p "$tmp/p" && : > "$tmp/p/jobs.tsv"
expect sweep_accuracy_stage_bad_points 2 "accuracy-stage: P = 1%: expected percentage points in (0, 100]" -- \
  "$sweep" accuracy-stage "$tmp/p" final 1%
expect sweep_accuracy_stage_bad_stage 2 "STAGE must be more, full or final, not 'most'" -- \
  "$sweep" accuracy-stage "$tmp/p" most 1pt
expect sweep_accuracy_stage_bad_jobs 2 "accuracy-stage: --jobs 0: expected a positive integer" -- \
  "$sweep" accuracy-stage "$tmp/p" more 1pt --jobs 0

if [ -n "${RTSIM_TB_SANITIZED:-}" ]; then
  echo "SKIP sweep_accuracy_change_runs: release build only (windowed and full sweeps of 640x360 diffuse frames)"
  exit 0
fi
grid=(--set-grid node_l1.size=4096,16384,65536 --scenes interior --rays diffuse --machines mbvh4 --res 640x360
      --set node_l2.size=32K --set prim.size=32K --jobs 1 --rtsim "$bin")
d=$tmp/acc
# 0.3 of the pixels: room for 4/3 the windows (at most 0.4 of the frame)
acc() { "$sweep" "${grid[@]}" --out "$d" --accuracy-change "$1" -- --bounces 1 --sample-rate 0.3 --jobs 1; }

# p_between PAIRED.CSV mid|under_wide: a P between the two non-baseline
# points' widest half-widths (mid: half-way; under_wide: just under the
# wider one, at least half-way), empty when the two are equal
p_between() {
  python3 - "$1" "$2" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))[1:]
w = sorted(max(float(r[f + "_change_err_pt"]) for f in ("mrps", "dram_mb", "energy_mj")) for r in rows)
mid = (w[0] + w[1]) / 2
print("%.6fpt" % (max(w[1] * 0.98, mid) if sys.argv[2] == "under_wide" else mid) if w[1] - w[0] > 1e-3 else "")
PY
}

# (a) a generous P: nothing rerun, every change the paired windowed one
acc 50pt >"$tmp/a.log" 2>&1; rc=$?
if [ $rc -eq 0 ] && grep -q "^sweep: --accuracy-change 50pt: 3 points passed at windowed, 0 with more windows, 0 rerun at full" "$tmp/a.log" &&
   [ "$(wc -l < "$d/full/jobs.tsv")" -eq 1 ] && [ -z "$(ls "$d/full/results")" ] &&
   [ "$(wc -l < "$d/more/jobs.tsv")" -eq 1 ] && [ -z "$(ls "$d/more/results")" ] &&
   python3 - "$d" <<'PY'
import csv, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(d + "/changes.csv")))
pr = {r["point"]: r for r in csv.DictReader(open(d + "/paired.csv"))}
assert len(rows) == 3 and all(r["change_from"] == "windowed-paired" and r["fidelity"] == "windowed" for r in rows), rows
for r in rows[1:]:
    for f in ("mrps", "dram_mb", "energy_mj"):
        assert r[f + "_change_pct"] == pr[r["point"]][f + "_change_pct"], (r["point"], f)
        assert r[f + "_change_err_pt"] == pr[r["point"]][f + "_change_err_pt"], (r["point"], f)
        assert float(r[f + "_change_err_pt"]) <= 50
assert all(rows[0][f + s] == "0.0000" for f in ("mrps", "dram_mb", "energy_mj") for s in ("_change_pct", "_change_err_pt"))
PY
then pass sweep_accuracy_change_generous_no_rerun
else fail sweep_accuracy_change_generous_no_rerun "exit $rc: $(tail -3 "$tmp/a.log" | tr '\n' ' ')"; fi

# (b) a tiny P: every point and the baseline rerun at full, changes as a plain full sweep's
"$sweep" "${grid[@]}" --out "$tmp/full" -- --bounces 1 >"$tmp/full.log" 2>&1
acc 0.001pt >"$tmp/b.log" 2>&1; rc=$?
cp "$d/changes.csv" "$tmp/b.csv"
if [ $rc -eq 0 ] && grep -q "^sweep: --accuracy-change 0.001pt: 0 points passed at windowed, 0 with more windows, 3 rerun at full (baselines: 1)" "$tmp/b.log" &&
   [ "$(wc -l < "$d/more/jobs.tsv")" -eq 1 ] &&
   python3 - "$d" "$tmp/full" <<'PY'
import csv, json, sys
sys.path.insert(0, "scripts")
import rtsim_runs
d, full = sys.argv[1:3]
rows = list(csv.DictReader(open(d + "/changes.csv")))
jobs = [l.rstrip("\n").split("\t") for l in open(full + "/jobs.tsv")][1:]
fj = [json.load(open("%s/results/%s.json" % (full, p[0]))) for p in jobs]
assert len(rows) == 3 and all(r["change_from"] == "full" and r["fidelity"] == "full" for r in rows), rows
for r, j in zip(rows, fj):
    for f, key in (("mrps", "mrps"), ("dram_mb", "dram_bytes"), ("energy_mj", "energy_mj")):
        want = "%.4f" % rtsim_runs.change_pct(j[key], fj[0][key])
        assert r[f + "_change_pct"] == want, (r["point"], f, r[f + "_change_pct"], want)
        assert r[f + "_change_err_pt"] == "0.0000", (r["point"], f)
        assert float(r[f]) == rtsim_runs.figure(j, f), (r["point"], f)
PY
then pass sweep_accuracy_change_tiny_all_full_equal_plain_full
else fail sweep_accuracy_change_tiny_all_full_equal_plain_full "exit $rc: $(tail -3 "$tmp/b.log" | tr '\n' ' ')"; fi

# the same inputs again: nothing runs, the same bytes; no temporary left
acc 0.001pt >"$tmp/b2.log" 2>&1
if cmp -s "$d/changes.csv" "$tmp/b.csv" && ! grep -q "done in" "$tmp/b2.log" &&
   [ -z "$(find "$d" -name '*.tmp.*')" ]; then pass sweep_accuracy_change_deterministic_resumed
else fail sweep_accuracy_change_deterministic_resumed "$(diff "$d/changes.csv" "$tmp/b.csv" | head -3 | tr '\n' ' ')"; fi

# P just under the wider point's widest half-width (and over the narrower's):
# the wider point and the baseline with more windows of the same size; its
# change the paired one of those two runs when within P, else both at full
p=$(p_between "$d/paired.csv" under_wide)
if [ -z "$p" ]; then echo "SKIP sweep_accuracy_change_more_windows: the two points' half-widths are equal"
else
  acc "$p" >"$tmp/m.log" 2>&1; rc=$?
  if [ $rc -eq 0 ] && grep -q "^sweep: running 2 points with more windows" "$tmp/m.log" &&
     python3 - "$d" "$tmp/b.csv" "${p%pt}" <<'PY'
import csv, json, sys
sys.path.insert(0, "scripts")
import paired
d, b, p = sys.argv[1], sys.argv[2], float(sys.argv[3])
rows = list(csv.DictReader(open(d + "/changes.csv")))
pr = {r["point"]: r for r in csv.DictReader(open(d + "/paired.csv"))}
full = {r["point"]: r for r in csv.DictReader(open(b))}
err = lambda r: max(float(r[f + "_change_err_pt"]) for f in ("mrps", "dram_mb", "energy_mj"))
narrow, wide = sorted(rows[1:], key=lambda r: err(pr[r["point"]]))
jobs = [l.rstrip("\n").split("\t") for l in open(d + "/more/jobs.tsv")][1:]
assert [j[6] for j in jobs] == [rows[0]["node_l1.size"], wide["node_l1.size"]], jobs
mj = [json.load(open("%s/more/results/%s.json" % (d, j[0]))) for j in jobs]
w0 = json.load(open("%s/results/%s.json" % (d, rows[0]["point"])))
# more windows of the same size, in whole pairs, for both runs alike
size = lambda j: (j["window.pixels"] + j["window.warm_pixels"])
assert mj[0]["window.count"] == mj[1]["window.count"] > w0["window.count"] and mj[0]["window.count"] % 2 == 0
assert abs(size(mj[0]) - size(w0)) <= 1, (size(mj[0]), size(w0))
assert "--windows %d" % mj[0]["window.count"] in jobs[0][-1] and "--sample-rate" in jobs[0][-1]
assert narrow["change_from"] == "windowed-paired"
for f in ("mrps", "dram_mb", "energy_mj"):
    assert narrow[f + "_change_pct"] == pr[narrow["point"]][f + "_change_pct"]
more_err = max(paired.change(mj[0], mj[1], fg)[1] for fg in paired.FIGS)
if more_err <= p:
    assert wide["change_from"] == "windowed-more" and rows[0]["change_from"] == "windowed-more", (wide, rows[0])
    for fg in paired.FIGS:
        ch, e, _ = paired.change(mj[0], mj[1], fg)
        assert wide[fg[0] + "_change_pct"] == "%.4f" % ch and wide[fg[0] + "_change_err_pt"] == "%.4f" % e
else:
    assert wide["change_from"] == "full" and rows[0]["change_from"] == "full", (wide, rows[0])
    for f in ("mrps", "dram_mb", "energy_mj"):
        assert wide[f + "_change_pct"] == full[wide["point"]][f + "_change_pct"]
print("more windows: %d, half-width %.3f against P %.3f" % (mj[0]["window.count"], more_err, p), file=sys.stderr)
PY
  then pass sweep_accuracy_change_more_windows
  else fail sweep_accuracy_change_more_windows "P $p, exit $rc: $(tail -3 "$tmp/m.log" | tr '\n' ' ')"; fi
fi

# P between the two points' widest half-widths at 0.4 of the frame (no room
# for more windows): only the wider point and the baseline rerun at full;
# the narrower keeps its paired windowed change
d=$tmp/acc_room
mkdir -p "$d/full/results"
cp "$tmp/acc/full/results/"*.json "$d/full/results/"   # the same full points (the level's options left out)
room() { "$sweep" "${grid[@]}" --out "$d" --accuracy-change "$1" -- --bounces 1 --sample-rate 0.4 --jobs 1; }
room 50pt >"$tmp/r.log" 2>&1
p=$(p_between "$d/paired.csv" mid)
if [ -z "$p" ]; then echo "SKIP sweep_accuracy_change_mixed: the two points' half-widths are equal"
else
  room "$p" >"$tmp/c.log" 2>&1; rc=$?
  if [ $rc -eq 0 ] && grep -q "no room for more windows" "$tmp/c.log" &&
     [ "$(wc -l < "$d/more/jobs.tsv")" -eq 1 ] && python3 - "$d" "$tmp/b.csv" <<'PY'
import csv, sys
d, b = sys.argv[1:3]
rows = list(csv.DictReader(open(d + "/changes.csv")))
pr = {r["point"]: r for r in csv.DictReader(open(d + "/paired.csv"))}
full = {r["node_l1.size"]: r for r in csv.DictReader(open(b))}   # the same points at full
err = lambda r: max(float(r[f + "_change_err_pt"]) for f in ("mrps", "dram_mb", "energy_mj"))
narrow, wide = sorted(rows[1:], key=lambda r: err(pr[r["point"]]))
assert rows[0]["change_from"] == "full" and wide["change_from"] == "full" and narrow["change_from"] == "windowed-paired"
for f in ("mrps", "dram_mb", "energy_mj"):
    assert wide[f + "_change_pct"] == full[wide["node_l1.size"]][f + "_change_pct"]
    assert narrow[f + "_change_pct"] == pr[narrow["point"]][f + "_change_pct"]
PY
  then pass sweep_accuracy_change_mixed_group
  else fail sweep_accuracy_change_mixed_group "P $p, exit $rc: $(tail -3 "$tmp/c.log" | tr '\n' ' ')"; fi
fi
