#!/usr/bin/env bash
# Architecture rules of docs/design.md "Layout", checked on the sources:
# kernel/ includes nothing from other project folders; tracer/ nothing from model/.
cd "$(dirname "$0")/.."
bad=$(grep -HnE '#include[[:space:]]*"' kernel/*.[ch] 2>/dev/null | grep -vE '#include[[:space:]]*"(kernel/)?[a-z0-9_]+\.h"')
if [ -z "$bad" ]; then echo "PASS layout_kernel_includes_only_kernel"; else echo "FAIL layout_kernel_includes_only_kernel: $bad" | head -3; fi
bad=$(grep -HnE '#include[[:space:]]*"(\.\./)?model/' tracer/*.[ch] tracer/*.cpp 2>/dev/null)
if [ -z "$bad" ]; then echo "PASS layout_tracer_independent_of_model"; else echo "FAIL layout_tracer_independent_of_model: $bad" | head -3; fi
