/* Metropolis chains on a toy target in primary sample space, for the MltStationary tests
 * (tests/mlt_test.cpp): the sampler's lazy vector (sampler/pss.cl) and its accept / reject,
 * without a scene. The target reads u2 only where u0 < 0.5, as a path reads a dimension only
 * when it gets that far:
 *   f(u) = g(u0, u1) * (u0 < 0.5 ? h(u2) : 1),
 *   g = 0.2 + exp(-|(u0, u1) - (0.3, 0.6)|^2 / (2 * 0.15^2)),  h = 0.25 + 1.5 u2^2.
 * Each chain starts at a fresh uniform vector and takes `iterations` proposals; out[c] is its
 * final state (u0, u1, u2, f).
 * rule: 0 Metropolis (pss_acceptance and pss_reject); the broken variants the test must
 * catch: 1 a rejected proposal's coordinates are not restored; 2 acceptance min(1, sqrt of
 * the ratio), whose chain samples sqrt(f). */
#define CLPT_PRIMARY_SAMPLE_SPACE 1
#include "sampler/sampler.cl"

inline float toy_target(const Sampler* s, float4* u) {
  const float2 a = sample_2d(s, 0u);
  const float dx = a.x - 0.3f, dy = a.y - 0.6f;
  float f = 0.2f + exp(-(dx * dx + dy * dy) / (2.0f * 0.15f * 0.15f));
  float u2 = -1.0f;
  if (a.x < 0.5f) {
    u2 = sample_1d(s, 2u);
    f *= 0.25f + 1.5f * u2 * u2;
  }
  *u = (float4)(a.x, a.y, u2, f);
  return f;
}

__kernel void mlt_toy_chains(__global PssCoord* coords, u32 chains, u32 iterations,
                             float large_step, float sigma, u32 rule, u32 seed,
                             __global float4* out) {
  const u32 c = get_global_id(0);
  if (c >= chains) return;
  const u32 dims = 4u; /* one more than the target reads: never read, still restored */
  __global PssCoord* vector = coords + (size_t)c * dims;
  MltChain ch;
  pss_chain_start(&ch, vector, 1u, dims, hash_combine(hash_u32(seed), c));
  float4 x;
  const Sampler start = pss_current(&ch, vector, 1u, dims);
  float fx = toy_target(&start, &x);
  const u32 key = pss_chain_key(seed, c);
  for (u32 i = 0; i < iterations; ++i) {
    const Sampler s = pss_propose(&ch, vector, 1u, dims, key, large_step, sigma);
    float4 y;
    const float fy = toy_target(&s, &y);
    const float a = rule == 2u ? fmin(1.0f, sqrt(fy / fx)) : pss_acceptance(fy, fx);
    if (pss_accept_u(&s) < a) {
      pss_accept(&ch, &s);
      x = y;
      fx = fy;
    } else if (rule != 1u) {
      pss_reject(&ch, &s);
    }
  }
  out[c] = x;
}

/* pss_gaussian for keys 0..n-1 at dimension 3 (the small steps' normal numbers). */
__kernel void mlt_gaussians(u32 n, __global float* out) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  out[i] = pss_gaussian(hash_u32(i), 3u);
}

/* pss_gaussian2 for keys 0..n-1 at dimension 3: out[2i], out[2i + 1] one pair. */
__kernel void mlt_gaussian_pairs(u32 n, __global float* out) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  const float2 g = pss_gaussian2(hash_u32(i), 3u);
  out[2u * i] = g.x;
  out[2u * i + 1u] = g.y;
}

#include "integrators/mlt/large_steps.cl"

/* A pool of n large steps of targets t[0..n-1] per trial (keys new per trial): out[trial]
 * holds the index of each of its MLT_PICKS picks (n: none) and the compensated sum. */
__kernel void mlt_pool_picks(u32 trials, u32 n, __global const float* t, __global float* sums,
                             __global u32* picks) {
  const u32 trial = get_global_id(0);
  if (trial >= trials) return;
  MltLargeSteps ls = {0.0f, 0.0f, 0.0f, 0u, {0u, 0u, 0u, 0u}};
  for (u32 k = 0; k < n; ++k) mlt_count_large_step(&ls, hash_combine(hash_u32(trial), k), t[k]);
  sums[trial] = ls.sum - ls.compensation;
  for (u32 j = 0; j < MLT_PICKS; ++j) {
    u32 index = n;
    for (u32 k = 0; k < n; ++k)
      if (t[k] > 0.0f && ls.pick[j] == hash_combine(hash_u32(trial), k)) index = k;
    picks[trial * MLT_PICKS + j] = index;
  }
}
