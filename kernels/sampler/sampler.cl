/* Dimension-indexed samplers. Every random number of a path has a fixed dimension index
 * (sampler/dimensions.h), so a sample is a pure function of (seed, pixel, sample index,
 * dimension): passes of any size give the same image as one long run, and quasi-Monte
 * Carlo samplers can stratify each dimension.
 * Independent sampler: a counter-based hash (no state carried between work-items). */
#ifndef CLPT_SAMPLER_SAMPLER_CL
#define CLPT_SAMPLER_SAMPLER_CL

#include "sampler/dimensions.h"

/* Chris Wellons' "lowbias32" integer hash (hash-prospector), a bijection on 32 bits. */
inline u32 hash_u32(u32 x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

typedef struct Sampler {
  u32 key; /* hash of (seed, pixel, sample index) */
} Sampler;

inline Sampler sampler_init(u32 seed, u32 pixel, u32 sample_index) {
  Sampler s;
  s.key = hash_u32(hash_u32(hash_u32(seed) ^ pixel) + sample_index);
  return s;
}

/* A float in [0, 1): the top 24 bits of the hash. */
inline float sample_1d(const Sampler* s, u32 dimension) {
  const u32 h = hash_u32(hash_u32(s->key ^ (dimension * 0x9e3779b9u)) + dimension);
  return (float)(h >> 8) * 0x1.0p-24f;
}

inline float2 sample_2d(const Sampler* s, u32 dimension) {
  return (float2)(sample_1d(s, dimension), sample_1d(s, dimension + 1));
}

#endif
