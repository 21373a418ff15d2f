#!/usr/bin/env bash
# fuzz.sh — fuzzes rtsim's input parsers with AFL++ (harnesses: testbench/fuzz/fuzz.h).
#   scripts/fuzz.sh AFL_BUILD_DIR SECONDS HARNESS...      (make fuzz runs it)
# Arguments:
#   AFL_BUILD_DIR  the build made with afl-cc (build/afl) holding fuzz/<harness>
#   SECONDS        how long each harness runs
#   HARNESS...     harness names (fuzz_<name>: testbench/fuzz/fuzz_<name>.c)
#   -h, --help     this text
# Each harness starts from testbench/fuzz/corpus/<harness>/ (plus the
# project's own data files it reads: model/data/*.ini for the DRAM spec, the
# machine presets for the machine harness, scenes/*.scene for the scene one)
# and runs SECONDS; the INI harnesses get a dictionary of the seeds' sections
# and keys. Findings land in
# AFL_BUILD_DIR/findings/<harness>/default/{crashes,hangs}; the summary lists
# their counts, and the script exits 1 when any harness crashed. A crash input
# that is fixed belongs in corpus/<harness>/ so make test replays it.
set -euo pipefail
case ${1:-} in -h|--help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 0 ;; esac
cd "$(dirname "$0")/.."
[ $# -ge 3 ] || { echo "usage: scripts/fuzz.sh AFL_BUILD_DIR SECONDS HARNESS..." >&2; exit 2; }
build=$1 seconds=$2; shift 2
case $seconds in ''|*[!0-9]*) echo "fuzz: SECONDS must be a whole number of seconds, got '$seconds'" >&2; exit 2;; esac
command -v afl-fuzz >/dev/null || { echo "fuzz: afl-fuzz missing: apt-get install -y afl++" >&2; exit 2; }
export AFL_SKIP_CPUFREQ=1 AFL_NO_UI=1 AFL_I_DONT_CARE_ABOUT_MISSING_CRASHES=1
# ASan aborts so AFL sees the crash. Leak checks cost ~40 ms a run, so they are
# left to the replay in make test (tb_fuzz_replay.sh, ASan build, leaks on).
export ASAN_OPTIONS=abort_on_error=1:symbolize=0:detect_leaks=0 UBSAN_OPTIONS=halt_on_error=1:abort_on_error=1
crashed=0
summary=()
for h in "$@"; do
  bin=$build/fuzz/$h
  [ -x "$bin" ] || { echo "fuzz: $bin not built (make fuzz-build)" >&2; exit 2; }
  seeds=$build/seeds/$h
  rm -rf "$seeds" && mkdir -p "$seeds"
  cp testbench/fuzz/corpus/"$h"/* "$seeds"/ 2>/dev/null || true
  case $h in
    fuzz_dram_spec) cp model/data/*.ini "$seeds"/ ;;
    fuzz_machine) cp model/data/machines/*.ini "$seeds"/ ;;
    fuzz_scene) cp scenes/*.scene "$seeds"/ ;;
  esac
  # INI harnesses: a dictionary of the sections and keys the seeds use, so
  # mutations combine real keys instead of guessing their spelling
  dict=()
  case $h in
    fuzz_dram_spec|fuzz_machine)
      sed -n -e 's/^[[:space:]]*\(\[[A-Za-z0-9_]*\]\).*/"\1"/p' -e 's/^[[:space:]]*\([A-Za-z0-9_.]*\)[[:space:]]*=.*/"\1="/p' \
        "$seeds"/* | sort -u >"$build/seeds/$h.dict"
      dict=(-x "$build/seeds/$h.dict") ;;
  esac
  out=$build/findings/$h
  rm -rf "$out" && mkdir -p "$(dirname "$out")"
  echo "fuzz: $h for ${seconds}s" >&2
  afl-fuzz -i "$seeds" -o "$out" ${dict[@]+"${dict[@]}"} -V "$seconds" -t 2000 -m none -- "$bin" >"$build/findings-$h.log" 2>&1 || {
    echo "fuzz: afl-fuzz failed for $h; last lines of $build/findings-$h.log:" >&2
    tail -n 15 "$build/findings-$h.log" >&2
    exit 1
  }
  st=$out/default/fuzzer_stats
  execs=$(awk -F: '/^execs_done/ { gsub(/ /, "", $2); print $2 }' "$st")
  paths=$(awk -F: '/^corpus_count/ { gsub(/ /, "", $2); print $2 }' "$st")
  nc=$(find "$out/default/crashes" -type f -name 'id:*' | wc -l)
  nh=$(find "$out/default/hangs" -type f -name 'id:*' | wc -l)
  summary+=("$(printf '%-18s %10s execs %6s inputs %4s crashes %4s hangs' "$h" "$execs" "$paths" "$nc" "$nh")")
  [ "$nc" -eq 0 ] || crashed=1
done
printf '%s\n' "${summary[@]}"
exit $crashed
