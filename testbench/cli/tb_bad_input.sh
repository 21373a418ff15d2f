#!/usr/bin/env bash
# tb_bad_input — the table-driven bad-input test of rtsim, rttrace and rtdram
# (docs/kernel.md, "Outputs and interruption"): every row of testbench/cli/bad_input.tsv runs one command in a
# fresh folder and checks
#   - the exit status and a fixed string of the message (stdout+stderr),
#   - that no output file is left behind that looks valid: every new file
#     must be listed in the row's "leftovers" column, no temporary file
#     ("*.tmp*", the output layer's "rtsim-out.*" staging files in $TMPDIR)
#     may remain, files present before the run keep their content and type
#     (a symlink stays a symlink), and a leftover of a failed or interrupted
#     run must say so: a .json holds "partial": true or "run_failed": 1, a
#     command trace ends with a "# partial" line, a .vcd is read by vcd2fst
#     (when installed).
# Table columns (tab-separated; '#' lines and blank lines skipped):
#   name  tool  exit  message  setup  command  leftovers
# setup and command are bash run in the case's folder with $RTSIM, $RTTRACE,
# $RTDRAM (the binaries) and $F (shared read-only fixtures made below);
# '-' = none. leftovers: space-separated globs of files allowed to remain.
# TB_BAD_INPUT_ROWS=regex runs only the rows whose name matches (tb_relocated.sh
# runs a few from a copy of the tree under a long path).
# The release build runs every row; a sanitized build (RTSIM_TB_SANITIZED,
# several times slower to start) runs every 8th row and every interruption
# and FIFO row, to keep make test short; TB_BAD_INPUT_FULL=1 runs all rows
# there too.
# interrupt SIG FILE cmd... (below) runs cmd, waits until FILE (a glob) is
# non-empty (the run is under way), sends SIG and returns cmd's exit status;
# it prints the time from the signal to the exit as an INFO line.
set -u
bindir=${RTSIM_BIN:?}
tmp=${RTSIM_TMP:-/tmp}/tb_bad_input
table="$(cd "$(dirname "$0")" && pwd)/bad_input.tsv"
rm -rf "$tmp"; mkdir -p "$tmp"
. "$(dirname "$0")/../cli_lib.sh"
export RTSIM="$bindir/rtsim" RTTRACE="$bindir/rttrace" RTDRAM="$bindir/rtdram"
export F="$tmp/fixtures" REPO="$(cd "$(dirname "$0")/../.." && pwd)"
# ASan runs are several times slower: the interruption helper waits longer
scale=1; [ -n "${RTSIM_TB_SANITIZED:-}" ] && scale=4

