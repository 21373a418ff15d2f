#!/usr/bin/env bash
# Architecture rules of docs/design.md "Layout", checked on the sources:
# - kernel/ includes nothing from other project folders;
# - tracer/ nothing from model/ or config/; inside it, each folder includes
#   only itself and the folders below it in the order
#   util < io < bvh < trace < log, check (small utilities, scene input, BVH
#   builders, ray generation and traversal, then trace logs and the Embree
#   check, which use all of those); no sources directly in tracer/;
# - config/ (the configuration store) nothing from the other folders;
# - model/ (all its folders) only tracer/bvh/bvh_layout.h from the tracer;
# - model/dram/ (the LPDDR3 library) does not use the kernel except through
#   its port (dram_port.[ch], dram_port_trace.[ch]).
cd "$(dirname "$0")/.."
rule() { # name, offending lines
  if [ -z "$2" ]; then echo "PASS $1"; else echo "FAIL $1: $(echo "$2" | head -3 | tr '\n' ' ')"; fi
}
rule layout_kernel_includes_only_kernel \
  "$(grep -HnE '#include[[:space:]]*"' kernel/*.[ch] 2>/dev/null | grep -vE '#include[[:space:]]*"(kernel/)?[a-z0-9_]+\.h"')"
rule layout_tracer_independent_of_model \
  "$(grep -HnE '#include[[:space:]]*"(\.\./)?(model|config)/' tracer/*/*.[ch] tracer/*/*.cpp 2>/dev/null)"
rule layout_tracer_sources_in_folders "$(ls tracer/*.[ch] tracer/*.cpp 2>/dev/null)"
tracer_layer() { # folder, the tracer folders it may include
  local d=$1 allowed=$2
  [ -d "tracer/$d" ] || { echo "tracer/$d missing"; return; }
  grep -HnoE '#include[[:space:]]*"tracer/[a-z]+/' tracer/"$d"/* | grep -vE "\"tracer/($allowed)/\$"
}
rule layout_tracer_folders_layered "$(
  tracer_layer util util; tracer_layer io 'util|io'; tracer_layer bvh 'util|io|bvh'
  tracer_layer trace 'util|io|bvh|trace'; tracer_layer log 'util|io|bvh|trace|log'
  tracer_layer check 'util|io|bvh|trace|check')"
rule layout_config_self_contained \
  "$(grep -HnE '#include[[:space:]]*"' config/*.[ch] 2>/dev/null | grep -vE '#include[[:space:]]*"config/[a-z0-9_]+\.h"')"
rule layout_model_uses_only_bvh_layout_from_tracer \
  "$(grep -rHnE '#include[[:space:]]*"(\.\./)?tracer/' model --include='*.[ch]' | grep -v 'tracer/bvh/bvh_layout\.h"')"
rule layout_dram_library_kernel_free \
  "$(grep -HnE '#include[[:space:]]*"(\.\./)?kernel/' model/dram/*.[ch] 2>/dev/null | grep -vE '^model/dram/dram_port(_trace)?\.[ch]:')"
