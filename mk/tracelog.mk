# --- trace logs and rttrace (docs/tracer-log.md) ---
# rttrace reports the git commit in --version.
$(BUILD)/obj/cli/rttrace.c.o: CPPFLAGS += -DRTSIM_GIT='"$(shell git rev-parse --short HEAD 2>/dev/null || echo unknown)"'
