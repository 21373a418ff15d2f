# Libraries the tracer uses: Embree 3 (reference), OpenImageIO (images), zlib (.gz scenes).
EXTRA_LDLIBS += -lembree3 $(shell pkg-config --libs OpenImageIO 2>/dev/null) -lz
