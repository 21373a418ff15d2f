#!/usr/bin/env bash
# tb_fuzz_replay — every input of testbench/fuzz/corpus/<harness>/ (seeds and
# the inputs fuzzing found, see testbench/fuzz/fuzz.h) through its harness in
# this build (under make test's ASan/UBSan build: any memory error, undefined
# behaviour or leak fails the case). A file named bad-* must be rejected with a
# message, any other one accepted; the machine and DRAM spec harnesses also
# take the project's own presets (model/data), which must be accepted.
set -u
cd "$(dirname "$0")/../.."
. testbench/cli_lib.sh
fz=${RTSIM_BIN:?}/../fuzz
[ -d "$fz" ] || { echo "FAIL fuzz_replay: $fz missing (make builds the harnesses)"; exit 0; }
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0

replay() { # harness file
  local h=$1 f=$2 out rc want=accepted
  case $(basename "$f") in bad-*) want=rejected ;; esac
  out=$("$fz/$h" -v "$f" 2>&1); rc=$?
  if [ $rc -ne 0 ]; then fail "$h:$(basename "$f")" "exit $rc: $(echo "$out" | tail -3 | tr '\n' ' ')"
  elif ! echo "$out" | grep -q "^$want "; then fail "$h:$(basename "$f")" "expected $want, got: $(echo "$out" | head -2 | tr '\n' ' ')"
  elif [ "$(echo "$out" | wc -l)" -ne 1 ]; then fail "$h:$(basename "$f")" "sanitizer or other output: $(echo "$out" | head -3 | tr '\n' ' ')"
  else pass "$h:$(basename "$f")"; fi
}

for dir in testbench/fuzz/corpus/*/; do
  h=$(basename "$dir")
  [ -x "$fz/$h" ] || { fail "$h" "harness $fz/$h not built"; continue; }
  for f in "$dir"*; do [ -f "$f" ] && replay "$h" "$f"; done
done
for f in model/data/lpddr3_1600.ini; do replay fuzz_dram_spec "$f"; done
for f in model/data/machines/*.ini; do replay fuzz_machine "$f"; done
