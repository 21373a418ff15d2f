#!/usr/bin/env bash
# tb_dram_ref — rtdram against the reference DRAM results in ../shared/ref/dram
# (Ramulator v1 + DRAMPower 4.1), through scripts/dram_compare.py. Skips cleanly
# when the reference folder is absent.
#  release:   the full comparison of config A (5 traces, 2-4 M requests each):
#             time within 3 %, row hits within 2 points, commands within 3 %,
#             energy within 5 %, zero timing violations; and the whole d_mix7030
#             trace (2 M requests, 30 % writes) through the kernel module
#             (rtdram --kernel) gives the same JSON as the direct loop.
#  sanitized: (RTSIM_TB_SANITIZED) 20000-line prefixes of the same traces through
#             the ASan/UBSan rtdram with the timing checker: fast == exhaustive ==
#             kernel module.
set -u
. "$(dirname "$0")/../../cli_lib.sh"   # sans_run: the JSON without its "run" object
bin=${RTSIM_BIN:?}/rtdram
tmp=${RTSIM_TMP:-/tmp}
cmp=scripts/dram_compare.py
if ! python3 $cmp --find-ref >/dev/null 2>&1; then
  echo "SKIP dram_ref_compare: ../shared/ref/dram not found"
  exit 0
fi
if [ -z "${RTSIM_TB_SANITIZED:-}" ]; then
  out=$(python3 $cmp --rtdram "$bin" 2>&1); rc=$?
  if [ $rc -eq 0 ]; then
    echo "PASS dram_ref_compare_config_A"
  else
    echo "FAIL dram_ref_compare_config_A: exit $rc: $(echo "$out" | grep -E ' NO$|dram_compare:' | head -3 | tr '\n' ';')"
    echo "$out" >&2
  fi
  traces=$(python3 $cmp --generate-only 2>/dev/null | tail -1)
  d=$("$bin" "$traces/d_mix7030.il32.trace" --json 2>&1 | sans_run)
  k=$("$bin" "$traces/d_mix7030.il32.trace" --json --kernel 2>&1 | sans_run)
  if [ -n "$d" ] && [ "$d" = "$k" ]; then echo "PASS dram_ref_kernel_module_equals_direct_d_mix7030"
  else echo "FAIL dram_ref_kernel_module_equals_direct_d_mix7030: direct $d; kernel $k"; fi
  exit 0
fi
traces=$(python3 $cmp --generate-only 2>/dev/null | tail -1)
if [ ! -d "$traces" ]; then
  echo "FAIL dram_ref_prefixes: could not generate traces"
  exit 0
fi
for t in a_seq b_rand64 c_rand128 d_mix7030 e_rowloc; do
  p=$tmp/dram_ref_$t.trace
  head -n 20000 "$traces/$t.il32.trace" > "$p"
  fast=$("$bin" "$p" --json --check 2>"$p.err"); rc=$?
  fast=$(echo "$fast" | sans_run)
  slow=$("$bin" "$p" --json --exhaustive 2>/dev/null | sans_run)
  kern=$("$bin" "$p" --json --kernel 2>/dev/null | sans_run)
  if [ $rc -ne 0 ]; then
    echo "FAIL dram_ref_prefix_$t: rtdram exit $rc: $(head -2 "$p.err" | tr '\n' ';')"
  elif [ "$fast" != "$slow" ]; then
    echo "FAIL dram_ref_prefix_$t: fast and exhaustive modes differ"
  elif [ "$fast" != "$kern" ]; then
    echo "FAIL dram_ref_prefix_$t: the kernel module (--kernel) differs from the direct loop"
  elif ! echo "$fast" | python3 -c 'import json,sys; d=json.load(sys.stdin); sys.exit(0 if d["n_rd"]+d["n_wr"]+d["reads_forwarded"]==20000 else 1)'; then
    echo "FAIL dram_ref_prefix_$t: not all 20000 requests served: $fast"
  else
    echo "PASS dram_ref_prefix_$t"
  fi
  rm -f "$p" "$p.err"
done
