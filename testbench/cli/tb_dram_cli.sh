#!/usr/bin/env bash
# tb_dram_cli — rtdram's command line: help/version, JSON keys and values on a tiny
# trace (m3 of ramulator_micro_latency.csv: 83 cycles, 5 commands), the command
# stream file (written via a temporary name), the timing checker, determinism,
# and bad input: malformed trace lines, unknown or out-of-range --set keys, missing
# files -> a message naming file:line or the key and allowed range, exit 2, no
# partial output file; --kernel (the kernel module) equals the direct loop.
set -u
bin=${RTSIM_BIN:?}/rtdram
tmp=${RTSIM_TMP:-/tmp}/tb_dram_cli
rm -rf "$tmp"; mkdir -p "$tmp"

. "$(dirname "$0")/../cli_lib.sh"

printf '0x0 R\n0x10000 R\n' > "$tmp/m3.trace"
printf '0x0 R\n# comment\n\n0x40 X\n' > "$tmp/bad_rw.trace"
printf '0x0 R\nzz R\n' > "$tmp/bad_addr.trace"
printf '0x0 R\n0x40 R extra\n' > "$tmp/bad_extra.trace"

expect dram_cli_help 0 "usage: rtdram TRACE" -- "$bin" --help
expect dram_cli_version 0 "rtdram" -- "$bin" --version
expect dram_cli_version_git 0 "git" -- "$bin" --version
expect dram_cli_no_trace 2 "exactly one TRACE" -- "$bin"
expect dram_cli_bad_option 2 "usage" -- "$bin" "$tmp/m3.trace" --bogus
expect dram_cli_missing_trace 2 "no_such.trace: cannot open" -- "$bin" "$tmp/no_such.trace"
expect dram_cli_malformed_rw 2 "bad_rw.trace:4: expected '0x<hex address> R|W'" -- "$bin" "$tmp/bad_rw.trace"
expect dram_cli_malformed_addr 2 "bad_addr.trace:2:" -- "$bin" "$tmp/bad_addr.trace"
expect dram_cli_malformed_extra 2 "bad_extra.trace:2:" -- "$bin" "$tmp/bad_extra.trace"
expect dram_cli_unknown_set_key 2 "unknown key 'timing.nXYZ'" -- "$bin" "$tmp/m3.trace" --set timing.nXYZ=1
expect dram_cli_set_out_of_range 2 "allowed 1..64" -- "$bin" "$tmp/m3.trace" --set organization.banks=0 2>&1
expect dram_cli_set_out_of_range_names_key 2 "banks" -- "$bin" "$tmp/m3.trace" --set organization.banks=0
expect dram_cli_missing_config 2 "nope.ini: cannot open" -- "$bin" "$tmp/m3.trace" --config "$tmp/nope.ini"
expect dram_cli_check_clean 0 "0 violations" -- "$bin" "$tmp/m3.trace" --check

# JSON: one object with the reference keys and the m3 values
json=$("$bin" "$tmp/m3.trace" --json 2>&1)
if echo "$json" | python3 -c '
import json, sys
d = json.loads(sys.stdin.read())
keys = "dram_cycles time_ns bw_GBps read_lat_avg_cycles row_hit_rate n_act n_pre n_prea n_ref n_rd n_wr energy_uJ energy_pJ_per_byte".split()
missing = [k for k in keys if k not in d]
assert not missing, missing
assert d["dram_cycles"] == 83 and d["n_act"] == 2 and d["n_pre"] == 1 and d["n_rd"] == 2, d
assert d["read_lat_avg_cycles"] == 58.0 and d["time_ns"] == 83 * 1.25, d
assert abs(d["row_hit_rate"]) < 1e-12 and d["energy_uJ"] > 0, d
'; then pass dram_cli_json; else fail dram_cli_json "$json"; fi

# determinism
a=$("$bin" "$tmp/m3.trace" --json | sans_run); b=$("$bin" "$tmp/m3.trace" --json | sans_run)
[ "$a" = "$b" ] && pass dram_cli_deterministic || fail dram_cli_deterministic "two runs differ"

# --set changes the result (tRCD 15 -> 20: both RDs of m3 5 cycles later, PRE still at tRAS: 83 -> 88)
c=$("$bin" "$tmp/m3.trace" --json --set timing.nRCD=20 | python3 -c 'import json,sys; print(json.load(sys.stdin)["dram_cycles"])')
[ "$c" = 88 ] && pass dram_cli_set_applies || fail dram_cli_set_applies "dram_cycles $c, expected 88"

