/* hash.h - the SplitMix64 finalizer (Steele, Lea, Flood 2014): a 64-bit mix whose every
 * output bit depends on every input bit. The counter-based random numbers (core/rng.h), the
 * Sobol scrambles (core/sobol.c) and the procedural fields' lattice hash are made with it. */
#ifndef BRUME_CORE_HASH_H
#define BRUME_CORE_HASH_H

#include <stdint.h>

static inline uint64_t hash_mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

#endif
