#!/usr/bin/env bash
# tb_accel_dram_set — the DRAM standard's keys through rtsim (model/mem/memsys_config.h
# [dram]; docs/dram.md "From rtsim"):
#  - accepted: --set dram.timing.nCL=14 changes the frame's cycles and the
#    run's config_hash; a machine .ini with a [dram] section gives the same
#    configuration (same hash, same cycles) as the --set; a constraint key
#    (a phrase with spaces) is settable; --help-module dram lists the keys;
#    --autosize-fifos writes the [dram] keys with their resolved values and
#    the written machine loads back with them;
#  - refused (exit 2, no JSON written): an unknown key (named, with the keys of
#    its section), a value out of range (named, with the range), a bad value in
#    a machine file (FILE:LINE).
set -u
bin=${RTSIM_BIN:?}/rtsim
tmp=${RTSIM_TMP:-/tmp}/tb_accel_dram_set
rm -rf "$tmp"; mkdir -p "$tmp"
. "$(dirname "$0")/../cli_lib.sh"
res=32x18

# field FILE KEY: a top-level statistic, or run.KEY
field() {
  python3 -c 'import json, sys
d = json.load(open(sys.argv[1]))
k = sys.argv[2]
print(d["run"][k[4:]] if k.startswith("run.") else d[k])' "$1" "$2"
}

if "$bin" interior --res $res --quiet --json "$tmp/base.json" &&
   "$bin" interior --res $res --quiet --set dram.timing.nCL=14 --json "$tmp/cl14.json"; then
  c0=$(field "$tmp/base.json" cycles); c1=$(field "$tmp/cl14.json" cycles)
  h0=$(field "$tmp/base.json" run.config_hash); h1=$(field "$tmp/cl14.json" run.config_hash)
  if [ "$c0" != "$c1" ] && [ "$h0" != "$h1" ]; then pass accel_dram_set_changes_cycles_and_hash
  else fail accel_dram_set_changes_cycles_and_hash "cycles $c0 vs $c1, config_hash $h0 vs $h1"; fi
else
  fail accel_dram_set_changes_cycles_and_hash "rtsim failed"
fi

# the same override from a machine file: [dram] section, keys SECTION.KEY
printf '[dram]\ntiming.nCL = 14\n' > "$tmp/cl14.ini"
if "$bin" interior --res $res --quiet --machine "$tmp/cl14.ini" --json "$tmp/file.json" &&
   [ "$(field "$tmp/file.json" cycles)" = "$(field "$tmp/cl14.json" cycles)" ] &&
   [ "$(field "$tmp/file.json" run.config_hash)" = "$(field "$tmp/cl14.json" run.config_hash)" ]; then
  pass accel_dram_set_from_machine_file
else fail accel_dram_set_from_machine_file "a [dram] file differs from --set dram.timing.nCL=14"; fi

# a constraint key (spaces in the key) and a controller key
if "$bin" interior --res $res --quiet --set "dram.constraints.bank ACT -> RD = 30" \
     --set dram.controller.row_hit_cap=2 --json "$tmp/cons.json" &&
   [ "$(field "$tmp/cons.json" cycles)" != "$(field "$tmp/base.json" cycles)" ]; then
  pass accel_dram_set_constraint_and_controller
else fail accel_dram_set_constraint_and_controller "no effect or refused"; fi

expect accel_dram_set_help_module 0 "dram.timing.nCL" -- "$bin" --help-module dram

# --autosize-fifos writes the [dram] keys; the written machine holds nCL = 14
if "$bin" interior --res $res --quiet --set dram.timing.nCL=14 --autosize-fifos "$tmp/sized.ini" &&
   grep -q '^\[dram\]' "$tmp/sized.ini" && grep -q '^timing\.nCL = 14$' "$tmp/sized.ini" &&
   grep -q '^organization\.channels = 2$' "$tmp/sized.ini" &&
   "$bin" interior --res $res --quiet --machine "$tmp/sized.ini" --json "$tmp/s1.json" &&
   "$bin" interior --res $res --quiet --machine "$tmp/sized.ini" --set dram.timing.nCL=14 --json "$tmp/s2.json" &&
   [ "$(field "$tmp/s1.json" run.config_hash)" = "$(field "$tmp/s2.json" run.config_hash)" ] &&
   [ "$(field "$tmp/s1.json" cycles)" = "$(field "$tmp/s2.json" cycles)" ]; then
  pass accel_dram_set_autosize_writes_dram_keys
else fail accel_dram_set_autosize_writes_dram_keys "$(grep -A3 '^\[dram\]' "$tmp/sized.ini" 2>/dev/null | tr '\n' ' ')"; fi

# refused: exit 2, the key named, no output
rm -f "$tmp/bad.json"
expect accel_dram_set_unknown_key 2 "unknown key dram.timing.nFOO (keys dram.timing.*: nBL, nCCD, nCL" -- \
  "$bin" interior --res 8x4 --set dram.timing.nFOO=3 --json "$tmp/bad.json"
expect accel_dram_set_unknown_section 2 "unknown key dram.refresh.x" -- \
  "$bin" interior --res 8x4 --set dram.refresh.x=1 --json "$tmp/bad.json"
expect accel_dram_set_out_of_range 2 "--set dram.organization.channels=99: [organization] channels = 99 out of range, allowed 1..16" -- \
  "$bin" interior --res 8x4 --set dram.organization.channels=99 --json "$tmp/bad.json"
expect accel_dram_set_negative_timing 2 "--set dram.timing.nCL=-1: [timing] nCL = -1 out of range, allowed 1..10000000" -- \
  "$bin" interior --res 8x4 --set dram.timing.nCL=-1 --json "$tmp/bad.json"
printf '[machine]\nname = x\n[dram]\ntiming.nRCD = 15 +\n' > "$tmp/bad.ini"
expect accel_dram_set_bad_file_value 2 "bad.ini:4: [timing] nRCD = '15 +'" -- \
  "$bin" interior --res 8x4 --machine "$tmp/bad.ini" --json "$tmp/bad.json"
check accel_dram_set_refused_no_output test ! -e "$tmp/bad.json"
rm -rf "$tmp"
