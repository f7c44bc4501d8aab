/* rng.h — PCG32 (O'Neill 2014) and hashing for per-pixel random streams.
 * Each pixel's stream depends only on the seed and the pixel index, so the
 * image does not depend on how tiles are scheduled over threads. */
#ifndef RTGI_RNG_H
#define RTGI_RNG_H

#include <stdint.h>

typedef struct Rng {
    uint64_t state;
    uint64_t inc;
} Rng;

static inline uint32_t rng_u32(Rng *r)
{
    uint64_t old = r->state;
    r->state = old * 6364136223846793005ULL + r->inc;
    uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31));
}

/* Uniform in [0, 1). */
static inline float rng_float(Rng *r)
{
    return (float)(rng_u32(r) >> 8) * (1.0f / 16777216.0f);
}

static inline uint64_t hash64(uint64_t x)
{
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ULL;
    x ^= x >> 33;
    return x;
}

static inline Rng rng_make(uint64_t seed, uint64_t stream)
{
    Rng r = {0, (hash64(stream) << 1u) | 1u};
    rng_u32(&r);
    r.state += hash64(seed ^ 0x9e3779b97f4a7c15ULL);
    rng_u32(&r);
    return r;
}

#endif
