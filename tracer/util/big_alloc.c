/* big_alloc.c — see big_alloc.h. */
#include "tracer/util/big_alloc.h"

#include <stdlib.h>
#include <sys/mman.h>

enum { HUGE_PAGE = 2u << 20, BIG_THRESHOLD = 4u << 20 };

void *rt_big_alloc(size_t n)
{
    if (n < BIG_THRESHOLD)
        return aligned_alloc(16, (n + 15) & ~(size_t)15 ? (n + 15) & ~(size_t)15 : 16);   /* SSE loads */
    void *p = NULL;
    const size_t rounded = (n + HUGE_PAGE - 1) & ~(size_t)(HUGE_PAGE - 1);
    if (posix_memalign(&p, HUGE_PAGE, rounded) != 0)
        return NULL;
#ifdef MADV_HUGEPAGE
    (void)madvise(p, rounded, MADV_HUGEPAGE);   /* a hint: failure is harmless */
#endif
    return p;
}
