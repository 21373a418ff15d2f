#!/usr/bin/env bash
# tb_fidelity_paired — a sweep's paired estimates (scripts/paired.py,
# docs/fidelity.md "windowed"): the same small sweep (node_l1.size on one
# machine, interior diffuse, one bounce, 640x360) at full and at windowed;
# every point runs the same windows; each windowed change against the
# baseline is inside its paired interval around the full sweep's change,
# and that interval is narrower than the sum of the two points' own
# estimates (what pairing is for); the lattice's and the start
# correction's errors pair as well (a run against itself keeps only its
# bias bound); `scripts/sweep` writes paired.csv when it merges windowed
# points, with the baseline --baseline names; a bad --baseline exits 2
# naming the keys or values.
set -u
bin=${RTSIM_BIN:?}/rtsim
tmp=${RTSIM_TMP:-/tmp}/tb_fidelity_paired
rm -rf "$tmp"; mkdir -p "$tmp"
. "$(dirname "$0")/../cli_lib.sh"
cd "$(dirname "$0")/../.."

if [ -n "${RTSIM_TB_SANITIZED:-}" ]; then
  echo "SKIP fidelity_paired: release build only (two sweeps of 640x360 diffuse frames)"
  exit 0
fi
grid=(--set-grid node_l1.size=4096,16384,65536 --scenes interior --rays diffuse --machines mbvh4 --res 640x360
      --jobs 1 --rtsim "$bin")
scripts/sweep "${grid[@]}" --out "$tmp/full" -- --bounces 1 >"$tmp/full.log" 2>&1
scripts/sweep "${grid[@]}" --out "$tmp/win" -- --bounces 1 --fidelity windowed --sample-rate 0.3 --jobs 2 \
  >"$tmp/win.log" 2>&1
if [ -f "$tmp/win/paired.csv" ] && grep -q "^sweep: paired changes of 3 points" "$tmp/win.log"; then
  pass fidelity_paired_csv_written_by_sweep
else fail fidelity_paired_csv_written_by_sweep "$(tail -3 "$tmp/win.log" | tr '\n' ' ')"; fi
python3 scripts/paired.py "$tmp/win" --against "$tmp/full" >"$tmp/paired.log" 2>&1
if python3 - "$tmp/win/paired.csv" "$tmp/win" <<'PY'
import csv, glob, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 3, len(rows)
runs = [json.load(open(f)) for f in sorted(glob.glob(sys.argv[2] + "/results/*.json"))]
# the same windows for every machine point
plans = {(d["window.count"], d["window.pixels"], d["window.warm_pixels"]) for d in runs}
assert len(plans) == 1, plans
base = rows[0]["baseline"]
for r in rows:
    for f in ("mrps", "dram_mb", "energy_mj"):
        ch, full, err = float(r[f + "_change_pct"]), float(r[f + "_full_change_pct"]), float(r[f + "_change_err_pt"])
        assert r[f + "_paired"] == "1", (r["point"], f)
        assert abs(ch - full) <= err, (r["point"], f, ch, full, err)
    assert r["baseline"] == base
# pairing narrows the change's interval below the sum of the two points' estimates
by_name = {}
for fpath in glob.glob(sys.argv[2] + "/results/*.json"):
    by_name[fpath.rsplit("/", 1)[1][:-5]] = json.load(open(fpath))
for r in rows:
    if r["point"] == base:
        continue
    for f in ("mrps", "dram_mb", "energy_mj"):
        unpaired = by_name[r["point"]]["error_estimate." + f] + by_name[base]["error_estimate." + f]
        assert float(r[f + "_change_err_pt"]) < unpaired, (r["point"], f, r[f + "_change_err_pt"], unpaired)
PY
then pass fidelity_paired_changes_within_interval
else fail fidelity_paired_changes_within_interval "$(cat "$tmp/paired.log") $(head -3 "$tmp/win/paired.csv" | tr '\n' ' ')"; fi
# the lattice's and the start correction's errors pair too: a run against
# itself has only its bias bound left; each run's pairing residuals carry
# about the variance of its own (independent) estimate of those errors
if python3 - "$tmp/win" <<'PY'
import glob, json, math, sys
sys.path.insert(0, "scripts")
import paired
for f in sorted(glob.glob(sys.argv[1] + "/results/*.json")):
    j = json.load(open(f))
    assert j["window.lattice_groups"] == 16 and j["window.start_windows"] >= 2, f
    for fig in paired.FIGS:
        col = fig[0]
        ch, err, was_paired = paired.change(j, j, fig)
        assert was_paired and ch == 0, (f, col, ch)
        assert abs(err - j["window.bias_err." + col]) < 1e-9, (f, col, err)
        g, w, n = 16, j["window.start_windows"], j["window.paired_windows"]
        lat = paired.t95(g - 1) * math.sqrt(sum(j["window.lat_resid.%s.%d" % (col, i)] ** 2 for i in range(g)))
        st = paired.t95(w - 1) * math.sqrt(sum(j["window.start_resid.%s.%d" % (col, q)] ** 2 for q in range(n)))
        own = j["window.other_err." + col] / 100
        # the same scale as the run's own estimate, which treats the lattice
        # as a simple random sample: the interleaved (systematic) groups see
        # 0.4-1.4 times its spread (a lost normalisation would be 15x off)
        assert 0.3 * own <= math.hypot(lat, st) <= 2 * own, (f, col, lat, st, own)
PY
then pass fidelity_paired_other_errors_pair
else fail fidelity_paired_other_errors_pair "a run against itself, or the residuals' sums"; fi
expect fidelity_paired_bad_baseline 2 "--baseline scene: allowed keys machine, node_l1.size" -- \
  python3 scripts/paired.py "$tmp/win" --baseline scene=interior
# scripts/sweep --baseline: kept in sweep.conf, used by the merge's paired.csv
scripts/sweep "${grid[@]}" --out "$tmp/win" --baseline node_l1.size=16384 -- --bounces 1 --fidelity windowed \
  --sample-rate 0.3 --jobs 2 >"$tmp/win2.log" 2>&1
if grep -q "^baseline node_l1.size=16384$" "$tmp/win/sweep.conf" && python3 - "$tmp/win" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1] + "/paired.csv")))
base = [r for r in rows if r["point"] == r["baseline"]]
assert len(base) == 1 and base[0]["node_l1.size"] == "16384", base
PY
then pass fidelity_paired_sweep_baseline
else fail fidelity_paired_sweep_baseline "$(tail -2 "$tmp/win2.log" | tr '\n' ' ')"; fi
expect fidelity_paired_sweep_bad_baseline_value 2 "--baseline node_l1.size=999: node_l1.size must be one of its --set-grid values" -- \
  scripts/sweep "${grid[@]}" --out "$tmp/bad" --baseline node_l1.size=999
expect fidelity_paired_sweep_bad_baseline_key 2 "--baseline scene=interior: allowed keys are machine and the --set-grid keys" -- \
  scripts/sweep "${grid[@]}" --out "$tmp/bad" --baseline scene=interior
