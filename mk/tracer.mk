# --- tracer-io (docs/tracer-io.md); kept above the shared lines so merges
# with the other tracer rules below stay clean. Recipes expand EXTRA_LDLIBS
# late, so its definition below is seen. ---
# tracer-io helpers (docs/tracer-io.md). Prerequisites name libtracer.a
# directly: LIB_FILES is defined after mk/*.mk are read.
$(BUILD)/scripts/rt_preview: $(BUILD)/obj/scripts/rt_preview.c.o $(BUILD)/lib/libtracer.a
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $< $(BUILD)/lib/libtracer.a $(EXTRA_LDLIBS) $(LDLIBS) -o $@

# Loader benchmark against Assimp (bench/tracer/loader.sh).
BENCH_BINS += $(BUILD)/bench/tracer_loader
$(BUILD)/bench/tracer_loader: $(BUILD)/obj/bench/tracer_loader.cpp.o $(BUILD)/lib/libtracer.a
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $< $(BUILD)/lib/libtracer.a $(EXTRA_LDLIBS) $(shell pkg-config --libs assimp 2>/dev/null || echo -lassimp) $(LDLIBS) -o $@

# Libraries the tracer uses: Embree 3 (reference), OpenImageIO (images), zlib (.gz scenes).
EXTRA_LDLIBS += -lembree3 $(shell pkg-config --libs OpenImageIO 2>/dev/null) -lz

# --- tracer BVH/traversal (docs/tracer-bvh.md) ---
# Build and traversal speed against Embree (bench/tracer.sh).
BENCH_BINS += $(BUILD)/bench/tracer_trace
$(BUILD)/bench/tracer_trace: $(BUILD)/obj/bench/tracer_trace.c.o $(BUILD)/lib/libtracer.a
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $< $(BUILD)/lib/libtracer.a $(EXTRA_LDLIBS) $(LDLIBS) -o $@
