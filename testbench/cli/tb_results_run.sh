#!/usr/bin/env bash
# tb_results_run — the provenance ("run" object) of every result JSON, and
# docs/results.md as the one place that documents the keys (cli/run_info.h):
#  - rtsim (primary and diffuse, with --views), rttrace (tracing and
#    --read-log) and rtdram write "run" first, with every key of the run table
#    of docs/results.md and no other, with the right types and values (the
#    command line as given, the 16-hex-digit hashes, the ISO 8601 date, null
#    exactly where the tool has no such value), and the commit and dirty flag
#    of the build (build/version.stamp);
#  - every result key of rttrace and rtdram is in their tables there, every
#    documented key is written, and every rtsim statistic has its unit and
#    description in the file (_units, _descriptions);
#  - the hashes: the same mesh gives the same mesh_hash in rtsim and rttrace;
#    the same configuration the same config_hash however it is written (16K or
#    16384), a changed key (also a DRAM key) another.
set -u
bin=${RTSIM_BIN:?}
tmp=${RTSIM_TMP:-/tmp}/tb_results_run
rm -rf "$tmp"; mkdir -p "$tmp"
. "$(dirname "$0")/../cli_lib.sh"
doc=docs/results.md

run_ok() { # NAME command...: runs, fails the case NAME on a non-zero exit
  local name=$1; shift
  if ! "$@" >"$tmp/$name.out" 2>&1; then fail "$name" "exit $?: $(head -3 "$tmp/$name.out" | tr '\n' ' ')"; return 1; fi
}

echo 'view side eye -17 2.5 -7.5 at 15 3 -7 up 0 1 0 fov 55' > "$tmp/views.txt"
printf '0x0 R\n0x40 R\n0x100000 W\n0x2000 R\n' > "$tmp/t.trace"
ok=1
run_ok results_rtsim_primary "$bin/rtsim" interior --res 16x8 --quiet --json "$tmp/sim_p.json" || ok=0
run_ok results_rtsim_diffuse "$bin/rtsim" interior --res 8x4 --rays diffuse --bounces 2 --seed 9 \
  --views "$tmp/views.txt" --view side --quiet --json "$tmp/sim_d.json" || ok=0
run_ok results_rtsim_16k "$bin/rtsim" interior --res 16x8 --quiet --set node_l1.size=16384 --json "$tmp/sim_16k.json" || ok=0
run_ok results_rtsim_trv "$bin/rtsim" interior --res 16x8 --quiet --set trv.count=2 --json "$tmp/sim_trv.json" || ok=0
run_ok results_rtsim_dram "$bin/rtsim" interior --res 16x8 --quiet --set dram.timing.nRCD=16 --json "$tmp/sim_dram.json" || ok=0
run_ok results_rttrace "$bin/rttrace" interior --res 16x8 --rays diffuse --quiet --log "$tmp/t.tlog" --json "$tmp/tr.json" || ok=0
run_ok results_rttrace_read "$bin/rttrace" interior --read-log "$tmp/t.tlog" --quiet --json "$tmp/tr_read.json" || ok=0
if "$bin/rtdram" "$tmp/t.trace" --json > "$tmp/dram.json" 2>"$tmp/dram.err" &&
   "$bin/rtdram" "$tmp/t.trace" --json --set timing.nCL=14 > "$tmp/dram_cl.json" 2>>"$tmp/dram.err"; then :
else fail results_rtdram "$(head -3 "$tmp/dram.err" | tr '\n' ' ')"; ok=0; fi
[ $ok = 1 ] || { rm -rf "$tmp"; exit 0; }

