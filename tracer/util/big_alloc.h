/* big_alloc.h — allocation of large work buffers (BVH builder, memory
 * image) aligned to 2 MiB and marked for transparent huge pages where the
 * kernel offers them (Linux madvise(MADV_HUGEPAGE)): first-touch page faults
 * were a fifth of the build time of a 2.7M-triangle scene with 4 KiB pages.
 * Smaller blocks are 16-byte aligned (SSE loads of the builder's boxes).
 * Memory is released with free(). Internal to tracer/. */
#ifndef RTSIM_TRACER_BIG_ALLOC_H
#define RTSIM_TRACER_BIG_ALLOC_H

#include <stddef.h>

/* NULL when out of memory; n = 0 gives a valid minimal block. */
void *rt_big_alloc(size_t n);

#endif
