#!/usr/bin/env bash
# tb_occlusion_cli — occlusion rays from the command line (docs/accel.md
# "Occlusion rays"): `rttrace --rays occlusion --check-embree` on the built-in
# scenes (every occlusion ray's answer equals rtcOccluded1's: 0 mismatches,
# 0 unexplained; JSON counts consistent); --log refused with occlusion rays;
# `rtsim --rays occlusion` on both machines runs exactly rttrace's occlusion
# rays (same count, same occluded count), with no sort pass; both tools are
# deterministic (same JSON twice, host timings aside).
set -u
tr=${RTSIM_BIN:?}/rttrace
sim=${RTSIM_BIN:?}/rtsim
tmp=${RTSIM_TMP:-/tmp}/tb_occlusion_cli
rm -rf "$tmp"; mkdir -p "$tmp"
res=48x27 scenes="interior hairball city forest"
[ -n "${RTSIM_TB_SANITIZED:-}" ] && res=16x9 scenes="interior city"

. "$(dirname "$0")/../cli_lib.sh"

expect occlusion_rttrace_no_log 2 "--log: not with --rays occlusion" -- "$tr" interior --rays occlusion --log "$tmp/x.tlog"
expect occlusion_rtsim_bad_rays 2 "allowed values are primary, diffuse, occlusion" -- "$sim" interior --rays shadow

# json_get FILE KEY -> value
json_get() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])' "$1" "$2"; }

for scene in $scenes; do
  # the primary rays' closest hits may tie on a shared edge (docs/tracer-bvh.md):
  # the allowed rate is for them; the occlusion rays must agree exactly (JSON)
  out=$("$tr" "$scene" --rays occlusion --res $res --check-embree --max-mismatch-rate 0.01 --json "$tmp/$scene.json" \
        --image "$tmp/$scene.png" 2>&1); rc=$?
  if [ $rc -ne 0 ]; then fail "occlusion_rttrace_embree_$scene" "exit $rc: $(echo "$out" | tail -3 | tr '\n' ' ')"; continue; fi
  if python3 - "$tmp/$scene.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["ray_type"] == "occlusion", d["ray_type"]
n = d["occlusion_rays"]
assert n > 0 and 0 < d["occluded"] < n, (n, d["occluded"])
assert n % d["ao_samples"] == 0 and n <= d["ao_samples"] * d["primary_rays"], n
assert d["rays"] == d["primary_rays"] + n and d["bounce_rays"] == 0
assert d["embree_occlusion_rays"] == n
assert d["embree_occlusion_mismatches"] == 0, d["embree_occlusion_mismatches"]
assert d["embree_occlusion_mismatch_other"] == 0
assert d["embree_rays"] == d["primary_rays"]
PY
  then pass "occlusion_rttrace_embree_$scene"; else fail "occlusion_rttrace_embree_$scene" "JSON check failed"; fi
  echo "$out" | grep -q "^occlusion  .* rays (any hit ends them, no sort)" \
    && pass "occlusion_rttrace_summary_$scene" || fail "occlusion_rttrace_summary_$scene" "no occlusion line"
done

# rtsim runs rttrace's occlusion rays: same count and occluded count; no sort pass
scene=interior
[ -f "$tmp/$scene.json" ] || "$tr" $scene --rays occlusion --res $res --json "$tmp/$scene.json" --quiet
want_n=$(json_get "$tmp/$scene.json" occlusion_rays); want_o=$(json_get "$tmp/$scene.json" occluded)
for m in bvh2 mbvh4; do
  out=$("$sim" $scene --machine $m --rays occlusion --res $res --set memory.model=fixed --json "$tmp/sim_$m.json" 2>&1); rc=$?
  if [ $rc -ne 0 ]; then fail "occlusion_rtsim_$m" "exit $rc: $(echo "$out" | tail -3 | tr '\n' ' ')"; continue; fi
  if python3 - "$tmp/sim_$m.json" "$want_n" "$want_o" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
n, o = int(sys.argv[2]), int(sys.argv[3])
assert d["sched.occlusion_rays"] == n == d["rays"], (d["sched.occlusion_rays"], n)
assert d["sched.occluded"] == o, (d["sched.occluded"], o)
sorts = sum(v for k, v in d.items() if k.startswith("trv") and k.endswith(".sort_passes"))
visits = sum(v for k, v in d.items() if k.startswith("trv") and k.endswith(".visits"))
assert sorts == 0 and visits > 0, (sorts, visits)
PY
  then pass "occlusion_rtsim_$m"; else fail "occlusion_rtsim_$m" "JSON check failed"; fi
  echo "$out" | grep -q "^scene .*occlusion rays" && echo "$out" | grep -q "^occlusion   $want_n rays, $want_o occluded" \
    && pass "occlusion_rtsim_summary_$m" || fail "occlusion_rtsim_summary_$m" "$(echo "$out" | head -6 | tr '\n' ' ')"
done

# determinism: the same JSON twice (host timings aside)
strip() { python3 -c '
import json, re, sys
d = json.load(open(sys.argv[1]))
v = re.compile(r"(_s$|wall|cpu|host|per_s|^run$)")
print(json.dumps({k: x for k, x in d.items() if not v.search(k)}, sort_keys=True))' "$1"; }
"$sim" $scene --machine mbvh4 --rays occlusion --res $res --set memory.model=fixed --json "$tmp/sim_again.json" --quiet
check occlusion_rtsim_deterministic cmp -s <(strip "$tmp/sim_mbvh4.json") <(strip "$tmp/sim_again.json")
"$tr" $scene --rays occlusion --res $res --json "$tmp/tr_again.json" --image "$tmp/again.png" --quiet
"$tr" $scene --rays occlusion --res $res --json "$tmp/tr_again2.json" --image "$tmp/again2.png" --quiet
check occlusion_rttrace_deterministic cmp -s <(strip "$tmp/tr_again.json") <(strip "$tmp/tr_again2.json")
check occlusion_rttrace_image_deterministic cmp -s "$tmp/again.png" "$tmp/again2.png"
# another seed: other AO rays, other occluded count (same primary rays)
"$tr" $scene --rays occlusion --res $res --seed 7 --json "$tmp/seed7.json" --quiet
check occlusion_rttrace_seeded test "$(json_get "$tmp/seed7.json" occluded)" != "$(json_get "$tmp/tr_again.json" occluded)"
