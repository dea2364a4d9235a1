/* Integer hashing for counter-based random numbers, and keyed bijections built from it. */
#ifndef CLPT_SAMPLER_HASH_CL
#define CLPT_SAMPLER_HASH_CL

#include "shared/compat.h"

/* Chris Wellons' "lowbias32" integer hash (hash-prospector), a bijection on 32 bits. */
static inline u32 hash_u32(u32 x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

/* The top 24 bits as a float in [0, 1). */
static inline float u32_to_unit_float(u32 x) { return (float)(x >> 8) * 0x1.0p-24f; }

/* A new key from a key (a hash value) and a value, with one hash: for a fixed key, distinct
 * values give distinct results (multiplication by an odd number, xor with the key and
 * hash_u32 are bijections). */
static inline u32 hash_combine(u32 key, u32 value) { return hash_u32(key ^ (value * 0x9e3779b9u)); }

/* Bit reversal of a 32-bit word (OpenCL C 1.2 has no builtin for it). */
static inline u32 reverse_bits_u32(u32 x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}

/* A keyed pseudo-random permutation of [0, n) for any n >= 1: permute_index(., n, key) is a
 * bijection of [0, n), and over keys the images of two distinct indices are close to a
 * uniformly random pair of distinct values (tested by
 * SamplerStratified.TwoSamplesTakeAUniformPairOfStrata).
 *
 * The role is that of A. Kensler's permute() ("Correlated Multi-Jittered Sampling", Pixar
 * Technical Memo 13-01, 2013): a hash-based bijection of [0, n) for any n, evaluated for one
 * index without building the permutation. Kensler's construction (a keyed bijection of the
 * covering power-of-two domain made of multiplications and masked xor-shifts, with
 * "cycle walking" back into [0, n)) and our own variants of it fail that pair test badly
 * (p ~ 0 for n = 7, 12, 16 and 64 over 65536 keys, measured off-line): such maps on a few
 * bits form small, structured families. Ours is the "swap-or-not" shuffle of V. T. Hoang,
 * B. Morris and P. Rogaway ("An Enciphering Scheme Based on a Card Shuffle", CRYPTO 2012),
 * written from the paper's description: round r draws K_r uniform in [0, n); the index x
 * and its partner x' = (K_r - x) mod n swap when a keyed bit function of max(x, x') is 1.
 * Each round is an involution of [0, n) itself (no cycle walking), and the joint law of a
 * pair of indices approaches the uniform one geometrically with the rounds. Measured
 * off-line over 4 * 10^6 keys, the chi-square divergence of that law from uniform is
 * about 1e-2 at 6 rounds, 1e-3 at 8, 1e-4 at 10 and at most 5e-5 at 12 (n = 3 to 64),
 * i.e. under 1 % rms per pair of values; hence 12. The round keys are an LCG stream
 * started from the key, which must itself be a hash value (its high bits choose K_r).
 * Cost: about 15 integer operations per round. */
#define PERMUTE_ROUNDS 12
static inline u32 permute_index(u32 i, u32 n, u32 key) {
  u32 state = key; /* already a hash value */
  for (int r = 0; r < PERMUTE_ROUNDS; ++r) {
    state = state * 0x2c1b3c6du + 0x297a2d39u;
    const u32 round_key = state ^ (state >> 15);
    const u32 k = mul_hi(round_key, n);                    /* uniform in [0, n) */
    const u32 partner = k - i + (n & (0u - (u32)(k < i))); /* (k - i) mod n */
    const u32 top = max(i, partner);                       /* the same for both of a pair */
    const u32 swap = 0u - (((top ^ round_key) * 0x9e3779b1u) >> 31);
    i ^= (i ^ partner) & swap; /* branch-free: PoCL vectorises it across work-items */
  }
  return i;
}

#endif
