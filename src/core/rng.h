/* rng.h - counter-based random numbers: a value is a hash of (seed, stream, sample, dimension).
 *
 * A pixel's samples never depend on which thread renders it or in what order: the stream
 * is the pixel index (or a photon / light-ray index), the sample is the sample index, and
 * the dimension counts the numbers drawn so far on that path. An image thus depends on
 * the seed and the sample count only. The hash is two rounds of the SplitMix64 finalizer
 * (Steele, Lea, Flood 2014), which passes BigCrush when used as a counter-based generator.
 *
 * A camera sample's sequence may instead be made by rng_make_qmc: its first `qmc_dims`
 * dimensions are then the pixel's padded, Owen-scrambled Sobol points (core/sobol.h) at
 * the sample index, the dimensions past them the same hash as rng_make's. Every value is
 * still uniform on [0, 1) and independent across pixels and seeds; within a pixel the
 * samples of each dimension pair are stratified (docs/sampling.md). */
#ifndef BRUME_CORE_RNG_H
#define BRUME_CORE_RNG_H

#include <stdint.h>

#include "core/hash.h"
#include "core/sobol.h"

typedef struct rng {
    uint64_t key;      /* hash of (seed, stream, sample) */
    uint64_t counter;  /* dimension: how many numbers this sequence has produced */
    uint64_t qmc_key;  /* hash of (seed, stream): the Sobol scrambles of the stream */
    uint32_t index;    /* the Sobol sample index (the sample) */
    uint32_t qmc_dims; /* dimensions [0, qmc_dims) are Sobol points; 0: none */
    uint32_t odd;      /* the Sobol point of dimension odd_dim, made with its even partner */
    uint32_t odd_dim;  /* 0 (even, never asked for) until a pair has been made */
} rng;

/* The sequence for one (seed, stream, sample). Distinct triples give independent sequences. */
static inline rng rng_make(uint64_t seed, uint64_t stream, uint64_t sample)
{
    uint64_t k = hash_mix64(seed + 0x9e3779b97f4a7c15ULL);
    k = hash_mix64(k ^ (stream + 0x632be59bd9b4e019ULL));
    k = hash_mix64(k ^ (sample + 0x85157af5a3f4b8d1ULL));
    return (rng){k, 0, 0, 0, 0, 0, 0};
}

/* The sequence of rng_make(seed, stream, sample) whose first `dims` dimensions are the
 * stream's scrambled Sobol points at index `sample` (the sample index within the stream). */
static inline rng rng_make_qmc(uint64_t seed, uint64_t stream, uint32_t sample, uint32_t dims)
{
    rng r = rng_make(seed, stream, sample);
    uint64_t q = hash_mix64(seed ^ 0x5851f42d4c957f2dULL);
    r.qmc_key = hash_mix64(q ^ (stream + 0x14057b7ef767814fULL));
    r.index = sample;
    r.qmc_dims = dims;
    return r;
}

static inline uint64_t rng_next_u64(rng *r)
{
    uint64_t c = r->counter++;
    return hash_mix64(hash_mix64(r->key ^ (c * 0x9e3779b97f4a7c15ULL)) + c);
}

/* The next number's 64 bits: in a Sobol dimension the 32 bits of the point come first and
 * the hash fills those below them. rng_next and rng_nextf keep the high bits. */
static inline uint64_t rng_next_bits(rng *r)
{
    uint64_t c = r->counter;
    uint64_t h = rng_next_u64(r);
#if !defined(RNG_HASH_ONLY) /* the GPU's stage kernels: their sequences have no Sobol dimensions */
    if (c < r->qmc_dims) {
        uint32_t x;
        if ((c & 1u) && r->odd_dim == c) {
            x = r->odd;
        } else {
            uint32_t p[2];
            sobol_padded_pair(r->qmc_key, r->index, (uint32_t)(c >> 1), p);
            x = p[c & 1u];
            r->odd = p[1];
            r->odd_dim = (uint32_t)c | 1u;
        }
        h = ((uint64_t)x << 32) | (h >> 32);
    }
#endif
    return h;
}

/* Uniform in [0, 1), 53 bits: in a Sobol dimension the value stays in the point's cell of
 * width 2^-32. */
static inline double rng_next(rng *r) { return (double)(rng_next_bits(r) >> 11) * 0x1.0p-53; }

/* Uniform in (0, 1), the single-precision stages' (docs/gpu.md), with no double arithmetic:
 * the centre of the cell of width 2^-23 that holds rng_next's number, so that its mean is
 * exactly 1/2 (truncation to 24 bits would bias every estimate by about 2^-25) and 1 - u
 * is never 0. Both operations are exact in float. */
static inline float rng_nextf(rng *r)
{
    return ((float)(uint32_t)(rng_next_bits(r) >> 41) + 0.5f) * 0x1.0p-23f;
}

/* The value of dimension dim (a number taken earlier with counter++ and made only when
 * needed); the counter is left where it is. */
static inline double rng_at(rng *r, uint64_t dim)
{
    const uint64_t c = r->counter;
    r->counter = dim;
    const double v = rng_next(r);
    r->counter = c;
    return v;
}
static inline float rng_atf(rng *r, uint64_t dim)
{
    const uint64_t c = r->counter;
    r->counter = dim;
    const float v = rng_nextf(r);
    r->counter = c;
    return v;
}

#endif
