# The main job of README's `make run`: the interior scene at 320x180 on the
# MBVH4 machine with primary rays (a few seconds).
RUN_CMD = $(BUILD)/bin/rtsim interior --res 320x180 --machine mbvh4 --rays primary
