#!/usr/bin/env bash
# tb_rttrace_cli — rttrace's command line: help/version; bad usage and input
# (unknown options, out-of-range values, unknown view/scene, bad output
# paths) -> exit 2 with a message naming the option and the allowed range, and
# no output file left behind; a small run of every built-in scene, primary and
# diffuse, with --check-embree and --json parsed by python3 (rays = pixels
# for primary rays, embree_mismatches == 0, counts consistent, bytes per node
# visit <= 2); the log re-read and validated by --read-log (same totals) and
# rejected when corrupted or read against another BVH; images written and
# readable with the right size; determinism: two runs give identical JSON
# counts, identical logs and identical images.
set -u
bin=${RTSIM_BIN:?}/rttrace
tmp=${RTSIM_TMP:-/tmp}/tb_rttrace_cli
rm -rf "$tmp"; mkdir -p "$tmp"
# Each process pays ~0.3 s of shared-library start-up (OIIO, Embree), so
# the sanitizer build runs two of the four scenes.
res=64x36 scenes="interior hairball city forest"
[ -n "${RTSIM_TB_SANITIZED:-}" ] && res=32x18 scenes="interior city"

. "$(dirname "$0")/../cli_lib.sh"

# Usage errors exit before any tracing: checked in the release build only
# (the sanitizer build runs the traced cases below).
if [ -z "${RTSIM_TB_SANITIZED:-}" ]; then
expect rttrace_help 0 "usage: rttrace SCENE" -- "$bin" --help
# the help states the option table's range and default (cli/options.h)
expect rttrace_help_range 0 "--leaf-size N          max triangles per leaf, 1..255 (default 4)" -- "$bin" --help
expect rttrace_version 0 "rttrace 0.1.0 (git " -- "$bin" --version
expect rttrace_no_scene 2 "missing SCENE" -- "$bin"
expect rttrace_unknown_option 2 "unknown option --bogus" -- "$bin" interior --bogus
expect rttrace_missing_value 2 "--res needs a value" -- "$bin" interior --res
expect rttrace_bad_bvh 2 "--bvh: 'mbvh9' is not a BVH type; allowed: bvh2, mbvh4, mbvhN with N = 2..8" -- "$bin" interior --bvh mbvh9
expect rttrace_bad_leaf 2 "--leaf-size: '0' is not an integer in 1..255" -- "$bin" interior --leaf-size 0
expect rttrace_bad_rays 2 "--rays: 'shadow' is not a ray type; allowed: primary, diffuse" -- "$bin" interior --rays shadow
expect rttrace_bad_res 2 "--res:" -- "$bin" interior --res 0x10
expect rttrace_bad_bounces 2 "--bounces: '33' is not an integer in 0..32" -- "$bin" interior --rays diffuse --bounces 33
expect rttrace_bounces_needs_diffuse 2 "--bounces: only with --rays diffuse" -- "$bin" interior --bounces 2
expect rttrace_bad_seed 2 "--seed: '-1' is not an integer in 0..18446744073709551615" -- "$bin" interior --seed -1
expect rttrace_bad_rate 2 "--max-mismatch-rate: '2' is not a number in 0..1" -- "$bin" interior --max-mismatch-rate 2
expect rttrace_bad_image_type 2 "--image $tmp/x.bmp: unsupported image type; allowed: .png, .exr" -- "$bin" interior --image "$tmp/x.bmp"
expect rttrace_missing_folder 2 "--log $tmp/nodir/a.tlog: folder $tmp/nodir does not exist" -- "$bin" interior --log "$tmp/nodir/a.tlog"
expect rttrace_unknown_scene 2 "nosuchscene" -- "$bin" nosuchscene
expect rttrace_unknown_view 2 "--view:" -- "$bin" interior --view nosuchview --res $res
expect rttrace_missing_views_file 2 "--views:" -- "$bin" interior --views "$tmp/none.txt"
expect rttrace_read_log_exclusive 2 "--read-log: only --bvh, --leaf-size, --json and --quiet apply" -- "$bin" interior --read-log x --image "$tmp/a.png"
fi
# no output of a failed run stays behind (the view is checked after the output paths)
"$bin" interior --res $res --view nosuchview --log "$tmp/fail.tlog" --json "$tmp/fail.json" --image "$tmp/fail.png" >/dev/null 2>&1
if ls -A "$tmp" | grep -q fail; then fail rttrace_no_partial_output "$(ls -A "$tmp")"; else pass rttrace_no_partial_output; fi

