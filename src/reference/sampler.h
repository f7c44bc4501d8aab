/* sampler.h — where a path's uniform numbers come from.
 *
 * PT_SAMPLER_SOBOL: Owen-scrambled Sobol' points with hash-based nested
 * uniform scrambling (Burley, "Practical Hash-based Owen Scrambling", JCGT
 * 2020), padded in pairs. Every 2D request of a path (pixel jitter, a light's
 * sample, a bounce direction) gets its own "dimension pair" d = 0, 1, 2, …
 * in the order the path asks for them; pair d of sample k of a pixel is the
 * first two Sobol' dimensions (a (0,2)-sequence: the van der Corput sequence
 * and the one of the primitive polynomial x + 1) at index k, where both the
 * index and the two coordinates go through a nested uniform (Owen) scramble
 * seeded by hash(seed, pixel, d). Shuffling the index per pair decorrelates
 * the pairs from one another (the padding of Kollig & Keller 2002), and the
 * per-pixel seeds decorrelate pixels, so the image has white-noise-like
 * error with the convergence of a stratified (0,2)-net within each pair:
 * for smooth integrands the variance falls faster than 1/N, best at powers
 * of two. 1D requests (Russian roulette) use one scrambled van der Corput
 * coordinate with its own index shuffle.
 *
 * PT_SAMPLER_INDEPENDENT: PCG32 numbers, one stream per pixel and sample
 * index (the state from the seed and the index, the increment from the
 * pixel), as the reference used before; kept to measure the gain.
 *
 * Both depend only on (seed, pixel, sample index, request order), never on
 * threads or tiles. */
#ifndef RTGI_SAMPLER_H
#define RTGI_SAMPLER_H

#include <stdint.h>
#include <string.h>

#include "reference/pt_settings.h"
#include "reference/rng.h"
#include "shared/hash.h"
#include "base/util.h"

/* Requests whose seeds sampler_make computes once per pixel (a path's
 * first vertices: its pixel jitter, light samples and bounces). */
enum { SAMPLER_CACHED_DIMS = 8 };

typedef struct Sampler {
    PtSampler kind;
    Rng rng;           /* independent: the stream of the current sample */
    uint64_t seed;     /* independent: the render's seed */
    uint64_t pixel;    /* independent: the pixel's index */
    uint64_t pixel_key;/* sobol: hash of (seed, pixel) */
    uint32_t index;    /* sobol: sample index within the pixel */
    uint32_t index_rev;/* sobol: its bits reversed (the Owen scramble's input) */
    uint32_t dim;      /* sobol: requests made so far in this sample */
    uint32_t seeds[SAMPLER_CACHED_DIMS][3]; /* sobol: sampler_seeds of the first requests */
} Sampler;

/* Burley's hash in the style of Laine & Karras: a permutation of 32-bit
 * integers in which each bit depends only on the bits below it, so that on
 * bit-reversed input it flips each bit depending only on the bits above it:
 * exactly a nested uniform scramble, with one random flip per tree node
 * drawn by hashing. */