stamp=$bin/../version.stamp
out=$(python3 - "$tmp" "$doc" "$stamp" "$bin" <<'PY' 2>&1
import json, os, re, sys
tmp, doc, stamp, bindir = sys.argv[1:5]
fails = []
def check(name, cond, why):
    print(("PASS %s" % name) if cond else ("FAIL %s: %s" % (name, why)))

# the tables of docs/results.md, by section: first-column `key`s
sections, cur = {}, None
for line in open(doc):
    if line.startswith("## "):
        cur = line[3:].strip().strip("`").split("`")[0].strip()
        cur = {"The": "run"}.get(cur.split()[0], cur)
        sections.setdefault(cur, set())
    elif line.startswith("| `") and cur:
        first = line.split("|")[1]
        sections[cur].update(re.findall(r"`([A-Za-z0-9_]+)`", first))
run_doc, tr_doc, dram_doc = sections.get("run", set()), sections.get("rttrace", set()), sections.get("rtdram", set())
check("results_doc_tables", len(run_doc) >= 20 and len(tr_doc) >= 40 and len(dram_doc) >= 25,
      "tables not found: run %d, rttrace %d, rtdram %d keys" % (len(run_doc), len(tr_doc), len(dram_doc)))

def load(name):
    with open(os.path.join(tmp, name)) as f:
        text = f.read()
    return json.loads(text), text
files = {n: load(n + ".json") for n in ("sim_p", "sim_d", "sim_16k", "sim_trv", "sim_dram", "tr", "tr_read", "dram", "dram_cl")}
hexre, datere = re.compile(r"^[0-9a-f]{16}$"), re.compile(r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ$")
commit, dirty = None, None
if os.path.exists(stamp):
    c, d = open(stamp).read().split()
    commit, dirty = c, {"1": True, "0": False}.get(d)

# run: first, exactly the documented keys, types
for n, (d, text) in files.items():
    r = d.get("run")
    why = []
    if not isinstance(r, dict):
        why.append("no run object")
    else:
        if next(iter(d)) != "run":
            why.append("run is not the first member")
        extra, missing = set(r) - run_doc, run_doc - set(r)
        if extra: why.append("undocumented run keys %s" % sorted(extra))
        if missing: why.append("documented but not written %s" % sorted(missing))
        if not (isinstance(r.get("command_line"), list) and all(isinstance(a, str) for a in r["command_line"])):
            why.append("command_line %r" % r.get("command_line"))
        if not datere.match(str(r.get("date"))): why.append("date %r" % r.get("date"))
        if not hexre.match(str(r.get("config_hash"))): why.append("config_hash %r" % r.get("config_hash"))
        if r.get("mesh_hash") is not None and not hexre.match(r["mesh_hash"]): why.append("mesh_hash %r" % r["mesh_hash"])
        for k in ("host_cpu_s", "host_wall_s", "sim_cpu_s", "sim_wall_s"):
            if not (isinstance(r.get(k), (int, float)) and r[k] >= 0): why.append("%s %r" % (k, r.get(k)))
        if r.get("version") is None or not isinstance(r.get("commit"), str): why.append("version/commit")
        if commit is not None and (r.get("commit") != commit or r.get("dirty") != dirty):
            why.append("commit %r dirty %r, build stamp says %s %s" % (r.get("commit"), r.get("dirty"), commit, dirty))
        if r.get("cwd") != os.getcwd(): why.append("cwd %r" % r.get("cwd"))
    check("results_run_keys_%s" % n, not why, "; ".join(why))

# values per tool
def expect(name, r, want):
    bad = ["%s = %r, expected %r" % (k, r.get(k), v) for k, v in want.items() if r.get(k) != v]
    check(name, not bad, "; ".join(bad))
p, dd = files["sim_p"][0]["run"], files["sim_d"][0]["run"]
expect("results_run_rtsim_primary", p, {"tool": "rtsim", "scene": "interior", "views_file": None, "view": "hall",
       "trace": None, "machine": "mbvh4", "width_px": 16, "height_px": 8, "ray_type": "primary", "bounces": None,
       "seed": None})
check("results_run_rtsim_command_line", p["command_line"][1:] == ["interior", "--res", "16x8", "--quiet", "--json", tmp + "/sim_p.json"]
      and p["command_line"][0].endswith("rtsim"), "command_line %r" % p["command_line"])
check("results_run_rtsim_cycles_per_s", p["cycles_per_host_s"] and p["sim_cpu_s"] > 0
      and abs(p["cycles_per_host_s"] * p["sim_cpu_s"] - files["sim_p"][0]["cycles"]) <= 1e-3 * files["sim_p"][0]["cycles"] + 1,
      "cycles_per_host_s %r x sim_cpu_s %r != cycles %r" % (p["cycles_per_host_s"], p["sim_cpu_s"], files["sim_p"][0]["cycles"]))
expect("results_run_rtsim_diffuse", dd, {"views_file": tmp + "/views.txt", "view": "side", "width_px": 8, "height_px": 4,
       "ray_type": "diffuse", "bounces": 2, "seed": 9})
t, tread = files["tr"][0]["run"], files["tr_read"][0]["run"]
expect("results_run_rttrace", t, {"tool": "rttrace", "scene": "interior", "view": "hall", "machine": None, "trace": None,
       "width_px": 16, "height_px": 8, "ray_type": "diffuse", "bounces": 4, "seed": 1, "cycles_per_host_s": None,
       "mesh_hash": files["tr"][0]["mesh_hash"]})
expect("results_run_rttrace_read_log", tread, {"trace": tmp + "/t.tlog", "view": None, "width_px": 16, "height_px": 8,
       "ray_type": "diffuse", "bounces": 4, "seed": 1, "config_hash": t["config_hash"]})
r = files["dram"][0]["run"]
expect("results_run_rtdram", r, {"tool": "rtdram", "scene": None, "views_file": None, "view": None, "mesh_hash": None,
       "trace": tmp + "/t.trace", "width_px": None, "height_px": None, "ray_type": None, "bounces": None, "seed": None})
check("results_run_rtdram_machine", str(r.get("machine")).endswith("lpddr3_1600.ini") and r["cycles_per_host_s"] > 0,
      "machine %r, cycles_per_host_s %r" % (r.get("machine"), r.get("cycles_per_host_s")))
check("results_run_rtdram_one_line", files["dram"][1].count("\n") == 1, "rtdram --json is no longer one line")

# hashes
check("results_mesh_hash_same_in_rtsim_and_rttrace", p["mesh_hash"] == t["mesh_hash"] == tread["mesh_hash"],
      "%s %s %s" % (p["mesh_hash"], t["mesh_hash"], tread["mesh_hash"]))
h = {n: files[n][0]["run"]["config_hash"] for n in ("sim_p", "sim_16k", "sim_trv", "sim_dram", "dram", "dram_cl")}
check("results_config_hash_canonical", h["sim_p"] == h["sim_16k"], "16K and 16384 hash differently: %s" % h)
check("results_config_hash_changes", len({h["sim_p"], h["sim_trv"], h["sim_dram"]}) == 3 and h["dram"] != h["dram_cl"],
      "a changed key keeps the hash: %s" % h)

# the tools' own keys
tr_keys = set(files["tr"][0]) | set(files["tr_read"][0])
tr_keys.discard("run")
check("results_rttrace_keys_documented", tr_keys <= tr_doc and tr_doc <= tr_keys,
      "undocumented %s; documented, not written %s" % (sorted(tr_keys - tr_doc), sorted(tr_doc - tr_keys)))
dram_keys = set(files["dram"][0]) - {"run"}
check("results_rtdram_keys_documented", dram_keys == dram_doc,
      "undocumented %s; documented, not written %s" % (sorted(dram_keys - dram_doc), sorted(dram_doc - dram_keys)))
sim = files["sim_p"][0]
stats = [k for k in sim if not k.startswith("_") and k != "run" and not isinstance(sim[k], str)]
bad = [k for k in stats if k not in sim["_units"] or k not in sim["_descriptions"]]
check("results_rtsim_stats_self_described", len(stats) > 100 and not bad, "%d stats; without unit/description: %s" % (len(stats), bad[:5]))
PY
)
echo "$out" | grep -E '^(PASS|FAIL|SKIP) ' || fail results_run_checks "$(echo "$out" | tail -3 | tr '\n' ' ')"
echo "$out" | grep -vE '^(PASS|FAIL|SKIP) ' >&2
rm -rf "$tmp"
