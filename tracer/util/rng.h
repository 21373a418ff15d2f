/* rng.h — PCG32 random numbers, seeded per (seed, pixel, bounce) stream.
 *
 * Algorithm: O'Neill, "PCG: A Family of Simple Fast Space-Efficient
 * Statistically Good Algorithms for Random Number Generation" (2014),
 * generator PCG-XSH-RR 64/32 with the 64-bit LCG multiplier
 * 6364136223846793005 (Knuth, TAOCP vol. 2). Contract: the sequence depends
 * only on the seeding arguments, so a pixel's random numbers do not depend on
 * the order in which pixels or rays are processed. No global state. */
#ifndef RTSIM_TRACER_RNG_H
#define RTSIM_TRACER_RNG_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rt_rng {
    uint64_t state;
    uint64_t inc;   /* stream selector, always odd */
} rt_rng;

/* Seeds a generator on stream `stream` (any 64-bit value). */
void rt_rng_seed(rt_rng *r, uint64_t seed, uint64_t stream);

/* The generator for one (frame seed, pixel, bounce number) triple: the
 * streams of different triples are decorrelated by hashing (SplitMix64
 * finalizer, Steele et al., OOPSLA 2014) before seeding. */
rt_rng rt_rng_for_ray(uint64_t seed, uint32_t pixel, uint32_t bounce);

/* Next 32 random bits. */
uint32_t rt_rng_u32(rt_rng *r);

/* Uniform float in [0, 1): the top 24 bits times 2^-24. */
float rt_rng_float(rt_rng *r);

/* Uniform integer in [0, n) without modulo bias (n > 0). */
uint32_t rt_rng_below(rt_rng *r, uint32_t n);

#ifdef __cplusplus
}
#endif

#endif
