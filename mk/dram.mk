# DRAM model (docs/dram.md): rtdram finds its default parameter files in model/data
$(BUILD)/obj/cli/rtdram.c.o: CPPFLAGS += $(DATA_DIR_DEFINE)
