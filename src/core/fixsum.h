/* fixsum.h - sums of non-negative reals as 128-bit integers: the same bits in any order.
 *
 * Floating-point addition is not associative, so a sum of doubles depends on the order of
 * its terms, and a sum spread over threads on the schedule. A fixsum counts whole units
 * (the caller's choice: a term x means x units) in 128 bits, two 64-bit words with the
 * carry made by hand (portable C11), where addition is exact and associative: partial sums
 * made in any order and merged give the same bits. Each term is truncated to a whole unit
 * (so a caller picks the unit well below the terms it cares about), terms above 2^127 units
 * count as 2^127 (a caller picks the unit so that none comes near), and a total beyond
 * 2^128 units wraps. tests/test_core.c checks the carries, the split of large terms and
 * the order independence. */
#ifndef BRUME_CORE_FIXSUM_H
#define BRUME_CORE_FIXSUM_H

#include <math.h>
#include <stdint.h>

typedef struct fixsum {
    uint64_t lo, hi; /* the count of units is hi 2^64 + lo */
} fixsum;

/* *a += x units, x >= 0, truncated to whole units. */
static inline void fixsum_add(fixsum *a, double x)
{
    uint64_t lo, hi = 0;
    if (x < 0x1p63) {
        lo = (uint64_t)(int64_t)x; /* the conversion the processor does in one instruction */
    } else { /* a term of 2^63 units or more (NaN counts as 2^127) */
        x = fmin(x, 0x1p127);
        double h = floor(x * 0x1p-64);
        lo = (uint64_t)(x - h * 0x1p64); /* exact: x and h 2^64 are multiples of x's ulp */
        hi = (uint64_t)h;
    }
    a->lo += lo;
    a->hi += hi + (a->lo < lo);
}

/* *a += b: partial sums merged. */
static inline void fixsum_merge(fixsum *a, fixsum b)
{
    a->lo += b.lo;
    a->hi += b.hi + (a->lo < b.lo);
}

/* The sum in units, rounded to a double. */
static inline double fixsum_value(fixsum a) { return (double)a.hi * 0x1p64 + (double)a.lo; }

#endif
