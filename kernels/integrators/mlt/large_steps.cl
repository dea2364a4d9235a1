/* A chain's pool of large steps (MltLargeSteps, host/integrators/metropolis.h): a large step
 * proposes a fresh uniform vector, independent of the chain's state, so its target value is a
 * sample of the chain's normalisation b as the bootstrap's paths are, and the proposals since
 * the last restart are a pool to restart chains from, as the bootstrap's paths were for the
 * first start. */
#ifndef CLPT_INTEGRATORS_MLT_LARGE_STEPS_CL
#define CLPT_INTEGRATORS_MLT_LARGE_STEPS_CL

#include "sampler/pss.cl"

/* Counts a large step's proposal of key `key` and target value `target` into the chain's
 * pool (MltLargeSteps): its sum by Kahan's compensated summation (float sums of many small
 * values drift otherwise), and the reservoirs: the proposal replaces each pick, independently,
 * with probability target / (the targets' sum with it), so that each pick is each proposal in
 * proportion to its target. */
static inline void mlt_count_large_step(MltLargeSteps* ls, u32 key, float target) {
  ls->count += 1u;
  if (!(target > 0.0f)) return;
  const float y = target - ls->compensation;
  const float t = ls->sum + y;
  ls->compensation = (t - ls->sum) - y;
  ls->sum = t;
  ls->sum_sq += target * target;
  for (u32 k = 0; k < MLT_PICKS; ++k)
    if (u32_to_unit_float(hash_combine(key ^ PSS_SALT_PICK, k)) * t < target) ls->pick[k] = key;
}

#endif
