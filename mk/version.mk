# Build provenance (cli/version.h; the "run" object of docs/results.md): the
# commit and whether tracked files differ from it (1, 0; -1 outside git),
# passed to every cli/ object (the tools' and libcli's). $(BUILD)/version.stamp
# holds both and is rewritten only when they change, and the cli/ objects
# depend on it: a new commit, or the tree turning dirty or clean, recompiles
# the tools' and libcli's objects and nothing else. Further edits that keep a dirty tree dirty change
# nothing here (the flag says "dirty", not which changes; those objects that
# changed are rebuilt as usual). Untracked files do not make the tree dirty.
RTSIM_GIT_COMMIT := $(shell git rev-parse --short HEAD 2>/dev/null || echo unknown)
RTSIM_GIT_DIRTY := $(shell if git rev-parse --git-dir >/dev/null 2>&1; then \
	test -z "$$(git status --porcelain --untracked-files=no 2>/dev/null)" && echo 0 || echo 1; else echo -1; fi)
VERSION_STAMP := $(BUILD)/version.stamp
$(shell mkdir -p $(BUILD) && { echo '$(RTSIM_GIT_COMMIT) $(RTSIM_GIT_DIRTY)' | cmp -s - $(VERSION_STAMP) 2>/dev/null || \
	echo '$(RTSIM_GIT_COMMIT) $(RTSIM_GIT_DIRTY)' > $(VERSION_STAMP); })
$(patsubst cli/%.c,$(BUILD)/obj/cli/%.c.o,$(wildcard cli/*.c cli/lib/*.c)): $(VERSION_STAMP)
$(BUILD)/obj/cli/%.c.o: CPPFLAGS += -DRTSIM_GIT='"$(RTSIM_GIT_COMMIT)"' -DRTSIM_GIT_DIRTY=$(RTSIM_GIT_DIRTY)
