#!/usr/bin/env bash
# tb_relocated — the tools and scripts work wherever the tree is: the built
# binaries, scripts/, testbench/ and model/data are copied under a path of more
# than 120 characters with spaces and non-ASCII letters, and from there
#   - scripts/sweep runs a 2-point grid on GNU parallel (a machine file under
#     that path, the default rtsim and output folder of the copy) and merges it,
#   - a few rows of bad_input.tsv run (files under that path, RTSIM_DATA_DIR
#     pointing into the copy): messages name the whole path, nothing is cut.
# A fixed-width cut of a path, or a command line split at a space, fails here.
set -u
bindir=${RTSIM_BIN:?}
tmp=${RTSIM_TMP:-/tmp}/tb_relocated
rm -rf "$tmp"; mkdir -p "$tmp"
cd "$(dirname "$0")/../.."
. testbench/cli_lib.sh

# The copy's root: long, with spaces and non-ASCII letters, whatever $tmp is.
dest="$tmp/a copy of the checkout/Jääskeläinen ja Immonen – säteenseuranta/another folder with a rather long name/one more level/rtsim tree"
check relocated_path_is_long test "$(printf '%s' "${dest#"$tmp"/}" | wc -m)" -ge 120
mkdir -p "$dest/build/bin" "$dest/model"
cp -a scripts testbench "$dest/"
cp -a model/data "$dest/model/data"
cp -a "$bindir"/. "$dest/build/bin/"
export RTSIM_DATA_DIR="$dest/model/data"

# --- a 2-point sweep from the copy (its rtsim, its output folder)
out=$(cd "$dest" && scripts/sweep --set-grid node_l1.size=4096,8192 \
        --machines "$dest/model/data/machines/mbvh4.ini" --scenes interior --res 32x18 --jobs 2 2>&1); rc=$?
check relocated_sweep_exit_0 test $rc -eq 0
check relocated_sweep_merged_both grep -q "merged 2 of 2 points" <<< "$out"
check relocated_sweep_two_rows test "$(tail -n +2 "$dest/build/sweep/results.csv" 2>/dev/null | wc -l)" -eq 2
check relocated_sweep_mrps_column grep -q "mrps" "$dest/build/sweep/results.csv"
[ $rc -eq 0 ] || echo "sweep output: $out" >&2

# --- a few bad-input rows, run by the copy's tb_bad_input.sh on the copy's
# binaries (case names prefixed relocated_)
rows='^(rtsim_machine_folder|rtsim_machine_missing_file|rtsim_machine_syntax|rtsim_scene_folder|rtsim_views_fov|rtsim_machine_dev_zero|rtsim_set_int_too_large|rttrace_read_log_folder|rtdram_trace_folder|rtdram_config_folder)$'
RTSIM_BIN="$dest/build/bin" RTSIM_TMP="$dest/tmp" TB_BAD_INPUT_ROWS="$rows" bash "$dest/testbench/tb_bad_input.sh" 2>&1 |
  grep -E '^(PASS|FAIL) bad_input_' | grep -v bad_input_table_has | sed -E 's/^(PASS|FAIL) bad_input_/\1 relocated_bad_input_/'
# a machine preset found through RTSIM_DATA_DIR under the long path
expect relocated_preset_from_data_dir 0 "" -- "$dest/build/bin/rtsim" interior --res 8x4 --quiet --machine bvh2
expect relocated_unknown_preset_lists_presets 2 "unknown machine preset 'mbvh8' (presets: " -- \
  "$dest/build/bin/rtsim" interior --res 8x4 --quiet --machine mbvh8
# the whole path in a message, not a cut of it
expect relocated_missing_views_named 2 "$dest/nosuch views.txt: cannot open" -- \
  "$dest/build/bin/rtsim" interior --res 8x4 --quiet --views "$dest/nosuch views.txt"
rm -rf "$tmp"
