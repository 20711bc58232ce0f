/* sobol.h - padded, Owen-scrambled Sobol points: the low-discrepancy part of rng.h.
 *
 * Dimensions go in pairs (0,1), (2,3), ...; each pair is the 2-D Sobol (0,2)-sequence
 * (first coordinate: van der Corput; second: the Sobol dimension of the primitive
 * polynomial x + 1, whose generator matrix is the Pascal matrix mod 2). Per key (one
 * pixel of one seed) and pair, the sample index is shuffled by a hashed nested scramble
 * that keeps aligned blocks of 2^m indices together, so pairs are decorrelated while the
 * first 2^m samples of a pixel still form a (0,m,2)-net; per key and dimension, each
 * coordinate gets a hashed nested uniform (Owen) scramble, which keeps every point
 * uniform on [0, 1) and keeps the net property (Burley 2020, "Practical Hash-based Owen
 * Scrambling", JCGT 9(4); pbrt-v4's padded Sobol sampler). docs/sampling.md has the
 * construction and the measurements. */
#ifndef BRUME_CORE_SOBOL_H
#define BRUME_CORE_SOBOL_H

#include <stdint.h>

/* Sobol dimension 0 (van der Corput) or 1 of sample index i, unscrambled, as a 32-bit
 * fixed-point fraction (value / 2^32). */
uint32_t sobol_u32(uint32_t i, int dim);

/* Nested uniform scramble of a 32-bit fraction under seed: output bit j (from the most
 * significant) is input bit j flipped by a hash of the bits above it and the seed. A
 * bijection; it maps every aligned block of 2^k values onto an aligned block of 2^k. */
uint32_t sobol_owen_scramble(uint32_t x, uint32_t seed);

/* Both coordinates, dimensions 2 pair and 2 pair + 1, of sample index of the padded,
 * scrambled sequence keyed by key, as 32-bit fixed-point fractions. */
void sobol_padded_pair(uint64_t key, uint32_t index, uint32_t pair, uint32_t x[2]);

#endif
