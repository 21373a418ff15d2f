#!/usr/bin/env bash
# tb_checkout_path — the build from a checkout whose path holds a single
# quote, a double quote, a backslash and spaces (/home/o'brien, ...): the
# objects that embed the checkout's model/data folder (Makefile
# DATA_DIR_DEFINE) compile, and hold the folder's name unchanged.
set -u
tmp=${RTSIM_TMP:-/tmp}/tb_checkout_path
rm -rf "$tmp"; mkdir -p "$tmp"
cd "$(dirname "$0")/.."
. testbench/cli_lib.sh
src="$tmp/o'brien \"work\" back\\slash/rtsim"
mkdir -p "$src"
# the tree's files as they are now (committed or not), without build/
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  git ls-files -z --cached --others --exclude-standard | tar --null -T - -cf - | tar -C "$src" -xf -
else   # an unpacked release: no git
  tar --exclude=./build --exclude=./.git -cf - . | tar -C "$src" -xf -
fi
objs=(build/obj/config/config.c.o build/obj/cli/rtdram.c.o)
make -C "$src" "${objs[@]}" >"$tmp/make.log" 2>&1
check checkout_path_compiles test $? -eq 0
for o in "${objs[@]}"; do
  check "checkout_path_data_dir_$(basename "$o" .c.o)" grep -aqF "$src/model/data" "$src/$o"
done
