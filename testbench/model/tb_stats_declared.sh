#!/usr/bin/env bash
# tb_stats_declared — one description per unit is the source of its
# statistics (docs/design.md, "Conventions of the model"): every statistic in
# rtsim's JSON is declared in the description of the unit that owns it (with
# that description's unit and text), every declared statistic is registered
# by some run (LPDDR3 and fixed memory, both machines, occlusion rays), and --help-module
# prints exactly those declarations. Declared names may use '#' (digits) and
# '*' ([a-z0-9_]+), as kernel/stats.h says.
set -u
bin=${RTSIM_BIN:?}/rtsim
tmp=${RTSIM_TMP:-/tmp}/tb_stats_declared
rm -rf "$tmp"; mkdir -p "$tmp"
. "$(dirname "$0")/../cli_lib.sh"

"$bin" interior --res 8x8 --machine mbvh4 --quiet --json "$tmp/lpddr3.json" >/dev/null 2>&1
"$bin" interior --res 8x8 --machine bvh2 --set memory.model=fixed --quiet --json "$tmp/fixed.json" >/dev/null 2>&1
"$bin" interior --res 8x8 --rays occlusion --quiet --json "$tmp/occlusion.json" >/dev/null 2>&1
modules="accel energy fidelity sched trv ist fifo cache arbiter fixed_mem dram_adapter dram memory_side"
for m in $modules; do "$bin" --help-module "$m" > "$tmp/help-$m.txt" 2>&1; done

python3 - "$tmp" $modules <<'PY'
import json, re, sys
tmp, modules = sys.argv[1], sys.argv[2:]
# declared statistics as --help-module prints them: name, unit, description
decl = {}
for m in modules:
    lines = open("%s/help-%s.txt" % (tmp, m)).read().split("\n")
    items, on = [], False
    for ln in lines:
        if ln.startswith("  Statistics"):
            on = True
            continue
        if on and not ln.startswith("    "):
            on = False
        if on:
            name, unit, desc = re.match(r"^    (\S+)\s+(\S+)\s+(.*)$", ln).groups()
            items.append((name, unit, desc))
    decl[m] = items
def rx(pattern):
    return re.compile("^" + re.escape(pattern).replace(r"\#", r"\d+").replace(r"\*", r"[a-z0-9_]+") + "$")
def owner(key, memory_module):
    """(module, name within the module) of a statistic's full name."""
    if key in ("node_l1.hit_rate", "memory.bytes_total"):
        return "memory_side", key
    if key in ("fidelity_level", "unreliable") or key.startswith("error_estimate."):
        return "fidelity", key
    if re.match(r"^(energy|power|area)\.", key) or key in ("energy_mj", "power_mw", "area_mm2", "mrps_per_mm2"):
        return "energy", key
    if "." not in key:
        return "accel", key
    if key.startswith("fifo."):
        return "fifo", key.rsplit(".", 1)[1]
    scope, name = key.split(".", 1)
    for pre, mod in (("trv", "trv"), ("ist", "ist"), ("sched", "sched"), ("node_l1_", "cache"),
                     ("node_l2", "cache"), ("prim", "cache"), ("l2_arbiter", "arbiter"),
                     ("mem_arbiter", "arbiter"), ("dram", "dram"), ("memory", memory_module)):
        if scope.startswith(pre):
            return mod, name
    return None, key
bad, used = [], set()
for run, memory_module in (("lpddr3", "dram_adapter"), ("fixed", "fixed_mem"), ("occlusion", "dram_adapter")):
    d = json.load(open("%s/%s.json" % (tmp, run)))
    for key in d:
        if key.startswith("_") or key == "run" or isinstance(d[key], str):   # fidelity's strings
            continue
        mod, name = owner(key, memory_module)
        hit = [it for it in decl.get(mod, []) if rx(it[0]).match(name)]
        if not hit:
            bad.append("%s (%s): not declared in module %s" % (key, run, mod))
            continue
        used.add((mod, hit[0][0]))
        if d["_units"][key] != hit[0][1]:
            bad.append("%s: unit %s, declared %s" % (key, d["_units"][key], hit[0][1]))
for m in modules:
    for it in decl[m]:
        if (m, it[0]) not in used:
            bad.append("%s.%s: declared but registered by no run" % (m, it[0]))
for b in bad[:20]:
    print("  " + b)
sys.exit(1 if bad else 0)
PY
rc=$?
check stats_declared_equal_registered test $rc -eq 0
check stats_declared_modules_have_tables sh -c 'd=$1; shift; for m; do grep -q Statistics "$d/help-$m.txt" || exit 1; done' _ "$tmp" $modules

# Parameters are written once, in the schema of a configuration section
# (docs/design.md, "Adding a unit"): a module's --help-module names its
# sections and prints their keys from the schema, and no module repeats a
# configuration key in a table of its own.
python3 - "$tmp" $modules <<'PY'
import re, sys
tmp, modules = sys.argv[1], sys.argv[2:]
bad, keys, own = [], set(), {}
for m in modules:
    text = open("%s/help-%s.txt" % (tmp, m)).read()
    shown = set(re.findall(r"^Configuration keys \[(\w+)\]:", text, re.M))
    keys |= set(re.findall(r"^  (\w+\.\w+(?:\.\w+)?)\s", text, re.M))
    named = re.search(r"^  Parameters: the configuration keys of (.*) \(below", text, re.M)
    for sec in re.findall(r"\[(\w+)\]", named.group(1)) if named else []:
        if sec not in shown:
            bad.append("%s names [%s] but does not print its keys" % (m, sec))
    block = re.search(r"^  Parameters \(--set[^\n]*\n((?:    [^\n]*\n)*)", text, re.M)
    own[m] = re.findall(r"^    (\S+)", block.group(1), re.M) if block else []
for m in modules:
    for name in own[m]:
        if name in keys:
            bad.append("%s: parameter %s repeats a configuration key" % (m, name))
for b in bad[:20]:
    print("  " + b)
sys.exit(1 if bad else 0)
PY
check params_written_once_in_schemas test $? -eq 0