# check_json FILE RAYTYPE PIXELS: python3 asserts on the statistics
check_json() {
  python3 - "$1" "$2" "$3" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
kind, pixels = sys.argv[2], int(sys.argv[3])
need = ("rays embree_mismatches node_visits box_tests triangle_tests node_visits_per_ray box_tests_per_ray "
        "triangle_tests_per_ray log_bytes log_bytes_per_node_visit bvh_build_s bvh_inner_nodes bvh_leaves "
        "bvh_sah_cost wall_s trace_s embree_rays primary_rays bounce_rays hits").split()
missing = [k for k in need if k not in d]
assert not missing, missing
assert d["embree_checked"] == 1 and d["embree_rays"] == d["rays"], d
assert d["embree_mismatches"] == 0, ("embree mismatches", d)
assert d["primary_rays"] == pixels, d
if kind == "primary":
    assert d["rays"] == pixels and d["bounce_rays"] == 0, d
else:
    assert d["rays"] == d["primary_rays"] + d["bounce_rays"] and d["bounce_rays"] > 0, d
assert d["node_visits"] >= d["rays"], d             # every ray visits the root
assert d["box_tests"] >= 2 * d["node_visits"], d     # >= 2 used slots per node
assert abs(d["node_visits_per_ray"] - d["node_visits"] / d["rays"]) < 1e-6 * d["node_visits_per_ray"], d
assert 0 < d["log_bytes_per_node_visit"] <= 2.0, d
assert abs(d["log_bytes_per_node_visit"] - d["log_bytes"] / d["node_visits"]) < 1e-6, d
assert d["stack_overflows"] == 0 and d["hits"] <= d["rays"], d
EOF
}