static inline uint32_t sampler_lk_permute(uint32_t x, uint32_t seed)
{
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

/* Owen scramble of a 32-bit binary fraction (most significant bit first). */
static inline uint32_t sampler_owen(uint32_t x, uint32_t seed)
{
    return util_reverse_bits(sampler_lk_permute(util_reverse_bits(x), seed));
}

/* Sobol' dimension 1 (generator matrix: Pascal's triangle mod 2, from the
 * primitive polynomial x + 1; dimension 0 is van der Corput, i.e. the
 * reversed index) at index i, as a 32-bit fraction with its bits reversed
 * (the order the Owen scramble takes them in: reversing is linear over
 * XOR), by table per byte of i: sobol1_rev_table[b][v] is the XOR of the
 * reversed direction numbers of the set bits of v at bits 8b… of the
 * index. Only the top 24 bits of a coordinate are ever used
 * (sampler_to_float), and index bit k only reaches coordinate bits below
 * 32 − k, through the scramble too (each output bit depends only on the
 * bits above it), so index bits from 24 up are dropped. Filled by
 * sampler_init. */
extern uint32_t sobol1_rev_table[3][256];

/* Fills the tables; idempotent and thread-safe. */
void sampler_init(void);

static inline uint32_t sobol_dim1_reversed(uint32_t i)
{
    return sobol1_rev_table[0][i & 0xffu] ^ sobol1_rev_table[1][(i >> 8) & 0xffu] ^
           sobol1_rev_table[2][(i >> 16) & 0xffu];
}

static inline float sampler_to_float(uint32_t x) { return (float)(x >> 8) * (1.0f / 16777216.0f); }

/* Seeds of request `dim` of a pixel: index shuffle, first and second
 * coordinate. */
static inline void sampler_seeds_of(uint64_t pixel_key, uint32_t dim, uint32_t seed[3])
{
    uint64_t h = hash64(pixel_key + 0x9e3779b97f4a7c15ULL * ((uint64_t)dim + 1));
    seed[0] = (uint32_t)h;
    seed[1] = (uint32_t)(h >> 32);
    seed[2] = hash_u32(seed[0] ^ 0xa511e9b3u) ^ seed[1];
}

static inline Sampler sampler_make(PtSampler kind, uint64_t seed, uint64_t pixel)
{
    Sampler s;
    memset(&s, 0, sizeof s);
    s.kind = kind;
    s.seed = seed;
    s.pixel = pixel;
    if (kind == PT_SAMPLER_SOBOL) {
        s.pixel_key = hash64(hash64(seed ^ 0x5851f42d4c957f2dULL) ^ pixel);
        for (uint32_t d = 0; d < SAMPLER_CACHED_DIMS; d++)
            sampler_seeds_of(s.pixel_key, d, s.seeds[d]);
    }
    return s;
}

/* Starts sample `index` of the pixel. Independent: a stream of its own, so
 * that a sample's numbers depend on its index and not on how many samples
 * came before it in this Sampler (the render makes a pixel's Sampler anew
 * for every pass: one stream per pixel restarted there, and every pass
 * repeated the first pass's samples). */
static inline void sampler_start(Sampler *s, uint32_t index)
{
    s->index = index;
    s->index_rev = util_reverse_bits(index);
    s->dim = 0;
    if (s->kind == PT_SAMPLER_INDEPENDENT)
        s->rng = rng_make(hash64(s->seed ^ hash64((uint64_t)index + 0x2545f4914f6cdd1dULL)), s->pixel);
}

/* Seeds of the current request: index shuffle, first and second coordinate. */
static inline void sampler_seeds(const Sampler *s, uint32_t seed[3])
{
    if (s->dim < SAMPLER_CACHED_DIMS) {
        seed[0] = s->seeds[s->dim][0];
        seed[1] = s->seeds[s->dim][1];
        seed[2] = s->seeds[s->dim][2];
    } else {
        sampler_seeds_of(s->pixel_key, s->dim, seed);
    }
}

/* The request's shuffled index: Owen scramble of the sample index. */
static inline uint32_t sampler_shuffled(const Sampler *s, uint32_t seed)
{
    return util_reverse_bits(sampler_lk_permute(s->index_rev, seed));
}

static inline void sampler_2d(Sampler *s, float u[2])
{
    if (s->kind == PT_SAMPLER_INDEPENDENT) {
        u[0] = rng_float(&s->rng);
        u[1] = rng_float(&s->rng);
        return;
    }
    uint32_t seed[3];
    sampler_seeds(s, seed);
    uint32_t i = sampler_shuffled(s, seed[0]);
    /* Owen(van der Corput(i)) = reverse(LK(reverse(reverse(i)))). */
    u[0] = sampler_to_float(util_reverse_bits(sampler_lk_permute(i, seed[1])));
    u[1] = sampler_to_float(util_reverse_bits(sampler_lk_permute(sobol_dim1_reversed(i), seed[2])));
    s->dim++;
}

static inline float sampler_1d(Sampler *s)
{
    if (s->kind == PT_SAMPLER_INDEPENDENT)
        return rng_float(&s->rng);
    uint32_t seed[3];
    sampler_seeds(s, seed);
    uint32_t i = sampler_shuffled(s, seed[0]);
    float u = sampler_to_float(util_reverse_bits(sampler_lk_permute(i, seed[1])));
    s->dim++;
    return u;
}

#endif
