/* fnv1a.h — FNV-1a 64-bit hashing of bytes, for the hashes that name what a
 * run used (mesh, configuration) and for hash tables.
 *
 * Contract: rt_fnv1a64(h, data, n) folds n bytes into h; start from
 * RT_FNV1A64_BASIS. Parameters (offset basis 14695981039346656037, prime
 * 1099511628211) are those of http://www.isthe.com/chongo/tech/comp/fnv/.
 * Not a cryptographic hash. */
#ifndef RT_FNV1A_H
#define RT_FNV1A_H

#include <stddef.h>
#include <stdint.h>

#define RT_FNV1A64_BASIS 14695981039346656037ULL
#define RT_FNV1A64_PRIME 1099511628211ULL

static inline uint64_t rt_fnv1a64(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++)
        h = (h ^ p[i]) * RT_FNV1A64_PRIME;
    return h;
}

#endif
