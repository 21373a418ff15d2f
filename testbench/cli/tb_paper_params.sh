#!/usr/bin/env bash
# tb_paper_params — the choices the paper leaves open, as machine keys
# (docs/paper.md): each changes what it should and is refused out of range,
# and the DRAM traffic statistics that explain them add up.
#   sched.pixel_order / sched.tile: tiles and Morton order lower primary
#     rays' DRAM traffic (refetches) on a built-in scene whose caches are
#     small against a scanline; the footprint stays the same;
#   bvh.builder = wald: fewer, fuller MBVH4 nodes than the collapse;
#   energy.sram_table: the low-operating-power cells lower cache and stack
#     power against the itrs-hp default, the same run otherwise;
#   dram_node_bytes + dram_triangle_bytes = dram_bytes; footprint +
#     refetched = dram_bytes; first-touch + refetch fills = memory grants.
set -u
bin=${RTSIM_BIN:?}/rtsim
tmp=${RTSIM_TMP:-/tmp}/tb_paper_params
rm -rf "$tmp"; mkdir -p "$tmp"

. "$(dirname "$0")/../cli_lib.sh"

# interior at 160x90 with caches a 16th of the paper's: a scanline of rays
# outgrows them, a tile does not
small=(interior --res 160x90 --set node_l1.size=4K --set node_l2.size=16K --set prim.size=16K)
ok=1
for o in scanline tiles morton; do
  "$bin" "${small[@]}" --set sched.pixel_order=$o --set sched.tile=8 --json "$tmp/$o.json" >"$tmp/$o.out" 2>&1 || ok=0
done
if [ $ok -eq 1 ] && python3 - "$tmp" <<'PY'
import json, sys
t = sys.argv[1]
d = {o: json.load(open(f"{t}/{o}.json")) for o in ("scanline", "tiles", "morton")}
s, ti, m = d["scanline"], d["tiles"], d["morton"]
assert ti["dram_bytes"] < 0.8 * s["dram_bytes"], (ti["dram_bytes"], s["dram_bytes"])
assert m["dram_bytes"] < 0.8 * s["dram_bytes"], (m["dram_bytes"], s["dram_bytes"])
assert s["dram_footprint_bytes"] == ti["dram_footprint_bytes"] == m["dram_footprint_bytes"]
assert s["rays"] == ti["rays"] == m["rays"]
PY
then pass paper_pixel_order_tiles_and_morton_lower_primary_traffic
else fail paper_pixel_order_tiles_and_morton_lower_primary_traffic "$(tail -3 "$tmp/scanline.out" 2>/dev/null)"; fi

if [ $ok -eq 1 ] && python3 - "$tmp" <<'PY'
import json, sys
for o in ("scanline", "tiles", "morton"):
    d = json.load(open(f"{sys.argv[1]}/{o}.json"))
    total = d["dram_bytes"]
    assert d["dram_node_bytes"] + d["dram_triangle_bytes"] == total, o
    assert d["dram_footprint_bytes"] + d["dram_refetch_bytes"] == total, o
    assert d["dram_compulsory_misses"] + d["dram_refetch_misses"] == d["mem_arbiter.grants"], o
    assert d["dram_refetch_bytes"] > 0 and d["dram_footprint_bytes"] > 0, o
    assert abs(d["dram_pj_per_byte"] - d["energy.dram_mj"] * 1e9 / total) < 1e-6 * d["dram_pj_per_byte"], o
    for k in ("dram_footprint_bytes", "dram_refetch_misses", "dram_pj_per_byte"):
        assert d["_units"][k] and d["_descriptions"][k], k
PY
then pass paper_traffic_statistics_add_up
else fail paper_traffic_statistics_add_up "node + triangle, footprint + refetch or fills do not add up"; fi
expect paper_traffic_summary_line 0 "footprint" -- cat "$tmp/tiles.out"

