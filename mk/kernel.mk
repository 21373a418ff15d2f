# Kernel benchmarks (bench/kernel.sh): our workloads in C and their SystemC
# 2.3.4 twins in C++ (SystemC is linked only here, never by the project).
# Prerequisites name libkernel.a directly: LIB_FILES is defined after mk/*.mk.
BENCH_BINS += $(BUILD)/bench/kernel_ours $(BUILD)/bench/kernel_systemc
$(BUILD)/bench/kernel_ours: $(BUILD)/obj/bench/kernel_ours.c.o $(BUILD)/lib/libkernel.a
	@mkdir -p $(@D)
	$(CC) $(LDFLAGS) $< $(BUILD)/lib/libkernel.a $(LDLIBS) -o $@
$(BUILD)/bench/kernel_systemc: $(BUILD)/obj/bench/kernel_systemc.cpp.o
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $< $(shell pkg-config --libs systemc 2>/dev/null || echo -lsystemc) $(LDLIBS) -o $@
