/* Owen-scrambled Sobol sampling (--sampler=sobol).
 *
 * The first two dimensions of the Sobol sequence form a (0,2)-sequence in base 2
 * (I. M. Sobol', 1967): every aligned block of 2^k consecutive points is a (0,k,2)-net,
 * i.e. every elementary interval [a 2^-p, (a+1) 2^-p) x [b 2^-q, (b+1) 2^-q) with
 * p + q = k holds exactly one point of the block. Dimension 0 is the van der Corput
 * sequence (the bit reversal of the index); dimension 1 xors the direction numbers
 * v_1 = 2^31, v_{j+1} = v_j ^ (v_j >> 1) for the set bits j of the index (the Pascal
 * matrix mod 2).
 *
 * This 2D sequence is used for every dimension pair of the path ("padding", as in
 * Kollig & Keller 2002), randomised per (pixel, pair) in two ways, both from
 * B. Burley, "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020:
 *  - Owen's nested uniform scrambling of each coordinate (A. B. Owen, "Randomly permuted
 *    (t,m,s)-nets and (t,s)-sequences", 1995): bit j of the value is flipped by a random
 *    function of the bits above it. Done with a hash in which every output bit depends
 *    only on the same and lower input bits (S. Laine and T. Karras, "Stratified sampling
 *    for stochastic transparency", EGSR 2011), applied to the bit-reversed value
 *    (Burley 2020, section 3). Owen scrambling maps elementary intervals onto elementary
 *    intervals of the same shape, so scrambled nets stay nets; every point on its own is
 *    uniform in [0,1)^2.
 *  - Shuffling of the sample order (Burley 2020, section 4): the sample index itself is
 *    Owen-scrambled (the same hash on its bit reversal), with a different seed per pair.
 *    The first 2^k indices then map onto one aligned block of 2^k sequence indices, still
 *    a (0,k,2)-net, but pairs (and 1D dimensions) no longer walk through the sequence in
 *    the same order, which would correlate them.
 * A 1D dimension uses the van der Corput sequence with the same two randomisations.
 *
 * The sequence is progressive: any prefix of the samples is well distributed, and every
 * power-of-two prefix is a scrambled (0,k,2)-net, so it does not need the sample count in
 * advance. Values keep the top 24 bits (a float's precision), so a pixel's 1D values
 * repeat their strata after 2^24 samples. */
#ifndef CLPT_SAMPLER_SOBOL_CL
#define CLPT_SAMPLER_SOBOL_CL

#include "sampler/hash.cl"

/* A seeded hash with the Laine-Karras property: bit j of the result is bit j of x xor a
 * function of bits 0..j-1 of x (and of the seed), so it is a bijection and, on reversed
 * bits, an Owen scramble. Allowed steps: adding a constant, multiplying by an odd number,
 * and x ^= x * (even number) (the product's bit j depends only on bits below j). Our own
 * choice of steps: the seed enters by addition and through an odd multiplier derived from
 * it (N. Vegdahl, "Building a better LK hash", 2021, showed that seed-dependent
 * multiplication improves on Laine and Karras' original, where the seed is only added);
 * the even constants are those of the Laine-Karras hash as given by Burley 2020. The seed
 * must itself be a hash value. */
static inline u32 owen_hash(u32 x, u32 seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x *= (seed >> 16) | 1u;
  x ^= x * 0xb82f1e52u;
  x += (seed << 16) | (seed >> 16);
  x ^= x * 0xc7afe638u;
  x *= (seed >> 8) | 1u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

/* Owen scrambling of a 32-bit binary fraction held in bit-reversed order (bit 0 = the
 * fraction's most significant bit); returns the scrambled fraction in normal order. */
static inline u32 owen_scramble_reversed(u32 reversed_value, u32 seed) {
  return reverse_bits_u32(owen_hash(reversed_value, seed));
}

/* Sobol dimension 1 of index i, bit-reversed. The reversed direction numbers are
 * r_1 = 1, r_{k+1} = r_k ^ (r_k << 1), i.e. the polynomial (1 + z)^(k-1) over GF(2), so bit j
 * of r_k is C(k-1, j) mod 2, which by Lucas' theorem is 1 exactly when the bits of j are a
 * subset of those of k-1. Bit j of the result, the xor of r_{m+1} over the set bits m of i,
 * is therefore the parity of the set bits of i at positions m that are supersets of j: a
 * "superset sum" over GF(2), computed bit-parallel in five steps instead of a loop over
 * the 24 bits of the index (equal for all 32-bit inputs, checked against the loop). */
static inline u32 sobol1_reversed(u32 i) {
  i ^= (i >> 1) & 0x55555555u;
  i ^= (i >> 2) & 0x33333333u;
  i ^= (i >> 4) & 0x0f0f0f0fu;
  i ^= (i >> 8) & 0x00ff00ffu;
  i ^= (i >> 16) & 0x0000ffffu;
  return i;
}

/* The sample index shuffled per seed: an Owen scramble of its bits read from the top, so
 * bit j is flipped by a function of the bits above it and indices [0, 2^k) map onto one
 * aligned block of 2^k indices. */
static inline u32 sobol_shuffle(u32 sample_index, u32 seed) {
  return owen_scramble_reversed(reverse_bits_u32(sample_index), seed);
}

/* The float in [0,1) with the top 24 bits of a 32-bit fraction. */
static inline float sobol_to_unit(u32 x) { return (float)(x >> 8) * 0x1.0p-24f; }

/* key: one per (pixel, dimension pair). */
static inline float2 sobol_2d(u32 key, u32 sample_index) {
  const u32 i = sobol_shuffle(sample_index, key);
  /* Dimension 0 is reverse_bits(i), which is i in reversed order. */
  return (float2)(sobol_to_unit(owen_scramble_reversed(i, hash_u32(key ^ 0x1b873593u))),
                  sobol_to_unit(
                      owen_scramble_reversed(sobol1_reversed(i), hash_u32(key ^ 0xcc9e2d51u))));
}

/* key: one per (pixel, dimension). Scrambled, shuffled van der Corput. */
static inline float sobol_1d(u32 key, u32 sample_index) {
  const u32 i = sobol_shuffle(sample_index, key);
  return sobol_to_unit(owen_scramble_reversed(i, hash_u32(key ^ 0x1b873593u)));
}

#endif
