#!/usr/bin/env python3
"""Compare rtdram with the reference DRAM results (Ramulator v1 timing, DRAMPower 4.1 energy).

  scripts/dram_compare.py [--ref DIR] [--traces DIR] [--rtdram BIN] [--config A] [--json FILE]

Generates the reference traces with the reference generator
(python3 REF/gen_traces.py TRACES, only if they are missing; traces land in build/,
never in the repository), runs `rtdram --json --check` on the five traces of config
A (A_x32_2ch_il32: 2 x 32-bit channels, 32 B per request) and compares with
REF/ramulator_results.csv and REF/drampower_results.csv:

  total time within 3 %, row-hit rate within 2 points, every command count within
  3 %, total energy within 5 %, zero timing-checker violations.

Prints a table and exits 1 when any figure is out of tolerance, 2 on bad usage or
missing inputs. Python 3 standard library only.
"""
import argparse
import csv
import json
import os
import subprocess
import signal
import sys
import time

# a reader that stops early (`| head`) ends this quietly, as it does a C tool
signal.signal(signal.SIGPIPE, signal.SIG_DFL)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TRACES = ["a_seq", "b_rand64", "c_rand128", "d_mix7030", "e_rowloc"]
# config -> (trace suffix, extra rtdram arguments). B differs from A only in its traces
# (address bits 5/6 swapped by gen_traces.py), so the same model configuration applies.
CONFIGS = {"A_x32_2ch_il32": ("il32", []), "B_x32_2ch_il64": ("il64", [])}
TOL_TIME = 0.03
TOL_HIT_POINTS = 0.02
TOL_CMD = 0.03
TOL_ENERGY = 0.05
# (our JSON key, reference CSV column)
COMMANDS = [("n_act", "ACT"), ("n_pre", "PRE"), ("n_prea", "PREA"), ("n_ref", "REF"), ("n_rd", "RD"), ("n_wr", "WR")]


def rel(ours, ref):
    if ref == 0:
        return 0.0 if ours == 0 else float("inf")
    return (ours - ref) / ref


def default_ref():
    """../shared/ref/dram beside the repository root; in a git worktree, beside the main
    checkout (git's common dir); RTSIM_REF_DRAM overrides."""
    cands = []
    if os.environ.get("RTSIM_REF_DRAM"):
        cands.append(os.environ["RTSIM_REF_DRAM"])
    cands.append(os.path.join(ROOT, "..", "shared", "ref", "dram"))
    try:
        common = subprocess.run(["git", "-C", ROOT, "rev-parse", "--path-format=absolute", "--git-common-dir"],
                                capture_output=True, text=True, check=True).stdout.strip()
        cands.append(os.path.join(os.path.dirname(common), "..", "shared", "ref", "dram"))
    except (OSError, subprocess.CalledProcessError):
        pass
    for c in cands:
        if os.path.exists(os.path.join(c, "ramulator_results.csv")):
            return os.path.normpath(c)
    return None


