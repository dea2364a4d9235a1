/* Jittered stratified sampling over a pixel's spp_total samples (--sampler=stratified).
 *
 * A 2D dimension pair is stratified as an nx x ny grid with nx * ny = n (the pixel's sample
 * count), nx the largest divisor of n not above sqrt(n), so the grid is as square as n
 * allows (a prime n gives a 1 x n grid of strips). Each sample takes one cell, chosen by a
 * keyed permutation of the sample index, and a uniformly jittered point inside it. The
 * permutation is keyed per (pixel, pair), so different pairs of one path pair their cells
 * at random: this is "padding" of low-dimensional stratified patterns (Kollig & Keller,
 * "Efficient multidimensional sampling", Eurographics 2002; Pharr, Jakob & Humphreys,
 * "Physically Based Rendering", 3rd ed., 7.3 StratifiedSampler, which shuffles the samples
 * of every dimension pair). A 1D dimension is split into n strata, one sample each,
 * permuted per (pixel, dimension).
 *
 * Every sample is a pure function of (key, dimension, sample index, n), so nothing is
 * carried between passes. Each sample on its own is uniformly distributed over [0,1)^2
 * (a uniformly random cell and a uniform point in it), so a render stopped before all n
 * samples is unbiased, only less well stratified. */
#ifndef CLPT_SAMPLER_STRATIFIED_CL
#define CLPT_SAMPLER_STRATIFIED_CL

#include "sampler/hash.cl"

/* nx of the nx x ny grid for n samples: the largest divisor of n that is <= sqrt(n). */
static inline u32 stratified_grid_width(u32 n) {
  if (n <= 1u) return 1u;
  u32 r = (u32)sqrt((float)n);
  r = min(r, 0xffffu);
  while (r > 1u && r * r > n) --r;
  while (r < 0xffffu && (r + 1u) * (r + 1u) <= n) ++r;
  while (n % r != 0u) --r; /* ends at 1 at the latest */
  return r;
}

/* A point of stratum `stratum` of n equal strata of [0,1), jittered by `bits` (a uniform
 * 32-bit hash). Computed in 24-bit fixed point so the result lies in
 * [stratum / n, (stratum + 1) / n) exactly, without rounding across the stratum's borders:
 * the result is f / 2^24 with f = ceil((stratum 2^24 + t) / n) for t in [0, 2^24 - n], so
 * ceil(stratum 2^24 / n) <= f <= ceil((stratum + 1) 2^24 / n) - 1 < (stratum + 1) 2^24 / n.
 * One 64-bit division (on PoCL faster than a float estimate with exact correction loops).
 * Beyond 2^24 strata (not representable in a float's 24 bits) it degrades to a plain
 * jittered float. Results are strictly below 1. */
static inline float stratum_to_unit(u32 stratum, u32 n, u32 bits) {
  if (n > 0x1000000u)
    return fmin(((float)stratum + u32_to_unit_float(bits)) / (float)n, 0x1.fffffep-1f);
  const u32 t = mul_hi(bits, 0x1000001u - n) + (n - 1u); /* in [n - 1, 2^24 - 1] */
  const ulong f = (((ulong)stratum << 24) + (ulong)t) / (ulong)n;
  return (float)f * 0x1.0p-24f;
}

/* One jittered stratum of n per sample, permuted per key (one key per pixel and dimension).
 * Also the Latin hypercube's value for one dimension (lhs.cl). Needs sample_index < n. */
static inline float stratified_1d(u32 key, u32 sample_index, u32 n) {
  const u32 stratum = permute_index(sample_index, n, key);
  return stratum_to_unit(stratum, n, hash_combine(key ^ 0x68e31da4u, sample_index));
}

/* One jittered cell of the nx x (n / nx) grid per sample, permuted per key (one key per
 * pixel and dimension pair). Needs sample_index < n and nx dividing n. */
static inline float2 stratified_2d(u32 key, u32 sample_index, u32 n, u32 nx) {
  const u32 cell = permute_index(sample_index, n, key);
  const u32 jitter = hash_combine(key ^ 0x68e31da4u, sample_index);
  return (float2)(stratum_to_unit(cell % nx, nx, jitter),
                  stratum_to_unit(cell / nx, n / nx, hash_u32(jitter ^ 0xb5297a4du)));
}

#endif