# command stream file, written via a temporary name
"$bin" "$tmp/m3.trace" --cmd-trace "$tmp/m3.cmd" >/dev/null 2>&1
if [ -f "$tmp/m3.cmd" ] && [ "$(grep -vc '^#' "$tmp/m3.cmd")" = 5 ] && grep -q '^35,0,0,0,PRE,-1$' "$tmp/m3.cmd" \
   && [ -z "$(ls "$tmp" | grep '\.tmp\.')" ]; then
  pass dram_cli_cmd_trace
else
  fail dram_cli_cmd_trace "$(cat "$tmp/m3.cmd" 2>/dev/null | tr '\n' ' ')"
fi
# a long --cmd-trace path: its temporary name was cut at 1099 characters,
# which here named victim.txt beside it: overwritten, then renamed away
pad=$((1089 - ${#tmp} - 1)); prefix="$tmp/"
if [ $((pad % 2)) = 1 ]; then prefix="$prefix/"; pad=$((pad - 1)); fi
prefix="$prefix$(printf './%.0s' $(seq $((pad / 2))))"
echo "keep me" > "$tmp/victim.txt"
"$bin" "$tmp/m3.trace" --cmd-trace "${prefix}victim.txt.long" >/dev/null 2>&1; rc=$?
if [ $rc = 0 ] && [ "$(cat "$tmp/victim.txt" 2>/dev/null)" = "keep me" ] && cmp -s "$tmp/victim.txt.long" "$tmp/m3.cmd"; then
  pass dram_cli_cmd_trace_long_path
else
  fail dram_cli_cmd_trace_long_path "exit $rc; victim.txt: '$(head -c 40 "$tmp/victim.txt" 2>/dev/null)'"
fi
# the power file beside a long --config path: its name was cut at 1023 characters
mkdir -p "$tmp/cfgdir"; cp model/data/lpddr3_1600.ini model/data/lpddr3_1600_idd.ini "$tmp/cfgdir/"
long_cfg="$tmp/$(printf './%.0s' $(seq 600))cfgdir/lpddr3_1600.ini"
out=$("$bin" "$tmp/m3.trace" --json --config "$long_cfg" 2>&1); rc=$?
if [ $rc = 0 ] && [ "$(echo "$out" | sans_run)" = "$("$bin" "$tmp/m3.trace" --json 2>&1 | sans_run)" ]; then
  pass dram_cli_config_long_path
else
  fail dram_cli_config_long_path "exit $rc: $(echo "$out" | head -c 200)"
fi
rm -f "$tmp/bad.cmd"
"$bin" "$tmp/bad_rw.trace" --cmd-trace "$tmp/bad.cmd" >/dev/null 2>&1
if [ ! -e "$tmp/bad.cmd" ] && [ -z "$(ls "$tmp" | grep '\.tmp\.')" ]; then pass dram_cli_no_partial_output
else fail dram_cli_no_partial_output "output file left after bad input"; fi
# --kernel: the same trace through the kernel module (FIFOs, DRAM clock) gives the
# same JSON and command stream as the direct loop; on m3 and on a mixed trace with
# writes, forwarded reads, refreshes and the final write drain
python3 - "$tmp/mix.trace" <<'PY'
import random, sys
r = random.Random(7)
with open(sys.argv[1], "w") as f:
    a, last_w = 0, 0
    for i in range(6000):
        a = a + 32 if r.random() < 0.5 else r.randrange(1 << 17) * 32
        w = r.random() < 0.3
        x = last_w if (not w and r.random() < 0.05) else a
        if w:
            last_w = x
        f.write("0x%x %s\n" % (x, "W" if w else "R"))
PY
for t in m3 mix; do
  d=$("$bin" "$tmp/$t.trace" --json --cmd-trace "$tmp/$t.direct.cmd" 2>&1 | sans_run)
  k=$("$bin" "$tmp/$t.trace" --json --kernel --check --cmd-trace "$tmp/$t.kernel.cmd" 2>&1); rc=$?
  k=$(echo "$k" | sans_run)
  if [ $rc -ne 0 ]; then fail dram_cli_kernel_equals_direct_$t "exit $rc: $k"
  elif [ "$d" != "$k" ]; then fail dram_cli_kernel_equals_direct_$t "JSON differs: $d vs $k"
  elif ! cmp -s <(grep -v '^#' "$tmp/$t.direct.cmd") <(grep -v '^#' "$tmp/$t.kernel.cmd"); then
    fail dram_cli_kernel_equals_direct_$t "command streams differ"
  else pass dram_cli_kernel_equals_direct_$t; fi
done
expect dram_cli_kernel_malformed 2 "bad_addr.trace:2:" -- "$bin" "$tmp/bad_addr.trace" --kernel
rm -rf "$tmp"
