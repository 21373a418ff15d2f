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

# sans_run: one JSON object on stdin, printed (keys sorted, one line)
# without its "run" object: the provenance of docs/results.md (command line,
# host times, date) differs between two runs with the same results.
sans_run() {
  python3 -c 'import json, sys; d = json.load(sys.stdin); d.pop("run", None); print(json.dumps(d, sort_keys=True))'
}

# same_results A.json B.json: the two files are equal but for their "run"
# objects, and those agree on what produced the results (scene, mesh, machine
# and configuration hash, rays).
same_results() {
  python3 - "$1" "$2" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
ra, rb = a.pop("run"), b.pop("run")
same = ("scene", "mesh_hash", "view", "machine", "config_hash", "width_px", "height_px", "ray_type", "bounces", "seed")
sys.exit(0 if a == b and all(ra[k] == rb[k] for k in same) else 1)
PY
}

# check NAME CONDITION-COMMAND...   passes when the command exits 0
check() {
  local name=$1; shift
  if "$@"; then pass "$name"; else fail "$name" "check failed: $*"; fi
}
