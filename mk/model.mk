# Libraries the model uses: inih for INI machine configurations.
EXTRA_LDLIBS += $(shell pkg-config --libs inih 2>/dev/null)
# Machine presets (model/data/machines/*.ini): rtcfg finds them in model/data
# unless RTSIM_DATA_DIR is set at run time.
$(BUILD)/obj/config/config.c.o: CPPFLAGS += $(DATA_DIR_DEFINE)
