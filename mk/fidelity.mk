# fidelity/ -> libfidelity.a: the cheaper fidelity levels (docs/fidelity.md).
# It uses model/ and tracer/, so it links before them.
LIBS := fidelity $(LIBS)