def load_csv(path, key_cols):
    with open(path, newline="") as f:
        return {tuple(r[k] for k in key_cols): r for r in csv.DictReader(f)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ref", default=None, help="reference folder (default: ../shared/ref/dram, see default_ref)")
    ap.add_argument("--find-ref", action="store_true", help="print the reference folder and exit (3 if absent)")
    ap.add_argument("--traces", default=os.path.join(ROOT, "build", "traces"),
                    help="folder of the request traces, made when missing (default build/traces)")
    ap.add_argument("--rtdram", default=os.path.join(ROOT, "build", "bin", "rtdram"),
                    help="the rtdram binary (default build/bin/rtdram)")
    ap.add_argument("--config", default="A_x32_2ch_il32", choices=sorted(CONFIGS),
                    help="the reference configuration to compare with (default %(default)s)")
    ap.add_argument("--generate-only", action="store_true", help="only make sure the traces exist, print their folder")
    ap.add_argument("--json", help="also write the comparison rows as JSON to this file")
    a = ap.parse_args()
    if a.ref is None:
        a.ref = default_ref()
    if a.find_ref:
        if a.ref is None:
            return 3
        print(a.ref)
        return 0
    if a.ref is None:
        print("dram_compare: reference folder ../shared/ref/dram not found (set RTSIM_REF_DRAM)", file=sys.stderr)
        return 2

    ram_csv = os.path.join(a.ref, "ramulator_results.csv")
    dp_csv = os.path.join(a.ref, "drampower_results.csv")
    for p in (ram_csv, dp_csv, os.path.join(a.ref, "gen_traces.py")) + (() if a.generate_only else (a.rtdram,)):
        if not os.path.exists(p):
            print("dram_compare: missing %s" % p, file=sys.stderr)
            return 2
    mode, extra = CONFIGS[a.config]
    need = [os.path.join(a.traces, "%s.%s.trace" % (t, mode)) for t in TRACES]
    if not all(os.path.exists(p) for p in need):
        os.makedirs(a.traces, exist_ok=True)
        print("generating traces: python3 %s %s" % (os.path.join(a.ref, "gen_traces.py"), a.traces), flush=True)
        subprocess.run([sys.executable, os.path.join(a.ref, "gen_traces.py"), a.traces], check=True,
                       stdout=subprocess.DEVNULL)
    if a.generate_only:
        print(os.path.abspath(a.traces))
        return 0
    ram = load_csv(ram_csv, ["config", "trace"])
    dp = load_csv(dp_csv, ["config", "trace", "channel"])

    rows, ok = [], True
    print("rtdram vs reference (Ramulator v1 time/row hits/commands, DRAMPower 4.1 energy), config %s" % a.config)
    hdr = "%-10s %-9s %14s %14s %9s %6s" % ("trace", "figure", "ours", "reference", "error", "ok")
    print(hdr)
    print("-" * len(hdr))
    for t, path in zip(TRACES, need):
        r = ram.get((a.config, t))
        e = dp.get((a.config, t, "ALL"))
        if r is None or e is None:
            print("dram_compare: no reference row for %s %s" % (a.config, t), file=sys.stderr)
            return 2
        t0 = time.time()
        p = subprocess.run([a.rtdram, path, "--json", "--check"] + extra, capture_output=True, text=True)
        host = time.time() - t0
        if p.returncode not in (0, 1):
            print("dram_compare: rtdram failed on %s: %s" % (path, p.stderr.strip()), file=sys.stderr)
            return 2
        o = json.loads(p.stdout)
        violations = 0 if p.returncode == 0 else sum(1 for l in p.stderr.splitlines() if l.startswith("violation"))
        checks = []
        ref_time = float(r["time_ns"])
        checks.append(("time_ns", o["time_ns"], ref_time, rel(o["time_ns"], ref_time), TOL_TIME, "%"))
        ref_hit = float(r["row_hit_rate"])
        checks.append(("row_hit", o["row_hit_rate"], ref_hit, o["row_hit_rate"] - ref_hit, TOL_HIT_POINTS, "pt"))
        for ours_key, col in COMMANDS:
            ref_n = float(r[col])
            checks.append((col, o[ours_key], ref_n, rel(o[ours_key], ref_n), TOL_CMD, "%"))
        ref_e = float(e["E_total_pJ"]) / 1e6
        checks.append(("energy_uJ", o["energy_uJ"], ref_e, rel(o["energy_uJ"], ref_e), TOL_ENERGY, "%"))
        ref_lat = float(r["read_lat_avg_cyc"])
        lat_err = rel(o["read_lat_avg_cycles"], ref_lat)
        def num(name, v):
            if name == "time_ns":
                return "%14.1f" % v
            if name == "row_hit":
                return "%14.5f" % v
            if name == "energy_uJ":
                return "%14.2f" % v
            return "%14d" % int(v)

        for name, ours, ref, err, tol, unit in checks:
            good = abs(err) <= tol
            ok &= good
            shown = "%+8.3f%%" % (100 * err) if unit == "%" else "%+7.4fpt" % err
            if err == float("inf"):
                shown = "     inf"
            print("%-10s %-9s %s %s %9s %6s" % (t, name, num(name, ours), num(name, ref), shown,
                                              "yes" if good else "NO"))
            rows.append({"trace": t, "figure": name, "ours": ours, "reference": ref, "error": err,
                         "tolerance": tol, "ok": good})
        print("%-10s %-9s %14.2f %14.2f %+8.3f%% %6s" % (t, "read_lat", o["read_lat_avg_cycles"], ref_lat,
                                                        100 * lat_err, "info"))
        print("%-10s %-9s %14d %14s %9s %6s" % (t, "violation", violations, "0", "", "yes" if violations == 0 else "NO"))
        print("%-10s host %.2f s" % (t, host))
        ok &= violations == 0
        rows.append({"trace": t, "figure": "timing_violations", "ours": violations, "reference": 0,
                     "ok": violations == 0})
    print("-" * len(hdr))
    print("tolerances: time %.0f%%, row-hit %.0f points, commands %.0f%%, energy %.0f%%; read latency informative" %
          (100 * TOL_TIME, 100 * TOL_HIT_POINTS, 100 * TOL_CMD, 100 * TOL_ENERGY))
    print("RESULT: %s" % ("all within tolerance" if ok else "OUT OF TOLERANCE"))
    if a.json:
        tmp = a.json + ".tmp"
        with open(tmp, "w") as f:
            json.dump(rows, f, indent=1)
        os.replace(tmp, a.json)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
