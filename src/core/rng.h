/* rng.h - counter-based random numbers: a value is a hash of (seed, stream, sample, dimension).
 *
 * A pixel's samples never depend on which thread renders it or in what order: the stream
 * is the pixel index (or a photon / light-ray index), the sample is the sample index, and
 * the dimension counts the numbers drawn so far on that path. An image thus depends on
 * the seed and the sample count only. The hash is two rounds of the SplitMix64 finalizer
 * (Steele, Lea, Flood 2014), which passes BigCrush when used as a counter-based generator. */
#ifndef BRUME_CORE_RNG_H
#define BRUME_CORE_RNG_H

#include <stdint.h>

typedef struct rng {
    uint64_t key;     /* hash of (seed, stream, sample) */
    uint64_t counter; /* dimension: how many numbers this sequence has produced */
} rng;

static inline uint64_t rng_mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* The sequence for one (seed, stream, sample). Distinct triples give independent sequences. */
static inline rng rng_make(uint64_t seed, uint64_t stream, uint64_t sample)
{
    uint64_t k = rng_mix64(seed + 0x9e3779b97f4a7c15ULL);
    k = rng_mix64(k ^ (stream + 0x632be59bd9b4e019ULL));
    k = rng_mix64(k ^ (sample + 0x85157af5a3f4b8d1ULL));
    return (rng){k, 0};
}

static inline uint64_t rng_next_u64(rng *r)
{
    uint64_t c = r->counter++;
    return rng_mix64(rng_mix64(r->key ^ (c * 0x9e3779b97f4a7c15ULL)) + c);
}

/* Uniform in [0, 1), 53 bits. */
static inline double rng_next(rng *r) { return (double)(rng_next_u64(r) >> 11) * 0x1.0p-53; }

#endif
