/* fuzz_check.h — what every harness asserts about a rejection: a message was
 * written. An empty message is a bug (the user would get no reason), so it
 * aborts, which the fuzzer and the replay test report as a crash. */
#ifndef RTSIM_TESTBENCH_FUZZ_CHECK_H
#define RTSIM_TESTBENCH_FUZZ_CHECK_H

#include <stdio.h>
#include <stdlib.h>

static inline int fuzz_rejected(const char *who, const char *err)
{
    if (!err[0]) {
        fprintf(stderr, "%s: input rejected without a message\n", who);
        abort();
    }
    return 0;
}

#endif
