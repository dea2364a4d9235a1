/* Dimension-indexed samplers. Every random number of a path has a fixed dimension index
 * (sampler/dimensions.h), so a sample is a pure function of (seed, pixel, sample index,
 * dimension): passes of any size give the same image as one long run, and quasi-Monte
 * Carlo samplers can stratify each dimension (pair) across a pixel's samples.
 *
 * Interface used by the integrators:
 *   Sampler sampler_init(params, pixel, sample_index);
 *   float  sample_1d(const Sampler*, dimension);
 *   float2 sample_2d(const Sampler*, dimension);  -- dimensions (d, d+1) as one pair
 * Values are in [0, 1). */
#ifndef CLPT_SAMPLER_SAMPLER_CL
#define CLPT_SAMPLER_SAMPLER_CL

#include "sampler/dimensions.h"
#include "sampler/hash.cl"
#include "shared/render_types.h"

typedef struct Sampler {
  u32 type;         /* SamplerType */
  u32 key;          /* hash of (seed, pixel): the pixel's randomisation */
  u32 sample_index; /* index of this sample within the pixel */
  u32 spp_total;    /* samples the pixel will take; 0 if unknown */
} Sampler;

inline Sampler sampler_init(__constant const RenderParams* params, u32 pixel, u32 sample_index) {
  Sampler s;
  s.type = params->sampler;
  s.key = hash_u32(hash_u32(params->seed) ^ pixel);
  s.sample_index = sample_index;
  s.spp_total = params->spp_total;
  return s;
}

/* Independent sampling: a hash of (pixel key, sample index, dimension). */
inline float independent_1d(const Sampler* s, u32 dimension) {
  const u32 h = hash_u32(hash_u32(s->key + s->sample_index * 0x9e3779b9u) ^ (dimension * 0x85ebca6bu));
  return u32_to_unit_float(hash_u32(h + dimension));
}

inline float sample_1d(const Sampler* s, u32 dimension) { return independent_1d(s, dimension); }

inline float2 sample_2d(const Sampler* s, u32 dimension) {
  return (float2)(independent_1d(s, dimension), independent_1d(s, dimension + 1u));
}

#endif
