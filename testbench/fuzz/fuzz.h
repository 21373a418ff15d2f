/* fuzz.h — the contract of one fuzz harness (testbench/fuzz/fuzz_*.c).
 *
 * Each harness defines fuzz_one(), which feeds one input to one of rtsim's
 * input parsers the way the tools do and must return normally whatever the
 * bytes are: a parser may reject the input (with a message), never crash,
 * hang or leak. fuzz_main.c calls it once per file; `make fuzz` builds every
 * harness with AFL++ and AddressSanitizer (scripts/fuzz.sh runs them), and
 * `make test` replays testbench/fuzz/corpus/<harness>/ through the plain
 * ASan/UBSan build (tb_fuzz_replay.sh). */
#ifndef RTSIM_TESTBENCH_FUZZ_H
#define RTSIM_TESTBENCH_FUZZ_H

#include <stddef.h>

/* path: the input as a file (for parsers that take a path); data/len: its
 * bytes, NUL-terminated one past len. Returns 1 if the parser accepted it,
 * 0 if it rejected it with a non-empty message. */
int fuzz_one(const char *path, const unsigned char *data, size_t len);

/* Name of the harness, for messages. */
extern const char fuzz_name[];

#endif