# caches of 1 MB (8x the paper's) hold this small frame whole: no refetch
# (the default 4-way 128 KB ones may already evict a line or two by
# conflict); no SRAM figure covers them, so without energy
"$bin" interior --res 32x18 --quiet --set node_l2.size=1M --set prim.size=1M --set energy.enabled=false \
  --json "$tmp/tiny.json" >/dev/null 2>&1
if python3 -c "import json,sys; d=json.load(open(sys.argv[1] + '/tiny.json')); sys.exit(0 if d['dram_refetch_bytes']==0 and d['dram_footprint_bytes']==d['dram_bytes'] else 1)" "$tmp"; then
  pass paper_traffic_no_refetch_when_the_frame_fits
else fail paper_traffic_no_refetch_when_the_frame_fits "refetches on a 32x18 frame"; fi

# the top-down splitting builder: fewer MBVH4 nodes, same rays
"$bin" interior --res 64x36 --rays diffuse --set bvh.builder=collapse --json "$tmp/bc.json" >"$tmp/bc.out" 2>&1
"$bin" interior --res 64x36 --rays diffuse --set bvh.builder=wald --json "$tmp/bw.json" >"$tmp/bw.out" 2>&1
nc=$(sed -n 's/^BVH *\([0-9]*\) nodes.*/\1/p' "$tmp/bc.out"); nw=$(sed -n 's/^BVH *\([0-9]*\) nodes.*/\1/p' "$tmp/bw.out")
if [ -n "$nc" ] && [ -n "$nw" ] && [ "$nw" -lt "$nc" ] &&
   python3 -c "import json,sys; a=json.load(open(sys.argv[1] + '/bc.json')); b=json.load(open(sys.argv[1] + '/bw.json')); sys.exit(0 if a['sched.primaries']==b['sched.primaries'] and a['run_failed']==0==b['run_failed'] else 1)" "$tmp"; then
  pass paper_builder_wald_fewer_nodes
else fail paper_builder_wald_fewer_nodes "collapse '$nc' nodes, wald '$nw'"; fi

# SRAM cells: lop against the itrs-hp table, the same run
"$bin" interior --res 32x18 --quiet --set energy.sram_table=sram_45nm.ini --json "$tmp/hp.json" >/dev/null 2>&1
"$bin" interior --res 32x18 --quiet --set energy.sram_table=sram_45nm_lop.ini --json "$tmp/lop.json" >/dev/null 2>&1
if python3 - "$tmp" <<'PY'
import json, sys
a = json.load(open(f"{sys.argv[1]}/hp.json")); b = json.load(open(f"{sys.argv[1]}/lop.json"))
assert a["cycles"] == b["cycles"] and a["dram_bytes"] == b["dram_bytes"]
assert b["energy.cache_static_mj"] < 0.05 * a["energy.cache_static_mj"]
assert b["energy.stack_mj"] < a["energy.stack_mj"] and b["energy_mj"] < a["energy_mj"]
PY
then pass paper_sram_table_lop_lowers_leakage
else fail paper_sram_table_lop_lowers_leakage "lop did not lower cache leakage"; fi

# out of range: named key, allowed range or choices, exit 2
expect paper_tile_zero_refused 2 "sched.tile" -- "$bin" interior --res 8x8 --set sched.tile=0
expect paper_tile_range_named 2 "1..65535" -- "$bin" interior --res 8x8 --set sched.tile=65536
expect paper_order_unknown_refused 2 "scanline|tiles|morton" -- "$bin" interior --res 8x8 --set sched.pixel_order=spiral
expect paper_builder_unknown_refused 2 "collapse|wald" -- "$bin" interior --res 8x8 --set bvh.builder=sah8
expect paper_leaf_size_refused 2 "bvh.leaf_size" -- "$bin" interior --res 8x8 --set bvh.leaf_size=0
expect paper_cost_refused 2 "bvh.cost_node" -- "$bin" interior --res 8x8 --set bvh.cost_node=-1
