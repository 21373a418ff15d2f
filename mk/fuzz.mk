# --- fuzz harnesses (testbench/fuzz/, fuzz.h) ---
# Every testbench/fuzz/fuzz_<name>.c (but fuzz_main.c) is one harness, linked
# with fuzz_main.c into $(BUILD)/fuzz/fuzz_<name>. `make` builds them with the
# rest (the ASan build's copies replay the corpus in make test,
# tb_fuzz_replay.sh); `make fuzz` builds them with AFL++'s afl-cc plus ASan and
# UBSan into build/afl and fuzzes each for FUZZ_SECONDS (scripts/fuzz.sh).
FUZZ_NAMES := $(filter-out fuzz_main,$(patsubst testbench/fuzz/%.c,%,$(wildcard testbench/fuzz/fuzz_*.c)))
FUZZ_BINS := $(patsubst %,$(BUILD)/fuzz/%,$(FUZZ_NAMES))
all: $(FUZZ_BINS)
$(BUILD)/fuzz/%: $(BUILD)/obj/testbench/fuzz/%.c.o $(BUILD)/obj/testbench/fuzz/fuzz_main.c.o \
		$(BUILD)/lib/libframe.a $(BUILD)/lib/libmodel.a $(BUILD)/lib/libconfig.a $(BUILD)/lib/libtracer.a $(BUILD)/lib/libkernel.a
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -Wl,--as-needed $(filter %.o,$^) $(BUILD)/lib/libframe.a $(BUILD)/lib/libmodel.a $(BUILD)/lib/libconfig.a $(BUILD)/lib/libtracer.a $(BUILD)/lib/libkernel.a \
		$(EXTRA_LDLIBS) $(LDLIBS) -o $@

FUZZ_SECONDS ?= 60
.PHONY: fuzz fuzz-build
fuzz-build:
	@scripts/install-deps.sh afl++
	$(MAKE) BUILD=build/afl SAN=1 CC=afl-cc CXX=afl-c++ AFL_QUIET=1 $(patsubst %,build/afl/fuzz/%,$(FUZZ_NAMES))
fuzz: fuzz-build
	scripts/fuzz.sh build/afl $(FUZZ_SECONDS) $(FUZZ_NAMES)
