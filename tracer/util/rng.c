/* rng.c — see rng.h. */
#include "tracer/util/rng.h"

/* PCG-XSH-RR 64/32 (O'Neill 2014, section 6.3.1). */
#define PCG_MULT 6364136223846793005ULL

uint32_t rt_rng_u32(rt_rng *r)
{
    uint64_t old = r->state;
    r->state = old * PCG_MULT + r->inc;
    uint32_t xorshifted = (uint32_t)(((old >> 18) ^ old) >> 27);
    uint32_t rot = (uint32_t)(old >> 59);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

void rt_rng_seed(rt_rng *r, uint64_t seed, uint64_t stream)
{
    /* The reference seeding procedure of pcg32_srandom_r. */
    r->state = 0;
    r->inc = (stream << 1) | 1u;
    rt_rng_u32(r);
    r->state += seed;
    rt_rng_u32(r);
}

/* SplitMix64 finalizer (Steele, Lea, Flood 2014): a bijective 64-bit mix. */
static uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

rt_rng rt_rng_for_ray(uint64_t seed, uint32_t pixel, uint32_t bounce)
{
    rt_rng r;
    uint64_t key = ((uint64_t)pixel << 8) ^ (uint64_t)bounce;
    rt_rng_seed(&r, mix64(seed ^ mix64(key)), mix64(key + 0x9e3779b97f4a7c15ULL));
    return r;
}

float rt_rng_float(rt_rng *r)
{
    return (float)(rt_rng_u32(r) >> 8) * (1.0f / 16777216.0f);
}

uint32_t rt_rng_below(rt_rng *r, uint32_t n)
{
    /* Rejection of the short top interval (as pcg32_boundedrand_r). */
    uint32_t threshold = (uint32_t)(-n) % n;
    for (;;) {
        uint32_t x = rt_rng_u32(r);
        if (x >= threshold)
            return x % n;
    }
}
