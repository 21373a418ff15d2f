#!/usr/bin/env bash
# DRAM model speed: requests simulated per host second by the standalone driver
# rtdram on the reference traces ("make bench", docs/dram.md).
#   bash bench/dram.sh [BUILD_DIR]        (RUNS=5 runs per trace by default)
# Traces: a_seq and b_rand64 of ../shared/ref/dram/gen_traces.py, config A
# (il32: 2,000,000 requests of 32 B each), generated into BUILD_DIR/bench/traces
# (never committed). Skips with a message when ../shared/ref/dram is absent.
# Ours: CPU time (user + sys) of the whole single-threaded `rtdram TRACE --json`
# process (trace parsing included), median of RUNS runs. CPU time rather than wall
# time because the 2-core machine is shared by several builds and benches: on an
# idle machine the two agree; under contention wall time measures the neighbours.
# The wall-time median is printed as well.
# Reference: Ramulator v1 is not installable here, so its time is DERIVED from the
# throughput given with the DRAM model's requirements for this machine (bench/dram_reference.csv):
# reference_median_s = requests / stated requests_per_s -- not measured here.
# Writes BUILD_DIR/bench/dram.csv: benchmark,ours_median_s,reference_median_s,ratio
# (ratio = reference/ours, > 1 means faster than the reference). The kernel-module
# path (rtdram --kernel) is timed too and printed for information only.
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
mkdir -p "$build/bench/traces"
python3 - "$ref" "$build" "$bin" "$runs" <<'EOF'
import csv, importlib.util, json, os, resource, statistics, subprocess, sys, time

ref, build, rtdram, runs = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
if runs < 1:
    sys.exit("dram bench: RUNS must be >= 1")
stated = {}
with open("bench/dram_reference.csv", newline="") as f:
    for row in csv.DictReader(l for l in f if not l.startswith("#")):
        stated[row["trace"]] = float(row["requests_per_s"])

spec = importlib.util.spec_from_file_location("gen_traces", os.path.join(ref, "gen_traces.py"))
gen = importlib.util.module_from_spec(spec)
spec.loader.exec_module(gen)
def measure(cmd, requests, runs):
    """Medians of the child's CPU time and of the wall time over `runs` runs."""
    cpu, wall = [], []
    for _ in range(runs):
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        p = subprocess.run(cmd, capture_output=True, text=True)
        wall.append(time.perf_counter() - t0)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu.append((r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime))
        if p.returncode != 0:
            sys.exit("dram bench: %s failed: %s" % (" ".join(cmd), p.stderr.strip()))
        o = json.loads(p.stdout)
        served = o["n_rd"] + o["n_wr"] + o["reads_forwarded"]
        if served != requests:
            sys.exit("dram bench: %s served %d of %d requests" % (" ".join(cmd), served, requests))
    return statistics.median(cpu), statistics.median(wall)


rows, kernel_rows = [], []
for name in stated:
    logical, mode = name.split(".")
    path = os.path.join(build, "bench", "traces", name + ".trace")
    if not os.path.exists(path):
        print("generating %s with %s" % (path, os.path.join(ref, "gen_traces.py")), flush=True)
        gen.emit(logical, mode, path + ".tmp")
        os.replace(path + ".tmp", path)
    with open(path, "rb") as f:
        requests = sum(1 for _ in f)
    reference = requests / stated[name]
    cpu, wall = measure([rtdram, path, "--json"], requests, runs)
    rows.append((name, requests, cpu, wall, reference))
    cpu, wall = measure([rtdram, path, "--json", "--kernel"], requests, runs)
    kernel_rows.append((name, requests, cpu, wall, reference))

print("DRAM model speed: rtdram (single-threaded) on the reference traces, median of %d runs" % runs)
print("ours = CPU time (user+sys) of the process; wall time shown for information")
print("reference time derived from the Ramulator throughput in bench/dram_reference.csv, not measured here")
hdr = "%-16s %10s %12s %10s %14s %16s %8s" % ("benchmark", "requests", "ours CPU (s)", "wall (s)",
                                              "ours (M req/s)", "Ramulator (M/s)", "ratio")
print(hdr)
print("-" * len(hdr))
out = os.path.join(build, "bench", "dram.csv")
with open(out + ".tmp", "w") as f:
    f.write("benchmark,ours_median_s,reference_median_s,ratio\n")
    for name, n, ours, wall_s, reference in rows:
        ratio = reference / ours
        print("%-16s %10d %12.3f %10.3f %14.2f %16.2f %7.1fx" % (name, n, ours, wall_s, n / ours / 1e6,
                                                                n / reference / 1e6, ratio))
        f.write("dram_%s,%.4f,%.4f,%.2f\n" % (name.replace(".", "_"), ours, reference, ratio))
os.replace(out + ".tmp", out)
print("-" * len(hdr))
print("wrote %s (target: ratio >= 10 on both traces)" % out)
print("for information, not in the CSV: the same traces through the kernel module (rtdram --kernel:")
print("request/response FIFOs, DRAM clock, producer and consumer processes; identical results)")
for name, n, ours, wall_s, reference in kernel_rows:
    print("%-16s %10d %12.3f %10.3f %14.2f %16.2f %7.1fx" % (name + "+k", n, ours, wall_s, n / ours / 1e6,
                                                            n / reference / 1e6, reference / ours))
EOF
