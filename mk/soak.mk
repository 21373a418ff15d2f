# `make soak`: the long run of the random-configuration property test
# (testbench/model/tb_accel_random_configs.c): SOAK_CONFIGS machine
# configurations drawn with seed SOAK_SEED, each run with primary and with
# diffuse rays; every run must finish with hits equal to the reference
# traversal or be refused at start-up naming a key. `make test` runs the
# short version (100 configurations, 16 under the sanitizers). About 30 ms of
# host time per configuration (release build, idle host).
SOAK_CONFIGS ?= 3000
SOAK_SEED ?= 1
.PHONY: soak
soak: deps all
	RTSIM_RANDOM_CONFIGS=$(SOAK_CONFIGS) RTSIM_CONFIG_SEED=$(SOAK_SEED) TB_TIMEOUT=86400 \
		TB_FILTER='^tb_accel_random_configs$$' testbench/run.sh $(BUILD)