# ---- fixtures ----
mkdir -p "$F/folder.obj" "$F/adir"
cd "$F"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n' > tri.obj
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nv 2 0 0\nf 1 2 9\n' > badidx.obj
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n' > shortface.obj
printf 'v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > nan.obj
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nbogus 1 2\n' > badkw.obj
printf 'v 1 2\nf 1 1 1\n' > shortvert.obj
: > empty.obj
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\n' > nofaces.obj
for s in 1e15 1e38 3e38 -2e12; do printf 'v 0 0 0\nv %s 0 0\nv 0 1 0\nf 1 2 3\n' "$s" > "scale_$s.obj"; done
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 18446744073709551615\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n01234567890123456789012345' > hugecount.ply
# 2^64 + 1 vertices: a count that does not fit in 64 bits
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 18446744073709551617\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0123456789' > hugecount2.ply
printf '[trv]\ncount = 99999999999999999999999\n' > m_huge.ini
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n' > truncated.ply
printf 'ply\nformat ascii 2.0\nend_header\n' > badformat.ply
printf 'not a ply\n' > notply.ply
printf 'garbage' > bad.obj.gz
printf 'view v1 eye 0 0 5 at 0 0 0 up 0 1 0\n' > views_short.txt
printf 'view v1 eye 0 0 5 at 0 0 5 up 0 1 0 fov 60\n' > views_same.txt
printf 'view v1 eye 0 0 5 at 0 0 0 up 0 0 1 fov 60\n' > views_par.txt
printf 'view v1 eye 0 0 5 at 0 0 0 up 0 1 0 fov 200\n' > views_fov.txt
printf 'view v1 eye 0 0 6e12 at 0 0 0 up 0 1 0 fov 60\n' > views_far.txt
printf 'mesh tri.obj\nbogus line\n' > bad.scene
printf 'mesh nosuch.obj\n' > missing_mesh.scene
printf '[trv]\ncount = 0\n' > m_range.ini
printf '[trv]\nnosuchkey = 1\n' > m_key.ini
printf '[nosuchsection]\nx = 1\n' > m_section.ini
printf 'count = 2\n' > m_nosection.ini
printf '[trv\ncount = 2\n' > m_syntax.ini
printf '0x0 R\n0x40 W\n0x1000 R\n' > ok.trace
: > empty.trace
printf '# only a comment\n\n' > comments.trace
printf '0x0 R\n0x40 R\0junk\n' > nul.trace
printf '0x0 R\n0x40000000 R\n' > beyond.trace
printf '0x0 R\n0xffffffffffffffff W\n' > max.trace
printf '0x0 R\n0x12345678901234567 R\n' > toolong.trace
printf '0x0 R\n0x40 X\n' > badop.trace
printf '0x0 R\n40 R\n' > nohex.trace
printf '0x0 R\n0x40 R extra\n' > extra.trace
printf '0x0R\n' > nospace.trace
printf '[organization]\nchannels = 2\n' > dram_partial.ini
printf 'not an ini\n' > dram_syntax.ini
"$RTTRACE" tri.obj --res 8x4 --log good.tlog --quiet >/dev/null 2>&1
head -c 100 good.tlog > cut.tlog
printf 'RTLGjunkjunkjunkjunk' > junk.tlog
# a long run for the interruption rows: 500k requests over 16 MB
awk 'BEGIN { x = 7; for (i = 0; i < 500000; i++) { x = (x * 1103515245 + 12345) % 2147483648;
     printf "0x%x %s\n", (x % 524288) * 32, (x % 10 < 3) ? "W" : "R" } }' > long.trace
chmod -R a-w "$F" 2>/dev/null; chmod u+w "$F"   # fixtures are read-only for the cases (root ignores it)
cd "$tmp"

interrupt() { # SIG FILEGLOB cmd...
  local sig=$1 glob=$2; shift 2
  "$@" & local pid=$!
  local i=0
  while [ $i -lt $((600 * scale)) ]; do
    # shellcheck disable=SC2086
    for f in $glob; do [ -s "$f" ] && break 2; done
    kill -0 $pid 2>/dev/null || break
    sleep 0.05; i=$((i + 1))
  done
  sleep 0.3
  local t0; t0=$(date +%s%N)
  kill -"$sig" $pid 2>/dev/null
  wait $pid; local rc=$?
  echo "INFO interrupt $sig: exited $rc, $(( ($(date +%s%N) - t0) / 1000000 )) ms after the signal" >&2
  return $rc
}
export -f interrupt; export scale

snapshot() { # the entries of . with type and content hash
  find . -mindepth 1 -printf '%y %p |%l\n' | sort
  find . -type f -exec md5sum {} + 2>/dev/null | sort -k2
}