w=${res%x*}; h=${res#*x}; pixels=$((w * h))
nscenes=0
for scene in $scenes; do
  nscenes=$((nscenes + 1))
  for rays in primary diffuse; do
    name=rttrace_${scene}_${rays}
    out=$("$bin" "$scene" --res $res --rays $rays --check-embree --log "$tmp/$name.tlog" \
          --image "$tmp/$name.png" --heatmap-visits "$tmp/$name.visits.exr" --heatmap-tris "$tmp/$name.tris.png" \
          --json "$tmp/$name.json" 2>&1)
    rc=$?
    if [ $rc -ne 0 ]; then fail "$name" "exit $rc: $(echo "$out" | tail -3 | tr '\n' ' ')"; continue; fi
    if msg=$(check_json "$tmp/$name.json" $rays $pixels 2>&1); then pass "${name}_json"; else fail "${name}_json" "$(echo "$msg" | tail -1)"; fi
    # the summary names the essentials
    if echo "$out" | grep -q "^embree .* 0 mismatches" && echo "$out" | grep -q "bytes per node visit"; then
      pass "${name}_summary"; else fail "${name}_summary" "$(echo "$out" | tr '\n' '|')"; fi
    # the log re-read (diffuse paths, and the primary rays of one scene): same totals
    [ $rays = primary ] && [ $scene != city ] && continue
    "$bin" "$scene" --read-log "$tmp/$name.tlog" --json "$tmp/$name.read.json" --quiet
    rc=$?
    if [ $rc -eq 0 ] && python3 - "$tmp/$name.json" "$tmp/$name.read.json" <<'EOF'
import json, sys
a, b = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
for k in ("rays", "hits", "node_visits", "triangle_tests", "stack_pushes", "stack_pops", "stack_culls", "log_bytes", "bvh_image_hash"):
    assert a[k] == b[k], (k, a[k], b[k])
EOF
    then pass "${name}_read_log"; else fail "${name}_read_log" "exit $rc or totals differ"; fi
  done
done

# images: readable, of the requested size (PNG via python's zlib-free header read; EXR magic)
python3 - "$tmp" $w $h $nscenes <<'EOF' && pass rttrace_images_valid || fail rttrace_images_valid "bad image"
import struct, sys, glob
d, w, h, n = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
pngs = glob.glob(d + "/rttrace_*.png")
assert len(pngs) == 4 * n, len(pngs)
for p in pngs:
    b = open(p, "rb").read()
    assert b[:8] == b"\x89PNG\r\n\x1a\n", p
    assert struct.unpack(">II", b[16:24]) == (w, h), (p, b[16:24])
exrs = glob.glob(d + "/rttrace_*.exr")
assert len(exrs) == 2 * n, len(exrs)
for p in exrs:
    assert open(p, "rb").read(4) == b"\x76\x2f\x31\x01", p
EOF

# the log rejected when corrupted, truncated, or read against another BVH
log=$tmp/rttrace_city_diffuse.tlog
size=$(stat -c %s "$log")
cp "$log" "$tmp/flip.tlog"
printf '\xff' | dd of="$tmp/flip.tlog" bs=1 seek=$((size / 2)) conv=notrunc status=none
expect rttrace_read_log_corrupt 2 "flip.tlog: byte " -- "$bin" city --read-log "$tmp/flip.tlog" --quiet
head -c $((size - 50)) "$log" > "$tmp/trunc.tlog"
expect rttrace_read_log_truncated 2 "trunc.tlog: byte " -- "$bin" city --read-log "$tmp/trunc.tlog" --quiet
expect rttrace_read_log_other_bvh 2 "hash" -- "$bin" city --read-log "$log" --leaf-size 2 --quiet
expect rttrace_read_log_other_scene 2 "hash" -- "$bin" interior --read-log "$log" --quiet
expect rttrace_read_log_not_a_log 2 "not a trace log" -- "$bin" city --read-log "$tmp/rttrace_city_diffuse.json" --quiet

# determinism: identical logs, images and counts
run2() { "$bin" hairball --res $res --rays diffuse --bvh bvh2 --seed 7 --log "$tmp/det$1.tlog" --image "$tmp/det$1.exr" \
         --heatmap-tris "$tmp/det$1.tris.exr" --json "$tmp/det$1.json" --quiet; }
run2 1; run2 2
if cmp -s "$tmp/det1.tlog" "$tmp/det2.tlog" && cmp -s "$tmp/det1.exr" "$tmp/det2.exr" && \
   cmp -s "$tmp/det1.tris.exr" "$tmp/det2.tris.exr" && python3 - "$tmp/det1.json" "$tmp/det2.json" <<'EOF'
import json, sys
a, b = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
timing = {k for k in a if k.endswith("_s") or k.endswith("_per_s")} | {"run"}
assert {k: v for k, v in a.items() if k not in timing} == {k: v for k, v in b.items() if k not in timing}
EOF
then pass rttrace_deterministic; else fail rttrace_deterministic "outputs differ between two runs"; fi
# a different seed changes the diffuse paths
"$bin" hairball --res $res --rays diffuse --bvh bvh2 --seed 8 --log "$tmp/det3.tlog" --quiet
if cmp -s "$tmp/det1.tlog" "$tmp/det3.tlog"; then fail rttrace_seed_matters "seed 7 and 8 gave the same log"; else pass rttrace_seed_matters; fi

# exit 1 on a validation failure: rays overflowing a 2-entry stack; the outputs
# are still written (they are valid), and the log still reads back
expect rttrace_stack_overflow_exit1 1 "rays overflowed the 2-entry stack" -- "$bin" interior --res 16x9 --stack-depth 2 --log "$tmp/over.tlog"
expect rttrace_stack_overflow_log_valid 0 "overflows" -- "$bin" interior --read-log "$tmp/over.tlog"
expect rttrace_bad_stack_depth 2 "--stack-depth: '0' is not an integer in 1..4096" -- "$bin" interior --stack-depth 0
expect rttrace_rate_zero_clean_run 0 "0 mismatches" -- "$bin" interior --res 16x9 --check-embree --max-mismatch-rate 0

# no temporary files left behind
if ls -A "$tmp" | grep -q '\.tmp'; then fail rttrace_no_temp_files "$(ls -A "$tmp" | grep '\.tmp')"; else pass rttrace_no_temp_files; fi
rm -rf "$tmp"
