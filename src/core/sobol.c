/* sobol.c - padded, Owen-scrambled Sobol points (sobol.h; derivation in docs/sampling.md). */
#include "core/sobol.h"

#include "core/hash.h"

/* The bits of x in reverse order: bits reversed within each byte, then the bytes. */
static inline uint32_t reverse_bits32(uint32_t x)
{
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    return __builtin_bswap32(x);
}

/* Dimension 1 before its final bit reversal (see sobol_u32): the superset-sum over GF(2). */
static inline uint32_t pascal_reversed(uint32_t i)
{
    i ^= (i >> 1) & 0x55555555u;
    i ^= (i >> 2) & 0x33333333u;
    i ^= (i >> 4) & 0x0f0f0f0fu;
    i ^= (i >> 8) & 0x00ff00ffu;
    i ^= (i >> 16) & 0x0000ffffu;
    return i;
}

/* Dimension 0: direction numbers v_k = 2^(31-k) (the identity matrix), i.e. the bits of i
 * reversed. Dimension 1: the primitive polynomial x + 1 (degree s = 1, m_1 = 1) gives the
 * recurrence m_k = 2 m_{k-1} xor m_{k-1}; with v_k = m_k 2^(32-k) that is
 * v_k = v_{k-1} xor (v_{k-1} >> 1), v_0 = 2^31: the columns of the Pascal matrix mod 2,
 * whose entry (digit j, index bit k) is binomial(k, j) mod 2, i.e. 1 when the bits of j are
 * a subset of those of k (Lucas). Digit j of the point is then the parity of the index bits
 * k that contain j: a superset-sum over GF(2), five masked shift-xor steps, after which the
 * digits are reversed into place. tests/test_sobol.c checks it against the recurrence. */
uint32_t sobol_u32(uint32_t i, int dim) { return reverse_bits32(dim == 0 ? i : pascal_reversed(i)); }

/* Laine and Karras' hash-based permutation as given by Burley 2020 (Listing 2), on the
 * bit-reversed value: adding the seed and xoring with products by even constants each
 * change bit k only as a function of bits 0..k. */
static inline uint32_t laine_karras(uint32_t x, uint32_t seed)
{
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

/* After reversing back every bit depends only on the more significant ones: a nested
 * (Owen-type) scramble. */
uint32_t sobol_owen_scramble(uint32_t x, uint32_t seed) { return reverse_bits32(laine_karras(reverse_bits32(x), seed)); }

/* With r(x) the bit reversal and LK the permutation above, the shuffled index is
 * j = r(LK_pair(r(index))), dimension 0 of it is x = r(j), dimension 1 x = r(P(j)) (P: the
 * superset-sum), and the scrambled coordinate r(LK_dim(r(x))) = r(LK_dim(j or P(j))). */
void sobol_padded_pair(uint64_t key, uint32_t index, uint32_t pair, uint32_t x[2])
{
    /* the pair's index shuffle (low half of the hash), the first coordinate's scramble
     * (high half) and the second's (both halves mixed by an odd multiplier) */
    uint64_t h = hash_mix64(key ^ (((uint64_t)pair + 1u) * 0xd1342543de82ef95ULL));
    uint32_t seed0 = (uint32_t)(h >> 32), seed1 = (seed0 ^ (uint32_t)h) * 0x2c1b3c6du + 0x297a2d39u;
    uint32_t j = reverse_bits32(laine_karras(reverse_bits32(index), (uint32_t)h));
    x[0] = reverse_bits32(laine_karras(j, seed0));
    x[1] = reverse_bits32(laine_karras(pascal_reversed(j), seed1));
}
