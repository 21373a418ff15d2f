#!/usr/bin/env bash
# Runs every testbench of every given build directory and counts the cases.
#   testbench/run.sh BUILD_DIR [BUILD_DIR...]
# Programs: BUILD_DIR/testbench/tb_*; scripts: every tb_*.sh below testbench/
# (the folders mirror the source tree; they get
# RTSIM_BIN=BUILD_DIR/bin and RTSIM_TMP, a scratch folder). Each case prints
# PASS/FAIL/SKIP (see tb.h). Ends with the line "N passed, N failed, N skipped".
# Set TB_FILTER=regex to run only matching programs. Before the count it
# names the slowest programs (wall seconds), to keep the suite short.
# The build directories run at once, up to TB_JOBS of them (default: the
# CPUs this shell may use); each program's lines are printed together when
# it ends, prefixed with its build's variant ([release], [asan], ...).
set -u
cd "$(dirname "$0")/.."
per_program_timeout=${TB_TIMEOUT:-900}
state=$(mktemp -d)
trap 'rm -rf "$state"' EXIT

# One program: its lines to stdout under the lock, its counts, time and
# name (when it failed) appended to the variant's state files.
run_one() { # variant, label, command...
  local variant=$1 label=$2; shift 2
  local out=$state/$variant.out rc
  local t0=$SECONDS
  timeout "$per_program_timeout" "$@" >"$out" 2>"$out.err"
  rc=$?
  echo "$((SECONDS - t0)) $variant:$label" >> "$state/$variant.durations"
  local p f s
  p=$(grep -c '^PASS ' "$out"); f=$(grep -c '^FAIL ' "$out"); s=$(grep -c '^SKIP ' "$out")
  {
    sed -e "s|^|[$variant] |" "$out"
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then
      echo "[$variant] FAIL $label: exited with status $rc without reporting a failed case"
      f=1
    fi
    if [ "$f" -gt 0 ] || [ "$rc" -ne 0 ]; then
      echo "[$variant] --- stderr of $label (last 30 lines) ---"
      tail -n 30 "$out.err" | sed -e "s|^|[$variant]   |"
      echo "$variant:$label" >> "$state/$variant.failed"
    fi
  } > "$out.block"
  # one program's block at a time, whichever variant ends first
  flock "$state/print.lock" cat "$out.block"
  echo "$p $f $s" >> "$state/$variant.counts"
  rm -f "$out" "$out.err" "$out.block"
}

run_build() { # build directory
  local build=$1 variant t name
  variant=$(basename "$build")
  [ "$build" = build ] && variant=release
  # The scratch folder sits under a long path with spaces, a single quote and
  # a non-ASCII letter, as a user's checkout may: a test or tool that cuts a
  # path to a fixed width, splits it at a space or pastes it into quoted
  # text fails here, wherever the checkout is.
  local deep="scratch with spaces/O'Brien's Jääskeläinen tmp/a folder name long enough that every path under it/is over 120 characters long"
  export RTSIM_BIN="$PWD/$build/bin" RTSIM_TMP="$PWD/$build/tmp/$deep/tb"
  if [ ${#RTSIM_TMP} -lt 120 ]; then echo "run.sh: RTSIM_TMP shorter than 120 characters: $RTSIM_TMP" >&2; return 1; fi
  rm -rf "$RTSIM_TMP"; mkdir -p "$RTSIM_TMP"
  if [ "$variant" != release ]; then export RTSIM_TB_SANITIZED=1; else unset RTSIM_TB_SANITIZED; fi
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 UBSAN_OPTIONS=print_stacktrace=1
  for t in "$build"/testbench/tb_*; do
    [ -x "$t" ] || continue
    name=$(basename "$t")
    [[ -n "${TB_FILTER:-}" && ! "$name" =~ $TB_FILTER ]] && continue
    run_one "$variant" "$name" "$t"
  done
  while IFS= read -r t; do
    [ -f "$t" ] || continue
    name=$(basename "$t")
    [[ -n "${TB_FILTER:-}" && ! "$name" =~ $TB_FILTER ]] && continue
    run_one "$variant" "$name" bash "$t"
  done < <(find testbench -name 'tb_*.sh' -type f | LC_ALL=C sort)
}

jobs=${TB_JOBS:-$(nproc 2>/dev/null || echo 1)}
case $jobs in '' | *[!0-9]* | 0) echo "run.sh: TB_JOBS must be a whole number >= 1, not '$jobs'" >&2; exit 2 ;; esac
pids=()
status=0
for build in "$@"; do
  if [ "$jobs" -gt 1 ]; then
    while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n; done
    ( run_build "$build" ) &
    pids+=($!)
  else
    ( run_build "$build" ) || status=1
  fi
done
for p in "${pids[@]}"; do wait "$p" || status=1; done
[ "$status" -eq 0 ] || exit 2

read -r pass fail skip < <(cat "$state"/*.counts 2>/dev/null | awk '{ p += $1; f += $2; s += $3 } END { print p + 0, f + 0, s + 0 }')
slowest=$(cat "$state"/*.durations 2>/dev/null | sort -rn | head -8 | awk '{ printf "%s%s %ss", (NR > 1 ? ", " : ""), $2, $1 }')
echo "slowest programs: $slowest"
failed=$(cat "$state"/*.failed 2>/dev/null | tr '\n' ' ')
if [ -n "$failed" ]; then echo "failed programs: ${failed% }"; fi
echo "$pass passed, $fail failed, $skip skipped"
[ "$fail" -eq 0 ]
