# DRAM model (issue 4): rtdram finds its default parameter files in model/data
# and reports the git commit in --version.
$(BUILD)/obj/cli/rtdram.c.o: CPPFLAGS += -DRTSIM_DATA_DIR='"$(CURDIR)/model/data"' \
	-DRTSIM_GIT='"$(shell git rev-parse --short HEAD 2>/dev/null || echo unknown)"'
