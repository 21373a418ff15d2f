#!/usr/bin/env bash
# tb_paper_tables — scripts/paper-tables on a tiny matrix (the built-in
# interior scene, 16x9, both machines, both ray types): Table 1 and Table 2
# in Markdown and CSV with the paper's numbers beside ours, values equal to
# rtsim's JSON, the change in percent computed from them, charts that
# gnuplot wrote (PNG and SVG), a second call that reuses the runs, bad
# arguments refused with exit 2, and --accuracy (cheaper levels for Table
# 2, full for Table 1's scene).
set -u
tmp=${RTSIM_TMP:-/tmp}/tb_paper_tables
rm -rf "$tmp"; mkdir -p "$tmp"
cd "$(dirname "$0")/../.."
. testbench/cli_lib.sh
pt=(scripts/paper-tables --bin "${RTSIM_BIN:?}/rtsim" --scenes interior --res 16x9 --jobs 2 --out "$tmp/out")
if ! command -v gnuplot >/dev/null; then
  echo "SKIP paper_tables: gnuplot is not installed (scripts/debian-packages.txt lists it)"; exit 0
fi
"${pt[@]}" >"$tmp/log" 2>&1; rc=$?
check paper_tables_runs test "$rc" -eq 0
for f in table1.md table1.csv table2.md table2.csv changes.png changes.svg; do
  check "paper_tables_writes_${f/./_}" test -s "$tmp/out/$f"
done
check paper_tables_png_is_png sh -c 'head -c 8 "$1/out/changes.png" | grep -q PNG' _ "$tmp"
check paper_tables_svg_is_svg grep -q '<svg' "$tmp/out/changes.svg"
check paper_tables_no_temp_left sh -c '! ls "$1/out" | grep -q "\.tmp$"' _ "$tmp"
check_values() {
  python3 - "$tmp/out" <<'PY'
import csv, json, os, sys
out = sys.argv[1]
runs = {}
for r in ("primary", "diffuse"):
    for m in ("bvh2", "mbvh4"):
        runs[(r, m)] = json.load(open(os.path.join(out, "runs", "interior_%s_%s_16x9.json" % (r, m))))
t2 = list(csv.DictReader(open(os.path.join(out, "table2.csv"))))
names = {"MRPS": "mrps", "mJ/frame": "energy_mj", "MRPS/mm2": "mrps_per_mm2"}
seen = 0
for row in t2:
    if row["scene"] != "interior":
        continue
    r = row["rays"]
    for m, col in (("bvh2", "ours_bvh2"), ("mbvh4", "ours_mbvh4")):
        d = runs[(r, m)]
        want = d["dram_bytes"] / 1e6 if row["figure"] == "DRAM MB" else d[names[row["figure"]]]
        assert abs(float(row[col]) - want) <= 1e-5 * abs(want), (row, want)
    b, a = float(row["ours_bvh2"]), float(row["ours_mbvh4"])
    assert abs(float(row["ours_change_pct"]) - 100 * (a - b) / b) < 0.01, row
    seen += 1
assert seen == 8, seen
means = [row for row in t2 if row["scene"] == "mean"]
assert len(means) == 8 and all(row["paper_change_pct"] for row in means), means
t1 = list(csv.DictReader(open(os.path.join(out, "table1.csv"))))
area = {row["unit"]: float(row["ours"]) for row in t1 if row["machine"] == "mbvh4" and row["figure"] == "area_mm2"}
assert abs(area["total"] - runs[("primary", "mbvh4")]["area_mm2"]) < 1e-5, area
assert [row["paper"] for row in t1 if row["machine"] == "bvh2" and row["unit"] == "trv" and row["figure"] == "area_mm2"] == ["0.25"]
p = [row for row in t1 if row["machine"] == "bvh2" and row["figure"] == "power_mw" and row["rays"] == "diffuse"
     and row["unit"] == "dram"]
assert p and p[0]["paper"] == "608" and abs(float(p[0]["ours"]) - runs[("diffuse", "bvh2")]["power.dram_mw"]) < 1e-3 * float(p[0]["ours"])
PY
}
check paper_tables_values_equal_json check_values
stamp=$(stat -c %Y "$tmp/out/runs/interior_primary_bvh2_16x9.json")
sleep 1
"${pt[@]}" >/dev/null 2>&1
check paper_tables_reuses_runs test "$stamp" = "$(stat -c %Y "$tmp/out/runs/interior_primary_bvh2_16x9.json")"
expect paper_tables_bad_rays 2 "allowed primary, diffuse" -- scripts/paper-tables --bin "$RTSIM_BIN/rtsim" --rays shadow
expect paper_tables_bad_jobs 2 "--jobs 0" -- scripts/paper-tables --bin "$RTSIM_BIN/rtsim" --jobs 0
expect paper_tables_bad_table1_scene 2 "not among --scenes" -- scripts/paper-tables --bin "$RTSIM_BIN/rtsim" --scenes interior --table1-scene city
# a bad --accuracy: rtsim's own message (not its "see --help" hint), exit 2
expect paper_tables_bad_accuracy 2 "rtsim: --accuracy abc: expected a percentage in (0, 100]" -- scripts/paper-tables --bin "$RTSIM_BIN/rtsim" --scenes interior --res 16x9 --accuracy abc --out "$tmp/badacc"
# --accuracy: every point at the level rtsim picks (hairball at 40%:
# functional for some points); Table 1's scene again at full where its level
# does not report each unit's power (functional, sampled); MRPS/mm2 from the
# machine's area where a cheaper level does not report it
acc=(scripts/paper-tables --bin "${RTSIM_BIN:?}/rtsim" --scenes interior,hairball --res 96x54 --jobs 2 --out "$tmp/acc"
     --accuracy 40% --no-charts --set sched.pixel_order=scanline)
"${acc[@]}" >"$tmp/acc.log" 2>&1; rc=$?
check paper_tables_accuracy_runs test "$rc" -eq 0
check_accuracy() {
  python3 - "$tmp/acc" <<'PY'
import csv, glob, json, os, sys
out = sys.argv[1]
levels = {}
for f in glob.glob(os.path.join(out, "runs", "*.json")):
    d = json.load(open(f))
    levels[os.path.basename(f).split("_")[0]] = levels.get(os.path.basename(f).split("_")[0], set()) | {d["fidelity"]}
assert "full" in levels["interior"], levels            # Table 1's scene, run again at full
assert levels["hairball"] & {"functional", "sampled"}, levels  # --accuracy 40% picks a cheap level somewhere
t1 = open(os.path.join(out, "table1.md")).read()
assert "(ours, full;" in t1, t1[:300]
md = open(os.path.join(out, "table2.md")).read()
line = [l for l in md.splitlines() if l.startswith("With --accuracy 40%: ")]
assert line and line[0].endswith("(Table 1's scene at full fidelity where the level picked does not report each "
                                 "unit's power).") and \
    any("runs %s" % lv in line[0] for lv in levels["hairball"] - {"full"}), md[-300:]
assert sum(int(w) for w in line[0].split(":")[1].split() if w.isdigit()) == 8, line
t2 = [r for r in csv.DictReader(open(os.path.join(out, "table2.csv"))) if r["scene"] == "hairball" and r["figure"] == "MRPS/mm2"]
assert len(t2) == 2 and all(float(r["ours_mbvh4"]) > 0 for r in t2), t2
PY
}
check paper_tables_accuracy_levels check_accuracy
