#!/usr/bin/env bash
# tb_energy_cli — energy, power and area in rtsim's summary and JSON
# (docs/energy.md): the figures of merit and the per-unit splits are present
# with units, add up, follow the definitions (power = energy / frame time,
# MRPS/mm2 = MRPS / area), repeat bit for bit, and a machine the SRAM table
# cannot cover, or a missing table, is refused at start-up naming the key.
set -u
bin=${RTSIM_BIN:?}/rtsim
tmp=${RTSIM_TMP:-/tmp}/tb_energy_cli
rm -rf "$tmp"; mkdir -p "$tmp"
. "$(dirname "$0")/../cli_lib.sh"

run=(interior --res 16x9 --quiet)
"$bin" "${run[@]}" --json "$tmp/a.json" >"$tmp/a.txt" 2>&1
"$bin" "${run[@]}" --json "$tmp/b.json" >/dev/null 2>&1
"$bin" interior --res 16x9 --machine bvh2 --rays diffuse --bounces 1 --json "$tmp/c.json" >"$tmp/c.txt" 2>&1

check_json() { # file
  python3 - "$1" <<'PY'
import json, math, sys
d = json.load(open(sys.argv[1]))
units = ["trv", "ist", "stack", "cache", "fifo", "dram"]
need = {"energy_mj": "mJ", "power_mw": "mW", "area_mm2": "mm2", "mrps_per_mm2": "MRPS/mm2"}
for u in units:
    need["energy.%s_mj" % u] = "mJ"
    need["energy.%s_dynamic_mj" % u] = "mJ"
    need["energy.%s_static_mj" % u] = "mJ"
    need["power.%s_mw" % u] = "mW"
    need["area.%s_mm2" % u] = "mm2"
for k, unit in need.items():
    assert k in d, "missing " + k
    assert d["_units"].get(k) == unit, "unit of %s: %s" % (k, d["_units"].get(k))
    assert d["_descriptions"].get(k), "no description for " + k
close = lambda a, b: math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12)
assert close(d["energy_mj"], sum(d["energy.%s_mj" % u] for u in units)), "energy sum"
assert close(d["area_mm2"], sum(d["area.%s_mm2" % u] for u in units)), "area sum"
for u in units:
    assert close(d["energy.%s_mj" % u], d["energy.%s_dynamic_mj" % u] + d["energy.%s_static_mj" % u]), u
    assert d["energy.%s_static_mj" % u] >= 0 and d["energy.%s_dynamic_mj" % u] >= 0, u
secs = d["cycles"] / 500e6
assert close(d["power_mw"], d["energy_mj"] / secs), "power"
assert close(d["mrps_per_mm2"], d["mrps"] / d["area_mm2"]), "MRPS/mm2"
assert d["area.dram_mm2"] == 0 and d["energy.dram_mj"] > 0 and d["energy.trv_dynamic_mj"] > 0
# per-bank stack counters add up to the unit's pushes and pops; FIFO counters exist
for t in range(4):
    w = sum(v for k, v in d.items() if k.startswith("trv%d.stack_bank" % t) and k.endswith("_writes"))
    r = sum(v for k, v in d.items() if k.startswith("trv%d.stack_bank" % t) and k.endswith("_reads"))
    assert w == d["trv%d.stack_pushes" % t] and r == d["trv%d.stack_pops" % t], t
    assert 1 <= d["trv%d.stack_max_depth" % t] <= 64
assert d["fifo.trv0.new.writes"] > 0 and d["fifo.trv0.new.reads"] == d["fifo.trv0.new.writes"]
PY
}
check energy_cli_json_keys_units_sums check_json "$tmp/a.json"
check energy_cli_json_bvh2_diffuse check_json "$tmp/c.json"
check energy_cli_deterministic cmp -s <(grep -v '"run"' "$tmp/a.json" | grep -E '"(energy|power|area|mrps)') \
  <(grep -v '"run"' "$tmp/b.json" | grep -E '"(energy|power|area|mrps)')
check energy_cli_summary_lines grep -qE '^energy +[0-9.e+-]+ mJ/frame: trv .* dram ' "$tmp/c.txt"
check energy_cli_summary_area grep -qE '^area +[0-9.]+ mm2: trv .*MRPS/mm2' "$tmp/c.txt"
expect energy_cli_help_module 0 "fifo_ray_bytes" -- "$bin" --help-module energy
expect energy_cli_no_figure_refused 2 "no SRAM figure" -- "$bin" "${run[@]}" --set node_l1.ways=2 --json "$tmp/x.json"
check energy_cli_no_figure_no_json test ! -e "$tmp/x.json"
expect energy_cli_disabled_runs 0 "cycles" -- "$bin" interior --res 16x9 --set node_l1.ways=2 --set energy.enabled=false
expect energy_cli_missing_table 2 "energy.sram_table" -- "$bin" "${run[@]}" --set energy.sram_table=/nonexistent/sram.ini
expect energy_cli_range 2 "energy.fifo_ray_bytes" -- "$bin" "${run[@]}" --set energy.fifo_ray_bytes=0
