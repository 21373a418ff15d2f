# rtsim top-level build. Out of tree into $(BUILD); `make asan` builds the same
# sources with AddressSanitizer + UndefinedBehaviorSanitizer into build/asan.
#
# Layout (docs/design.md "Layout"): one static library per folder
#   kernel/  -> libkernel.a   (discrete-event kernel; includes nothing else)
#   tracer/  -> libtracer.a   (software ray tracer; may use nothing from model/)
#   model/   -> libmodel.a    (the accelerator, with its subfolders ray/, mem/,
#                              dram/, energy/; uses kernel/, config/ and the
#                              tracer's node/triangle layout)
#   config/  -> libconfig.a   (the typed, ranged configuration store)
#   cli/lib/ -> libcli.a      (what the tools share: options, provenance,
#                              outputs, JSON, progress; declared in cli/*.h)
#   cli/     -> one binary per cli/<name>.c in $(BUILD)/bin
#   testbench/ mirrors the source tree (testbench/kernel/, testbench/model/ray/,
#   ...): every tb_*.c below it -> one test program $(BUILD)/testbench/tb_*;
#   every tb_*.sh below it runs as a script (testbench/run.sh)
# Per-area extras (link flags, bench targets) live in mk/*.mk.

BUILD    ?= build
SAN      ?=
CC       ?= gcc
CXX      ?= g++
OPT      ?= -O2
# _GNU_SOURCE only for POSIX bits (clock_gettime, isatty, mkstemp, getopt_long).
CPPFLAGS += -I. -D_GNU_SOURCE -MMD -MP
CFLAGS   += -std=c11 $(OPT) -g -Wall -Wextra -Werror
CXXFLAGS += -std=c++17 $(OPT) -g -Wall -Wextra -Werror
LDLIBS   += -lm

ifeq ($(SAN),1)
  OPT       = -O1
  SANFLAGS  = -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
  CFLAGS   += $(SANFLAGS)
  CXXFLAGS += $(SANFLAGS)
  LDFLAGS  += $(SANFLAGS)
endif

# A C string literal of $(1) inside shell single quotes, for -D...='...':
# backslashes and double quotes escaped for C, single quotes for the shell,
# so a checkout under a folder such as /home/o'brien builds too.
shell_c_string = '$(subst ','\'',"$(subst ",\",$(subst \,\\,$(1)))")'
# Where the tools find model/data (machine presets, DRAM parameters) unless
# RTSIM_DATA_DIR is set at run time: this checkout's (mk/model.mk, mk/dram.mk).
DATA_DIR_DEFINE = -DRTSIM_DATA_DIR=$(call shell_c_string,$(CURDIR)/model/data)

LIBS := cli frame model config tracer kernel
# Extra libraries per area (set in mk/*.mk): EXTRA_LDLIBS. Recursively
# expanded on purpose: its $(shell pkg-config ...) parts run when a link recipe
# runs, after `deps` has installed the packages, not when make reads this file
# (on a fresh machine they would find nothing and every link would fail).
EXTRA_LDLIBS =
# Benchmark programs (bench/ only; may link SystemC, Assimp): BENCH_BINS
BENCH_BINS :=
-include $(sort $(wildcard mk/*.mk))

# a library's sources: its folder and the folders inside it (model/ray, ...);
# libcli's are cli/lib alone (cli/*.c are the tools, one binary each)
LIB_DIR_cli := cli/lib
lib_dir = $(or $(LIB_DIR_$(1)),$(1))
lib_srcs = $(sort $(wildcard $(call lib_dir,$(1))/*.c $(call lib_dir,$(1))/*/*.c) \
	$(wildcard $(call lib_dir,$(1))/*.cpp $(call lib_dir,$(1))/*/*.cpp))
lib_objs = $(patsubst %,$(BUILD)/obj/%.o,$(call lib_srcs,$(1)))
LIB_FILES := $(foreach l,$(LIBS),$(if $(call lib_srcs,$(l)),$(BUILD)/lib/lib$(l).a))
LINK_LIBS = $(LIB_FILES) $(EXTRA_LDLIBS) $(LDLIBS)

CLI_SRCS := $(sort $(wildcard cli/*.c))
CLI_BINS := $(patsubst cli/%.c,$(BUILD)/bin/%,$(CLI_SRCS))
TB_SRCS  := $(sort $(shell find testbench -name 'tb_*.c'))
# Test programs are flat in $(BUILD)/testbench whatever folder holds their
# source: a test's name is unique across the tree.
TB_BINS  := $(patsubst %.c,$(BUILD)/testbench/%,$(notdir $(TB_SRCS)))

.PHONY: all asan test run bench deps clean
.DEFAULT_GOAL := all
# Object files are intermediates of the libraries and binaries; without this,
# make deletes them after every build and the next `make` compiles them again.
.SECONDARY:
all: $(CLI_BINS) $(TB_BINS)

$(foreach l,$(LIBS),$(eval $(BUILD)/lib/lib$(l).a: $(call lib_objs,$(l))))
# The archive is made anew: `ar r` into an existing one would keep the
# members of sources since moved or deleted (duplicate symbols at link time).
$(BUILD)/lib/%.a:
	@mkdir -p $(@D)
	@rm -f $@
	$(AR) rcs $@ $^

# Every tool reports the commit it was built from and whether the tree was
# dirty (cli/version.h): mk/version.mk.

$(BUILD)/obj/%.c.o: %.c
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c $< -o $@
$(BUILD)/obj/%.cpp.o: %.cpp
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) -c $< -o $@

# Binaries are linked with g++ because the OpenImageIO shim is C++.
$(BUILD)/bin/%: $(BUILD)/obj/cli/%.c.o $(LIB_FILES)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $< $(LINK_LIBS) -o $@
$(foreach t,$(TB_SRCS),$(eval $(BUILD)/testbench/$(basename $(notdir $(t))): $(BUILD)/obj/$(t).o $(LIB_FILES)))
$(TB_BINS):
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $< $(LINK_LIBS) -o $@

asan:
	$(MAKE) BUILD=build/asan SAN=1 all

deps:
	@scripts/install-deps.sh

# The test command of README: builds both variants, runs every testbench in
# both, ends with "N passed, N failed".
# The builds get one job per CPU unless the user gave a -j; the two variants'
# testbenches then run at once (testbench/run.sh, TB_JOBS).
NPROC := $(shell nproc 2>/dev/null || echo 1)
BUILD_JOBS = $(if $(findstring j,$(MAKEFLAGS)),,-j$(NPROC))
test: deps
	$(MAKE) $(BUILD_JOBS) all
	$(MAKE) $(BUILD_JOBS) asan
	@testbench/run.sh build build/asan

# run and bench build in a second make, started after `deps`: that make reads
# the Makefile again with the packages installed (pkg-config answers).
RUN_CMD ?= $(BUILD)/bin/rtsim
run: deps
	$(MAKE) $(BUILD_JOBS) all
	$(RUN_CMD)

bench: deps
	$(MAKE) $(BUILD_JOBS) all $(BENCH_BINS)
	@mkdir -p $(BUILD)/bench
	@set -e; for s in $(sort $(wildcard bench/*.sh)); do bash $$s $(BUILD); done
	@scripts/bench-history append $(BUILD)/bench

clean:
	rm -rf build

-include $(shell find $(BUILD)/obj -name '*.d' 2>/dev/null)
