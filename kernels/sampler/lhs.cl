/* Latin hypercube sampling, also called N-rooks (--sampler=lhs).
 *
 * M. D. McKay, R. J. Beckman, W. J. Conover, "A comparison of three methods for selecting
 * values of input variables in the analysis of output from a computer code",
 * Technometrics 21(2), 1979; A. B. Owen, "Monte Carlo variance of scrambled net
 * quadrature", 1997, shows its variance is never worse than n/(n-1) times independent
 * sampling's and removes the additive part of the integrand's variance.
 *
 * Each dimension d on its own is split into n = spp_total strata; sample i of the pixel
 * falls in stratum pi_d(i), jittered, where pi_d is a keyed permutation of [0, n) per
 * (pixel, dimension) (permute_index in hash.cl, after Kensler 2013). Independent
 * permutations per dimension pair the strata of different dimensions at random, so any
 * two dimensions (also the two of a 2D pair) form an n-rooks pattern. The 1D value is the
 * same computation as the stratified sampler's 1D value. */
#ifndef CLPT_SAMPLER_LHS_CL
#define CLPT_SAMPLER_LHS_CL

#include "sampler/stratified.cl"

/* key: one per (pixel, dimension). Needs sample_index < n. */
static inline float lhs_1d(u32 key, u32 sample_index, u32 n) {
  return stratified_1d(key, sample_index, n);
}

#endif
