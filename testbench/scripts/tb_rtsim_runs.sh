#!/usr/bin/env bash
# tb_rtsim_runs — scripts/rtsim_runs.py, the experiment scripts' one runner of
# rtsim points: the change in percent is undefined (None, written "n/a" or
# empty) when the old value is 0, never 0 or nan; the figures of merit of a
# run's JSON (DRAM bytes in MB, MRPS/mm2 from the machine's area when a
# cheaper level does not report it, absent ones left out); a sweep point's
# name is independent of the order of its overrides and keeps only
# [A-Za-z0-9._-]; rtsim's command line of a point. No rtsim run: pure Python.
set -u
cd "$(dirname "$0")/../.."
python3 - <<'PY'
import math
import sys

sys.path.insert(0, "scripts")
import rtsim_runs as R


def check(name, ok, why=""):
    print("PASS %s" % name if ok else "FAIL %s: %s" % (name, why))


c = R.change_pct(5.0, 0.0)
check("runs_change_from_zero_undefined", c is None, repr(c))
check("runs_change_zero_to_zero_undefined", R.change_pct(0.0, 0) is None)
check("runs_change_from_zero_written_na", R.fmt_change(R.change_pct(1, 0), "%+.0f%%") == "n/a")
check("runs_change_from_zero_csv_empty", R.fmt_change(R.change_pct(1, 0), "%.2f", "") == "")
check("runs_change_defined", R.change_pct(3.0, 2.0) == 50.0 and R.change_pct(1.0, 2.0) == -50.0)
check("runs_change_to_zero", R.change_pct(0.0, 4.0) == -100.0)
check("runs_change_formatted", R.fmt_change(R.change_pct(3.0, 2.0), "%+.0f%%") == "+50%")
check("runs_change_not_nan", all(v is None or not math.isnan(v) for v in
                                 (R.change_pct(a, b) for a in (0.0, 1.0) for b in (0.0, 1.0))))

run = {"mrps": 100.0, "energy_mj": 2.0, "mrps_per_mm2": 10.0, "dram_bytes": 3e6, "area_mm2": 10.0}
f = R.fom(run)
check("runs_fom_all", f == {"mrps": 100.0, "energy_mj": 2.0, "mrps_per_mm2": 10.0, "dram_mb": 3.0,
                            "area_mm2": 10.0}, repr(f))
f = R.fom({"mrps": 100.0, "energy_mj": 2.0, "dram_bytes": 0}, area_mm2=4.0)
check("runs_fom_area_fallback", f.get("mrps_per_mm2") == 25.0 and f.get("dram_mb") == 0.0 and "area_mm2" not in f,
      repr(f))

a = R.sweep_point_name("interior", "primary", "mbvh4", "32x18", "-", ["trv.count=2", "node_l1.size=4096"])
b = R.sweep_point_name("interior", "primary", "mbvh4", "32x18", "-", ["node_l1.size=4096", "trv.count=2"])
check("runs_sweep_name_order_free", a == b, "%s != %s" % (a, b))
n = R.sweep_point_name("/a b/ünï.obj.gz", "diffuse", "x y/é.ini", "8x4", "-", [])
check("runs_sweep_name_safe", n.startswith("__n__-diffuse-__-") and len(n) == len("__n__-diffuse-__-") + 12, n)
argv = R.rtsim_argv("rtsim", "city", "diffuse", "bvh2", "8x4", ["trv.count=2"], ["--bounces", "1"], "p.json")
check("runs_rtsim_argv", argv == ["rtsim", "city", "--rays", "diffuse", "--machine", "bvh2", "--res", "8x4",
                                  "--set", "trv.count=2", "--bounces", "1", "--quiet", "--json", "p.json"],
      repr(argv))
PY
