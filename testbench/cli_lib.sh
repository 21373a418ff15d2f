# cli_lib.sh — shell helpers shared by the command-line testbenches
# (tb_*_cli.sh source it; it is not a test itself, so it has no tb_ prefix).
# Every case prints one line of testbench/tb.h's protocol: PASS/FAIL.

pass() { echo "PASS $1"; }
fail() { echo "FAIL $1: $2"; }

# expect NAME EXIT_CODE PATTERN -- command...
# Runs the command; passes when it exits with EXIT_CODE and its stdout+stderr
# contains PATTERN (fixed string).
expect() {
  local name=$1 code=$2 pat=$3; shift 4
  local out rc
  out=$("$@" 2>&1); rc=$?
  if [ $rc -ne "$code" ]; then fail "$name" "exit $rc, expected $code: $(echo "$out" | head -3 | tr '\n' ' ')"
  elif ! echo "$out" | grep -qF -- "$pat"; then fail "$name" "output lacks '$pat': $(echo "$out" | head -3 | tr '\n' ' ')"
  else pass "$name"; fi
}

# check NAME CONDITION-COMMAND...   passes when the command exits 0
check() {
  local name=$1; shift
  if "$@"; then pass "$name"; else fail "$name" "check failed: $*"; fi
}
