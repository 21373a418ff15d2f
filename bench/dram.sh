#!/usr/bin/env bash
# DRAM model speed: requests simulated per host second by the standalone driver
# rtdram on the reference traces (issue 4, "make bench").
#   bash bench/dram.sh [BUILD_DIR]        (RUNS=5 runs per trace by default)
# Traces: a_seq and b_rand64 of ../shared/ref/dram/gen_traces.py, config A
# (il32: 2,000,000 requests of 32 B each), generated into BUILD_DIR/bench/traces
# (never committed). Skips with a message when ../shared/ref/dram is absent.
# Ours: wall time of the whole `rtdram TRACE --json` process (parsing included),
# pinned to one core with taskset when available; median of RUNS runs.
# Reference: Ramulator v1 is not installable here, so its time is DERIVED from the
# throughput the issue states for this machine (bench/dram_reference.csv):
# reference_median_s = requests / stated requests_per_s -- not measured here.
# Writes BUILD_DIR/bench/dram.csv: benchmark,ours_median_s,reference_median_s,ratio
# (ratio = reference/ours, > 1 means faster than the reference).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
runs=${RUNS:-5}
bin=$build/bin/rtdram
if [ ! -x "$bin" ]; then make -s BUILD="$build" "$bin" >&2; fi
if ! ref=$(python3 scripts/dram_compare.py --find-ref 2>/dev/null); then
  echo "dram bench: ../shared/ref/dram absent (set RTSIM_REF_DRAM); nothing to measure"
  exit 0
fi
pin=()
if command -v taskset >/dev/null 2>&1 && taskset -c 0 true 2>/dev/null; then pin=(taskset -c 0); fi
mkdir -p "$build/bench/traces"
python3 - "$ref" "$build" "$bin" "$runs" "${pin[@]}" <<'EOF'
import csv, importlib.util, json, os, statistics, subprocess, sys, time

ref, build, rtdram, runs = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
pin = sys.argv[5:]
if runs < 1:
    sys.exit("dram bench: RUNS must be >= 1")
stated = {}
with open("bench/dram_reference.csv", newline="") as f:
    for row in csv.DictReader(l for l in f if not l.startswith("#")):
        stated[row["trace"]] = float(row["requests_per_s"])

spec = importlib.util.spec_from_file_location("gen_traces", os.path.join(ref, "gen_traces.py"))
gen = importlib.util.module_from_spec(spec)
spec.loader.exec_module(gen)
rows = []
for name in stated:
    logical, mode = name.split(".")
    path = os.path.join(build, "bench", "traces", name + ".trace")
    if not os.path.exists(path):
        print("generating %s with %s" % (path, os.path.join(ref, "gen_traces.py")), flush=True)
        gen.emit(logical, mode, path + ".tmp")
        os.replace(path + ".tmp", path)
    with open(path, "rb") as f:
        requests = sum(1 for _ in f)
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        p = subprocess.run(pin + [rtdram, path, "--json"], capture_output=True, text=True)
        times.append(time.perf_counter() - t0)
        if p.returncode != 0:
            sys.exit("dram bench: %s failed on %s: %s" % (rtdram, path, p.stderr.strip()))
        o = json.loads(p.stdout)
        served = o["n_rd"] + o["n_wr"] + o["reads_forwarded"]
        if served != requests:
            sys.exit("dram bench: %s served %d of %d requests" % (path, served, requests))
    ours = statistics.median(times)
    reference = requests / stated[name]
    rows.append((name, requests, ours, reference))

print("DRAM model speed: rtdram on the reference traces, median of %d runs%s" %
      (runs, ", pinned to core 0" if pin else ""))
print("reference time derived from the issue's stated Ramulator throughput, not measured here")
hdr = "%-16s %10s %12s %14s %16s %8s" % ("benchmark", "requests", "ours (s)", "ours (M req/s)",
                                        "Ramulator (M/s)", "ratio")
print(hdr)
print("-" * len(hdr))
out = os.path.join(build, "bench", "dram.csv")
with open(out + ".tmp", "w") as f:
    f.write("benchmark,ours_median_s,reference_median_s,ratio\n")
    for name, n, ours, reference in rows:
        ratio = reference / ours
        print("%-16s %10d %12.3f %14.2f %16.2f %7.1fx" % (name, n, ours, n / ours / 1e6, n / reference / 1e6, ratio))
        f.write("dram_%s,%.4f,%.4f,%.2f\n" % (name.replace(".", "_"), ours, reference, ratio))
os.replace(out + ".tmp", out)
print("-" * len(hdr))
print("wrote %s (target: ratio >= 10 on both traces)" % out)
EOF
