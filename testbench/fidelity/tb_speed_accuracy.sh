#!/usr/bin/env bash
# tb_speed_accuracy — scripts/speed-accuracy on a tiny matrix (interior,
# 64x36, both machines, both ray types, the functional level and
# --accuracy 40%): the CSV has a row per configuration and level with the
# true error of each figure equal to the one computed from the runs' JSON,
# the estimate, the flag, CPU and wall speedups; the summary counts the
# points outside their estimate and not flagged; gnuplot wrote the charts;
# bad levels are refused with exit 2.
set -u
tmp=${RTSIM_TMP:-/tmp}/tb_speed_accuracy
rm -rf "$tmp"; mkdir -p "$tmp"
cd "$(dirname "$0")/../.."
. testbench/cli_lib.sh
if ! command -v gnuplot >/dev/null; then
  echo "SKIP speed_accuracy: gnuplot is not installed (scripts/debian-packages.txt lists it)"; exit 0
fi
sa=(scripts/speed-accuracy --bin "${RTSIM_BIN:?}/rtsim" --scenes interior --res 64x36 --levels functional,auto@40
    --jobs 2 --out "$tmp/out")
"${sa[@]}" >"$tmp/log" 2>&1; rc=$?
check speed_accuracy_runs test "$rc" -eq 0
for f in speed-accuracy.csv speed-accuracy.md speed-accuracy-mrps.png speed-accuracy-dram_mb.svg; do
  check "speed_accuracy_writes_${f//[.-]/_}" test -s "$tmp/out/$f"
done
check_csv() {
  python3 - "$tmp/out" <<'PY'
import csv, json, os, sys
out = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(out, "speed-accuracy.csv"))))
assert len(rows) == 8, len(rows)          # 2 rays x 2 machines x 2 levels
for r in rows:
    full = json.load(open(os.path.join(out, "runs", "interior_%s_%s_64x36_full.json" % (r["rays"], r["machine"]))))
    lv = json.load(open(os.path.join(out, "runs", "interior_%s_%s_64x36_%s.json" % (r["rays"], r["machine"], r["level"].replace("@", "-")))))
    for key, st in (("mrps", "mrps"), ("dram_mb", "dram_bytes"), ("energy_mj", "energy_mj")):
        err = 100 * abs(lv[st] / full[st] - 1)
        assert abs(float(r["true_err_" + key]) - err) < 0.01, (r, key, err)
        assert abs(float(r["est_err_" + key]) - lv["error_estimate." + key]) < 0.01, (r, key)
    assert r["picked"] == lv["fidelity"] and int(r["unreliable"]) == lv["unreliable"], r
    assert float(r["speedup"]) > 0 and float(r["wall_speedup"]) > 0, r
    silent = any(float(r["true_err_" + k]) > float(r["est_err_" + k]) + 1e-9 for k in ("mrps", "dram_mb", "energy_mj"))
    assert int(r["silent"]) == int(silent and not lv["unreliable"]), r
md = open(os.path.join(out, "speed-accuracy.md")).read()
total = sum(int(r["silent"]) for r in rows)
assert "Points outside their estimate and not flagged, in all: %d of 8." % total in md, md
PY
}
check speed_accuracy_csv_matches_runs check_csv
expect speed_accuracy_bad_level 2 "--levels fast: allowed fixed-mem, functional, sampled, sampled@R, windowed, windowed@R, auto@P" -- scripts/speed-accuracy --bin "$RTSIM_BIN/rtsim" --levels fast
