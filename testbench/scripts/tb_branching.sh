#!/usr/bin/env bash
# tb_branching — scripts/branching on a tiny case (interior, 8x8, primary
# rays, widths 3 and 4): a CSV row per width and organisation (1 bank, 2
# banks, index) with the figures of each point's JSON; at N = 4 the three
# organisations are the same machine (a 128 B node is one line), so their
# figures are equal; the Markdown table and the comparison against N = 4;
# both charts; bad arguments refused with exit 2.
set -u
tmp=${RTSIM_TMP:-/tmp}/tb_branching
rm -rf "$tmp"; mkdir -p "$tmp"
cd "$(dirname "$0")/../.."
. testbench/cli_lib.sh
if [ -n "${RTSIM_TB_SANITIZED:-}" ]; then
  echo "SKIP branching: 6 model runs; the release build covers the script"; exit 0
fi
if ! command -v gnuplot >/dev/null; then
  echo "SKIP branching: gnuplot is not installed (scripts/debian-packages.txt lists it)"; exit 0
fi
scripts/branching --bin "${RTSIM_BIN:?}/rtsim" --scenes interior --rays primary --res 8x8 --widths 3,4 --jobs 2 \
  --out "$tmp/out" >"$tmp/log" 2>&1
check branching_runs test $? -eq 0
check branching_csv python3 - "$tmp/out" <<'PY'
import csv, glob, json, sys
rows = list(csv.DictReader(open(sys.argv[1] + "/branching.csv")))
assert len(rows) == 6, rows
assert sorted((r["organisation"], r["branching"]) for r in rows) == sorted(
    (o, w) for o in ("1bank", "2bank", "index") for w in ("3", "4"))
runs = [json.load(open(p)) for p in glob.glob(sys.argv[1] + "/runs/*.json")]
assert len(runs) == 6
for r in rows:
    n = int(r["branching"])
    def org(cl):
        return "index" if "node_l1.addressing=index" in cl else "2bank" if "node_l1.banks=2" in cl else "1bank"
    d = [x for x in runs if "machine.branching=%d" % n in x["run"]["command_line"]
         and org(x["run"]["command_line"]) == r["organisation"]]
    assert len(d) == 1, (r, len(d))
    assert float(r["mrps_per_mm2"]) == float("%.6g" % d[0]["mrps_per_mm2"]), (r, d[0]["mrps_per_mm2"])
four = [r for r in rows if r["branching"] == "4"]
assert all(r["mrps"] == four[0]["mrps"] and r["area_mm2"] == four[0]["area_mm2"] for r in four), four
three = {r["organisation"]: r for r in rows if r["branching"] == "3"}
assert three["index"]["area_mm2"] != three["1bank"]["area_mm2"]  # 96 B node words: another L1 and FIFO width
PY
check branching_md_table grep -q '^| \*\*4\*\* | ' "$tmp/out/branching.md"
check branching_md_against_4 grep -q '^| 3 | index | ' "$tmp/out/branching.md"
check branching_charts sh -c 'head -c 8 "$1/out/branching-mrps-per-mm2.png" | grep -q PNG && test -s "$1/out/branching-energy.svg"' _ "$tmp"
expect branching_bad_widths 2 "4 among them" -- scripts/branching --bin "$RTSIM_BIN/rtsim" --widths 3,5
expect branching_bad_rays 2 "allowed primary, diffuse" -- scripts/branching --bin "$RTSIM_BIN/rtsim" --rays shadow