have_vcd2fst=0; command -v vcd2fst >/dev/null && have_vcd2fst=1
n=0; ran=0; outs=(); declare -A per_tool
while IFS=$'\t' read -r name tool code msg setup cmd allowed; do
  [[ -z "$name" || "$name" == \#* ]] && continue
  n=$((n + 1))
  per_tool[$tool]=$(( ${per_tool[$tool]:-0} + 1 ))
  [[ -n "${TB_BAD_INPUT_ROWS:-}" && ! "$name" =~ $TB_BAD_INPUT_ROWS ]] && continue
  if [ -n "${RTSIM_TB_SANITIZED:-}" ] && [ -z "${TB_BAD_INPUT_FULL:-}" ] && [ $((n % 8)) -ne 1 ] &&
     [[ "$cmd" != *interrupt* && "$cmd" != *fifo* ]]; then
    continue
  fi
  ran=$((ran + 1))
  w="$tmp/case_$n"; mkdir -p "$w/tmpdir"
  # Rows that send signals or feed FIFOs depend on timing: they run alone.
  # The others run two at a time (each in its own folder and TMPDIR), their
  # lines printed in table order at the end.
  serial=0; [[ "$cmd" == *interrupt* || "$cmd" == *fifo* ]] && serial=1
  if [ $serial -eq 1 ]; then wait; else while [ "$(jobs -rp | wc -l)" -ge 2 ]; do wait -n; done; fi
  outs+=("$w.out")
  (
    cd "$w" || exit 1
    export TMPDIR="$w/tmpdir"
    [ "$setup" != "-" ] && bash -c "$setup" >/dev/null 2>&1
    before=$(snapshot)
    out=$(timeout 120 bash -c "$cmd" 2>&1 </dev/null); rc=$?
    problems=""
    [ "$rc" -ne "$code" ] && problems+="exit $rc, expected $code; "
    [ "$msg" != "-" ] && ! grep -qF -- "$msg" <<<"$out" && problems+="message lacks '$msg'; "
    # temporaries, anywhere in the case folder (TMPDIR included)
    tmps=$(find . -name '*.tmp*' -o -name 'rtsim-out.*' | tr '\n' ' ')
    [ -n "$tmps" ] && problems+="temporary files left: $tmps; "
    after=$(snapshot)
    # files present before: unchanged (content, type), unless allowed
    while read -r line; do
      [ -z "$line" ] && continue
      if ! grep -qxF -- "$line" <<<"$after"; then
        p=$(awk '{print $2}' <<<"$line"); p=${p#./}
        ok=0; for g in $allowed; do [[ "$g" != "-" && "$p" == $g ]] && ok=1; done
        [ $ok -eq 0 ] && problems+="changed or removed: $line; "
      fi
    done <<<"$before"
    # new files: allowed, and marked when the run failed
    for p in $(find . -mindepth 1 -not -type d -not -path './tmpdir/*' | sed 's|^\./||'); do
      grep -qF -- " ./$p" <<<"$before" && continue
      ok=0; for g in $allowed; do [[ "$g" != "-" && "$p" == $g ]] && ok=1; done
      if [ $ok -eq 0 ]; then problems+="left $p; "; continue; fi
      [ "$code" -eq 0 ] && continue
      case "$p" in
        *.json) grep -qE '"partial": true|"run_failed": 1' "$p" || problems+="$p is not marked partial; " ;;
        *.vcd) if [ $have_vcd2fst -eq 1 ]; then vcd2fst "$p" "$w/check.fst" >/dev/null 2>&1 || problems+="vcd2fst cannot read $p; "; rm -f "$w/check.fst"; fi ;;
        *.cmd) tail -1 "$p" | grep -q '^# partial' || problems+="$p does not end with '# partial'; " ;;
      esac
    done
    grep '^INFO interrupt' <<<"$out" | sed "s/^INFO /INFO $name: /"
    if [ -z "$problems" ]; then pass "bad_input_$name"
    else fail "bad_input_$name" "${problems}output: $(head -c 300 <<<"$out" | tr '\n' ' ')"; fi
    cd "$tmp" && rm -rf "$w"
  ) >"$w.out" 2>&1 </dev/null &
  [ $serial -eq 1 ] && wait
done < "$table"
wait
for o in "${outs[@]}"; do cat "$o"; rm -f "$o"; done
for t in "${!per_tool[@]}"; do echo "INFO bad_input: ${per_tool[$t]} cases for $t"; done
echo "INFO bad_input: $n cases in total, $ran run in this build"
chmod -R u+w "$F" 2>/dev/null
[ "$n" -ge 150 ] && pass bad_input_table_has_150_cases || fail bad_input_table_has_150_cases "only $n rows"
