# Libraries the model uses: inih for INI machine configurations.
EXTRA_LDLIBS += $(shell pkg-config --libs inih 2>/dev/null)
