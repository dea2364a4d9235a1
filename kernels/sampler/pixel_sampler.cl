/* The pixel samplers (--sampler), dimension-indexed. Every random number of a path has a
 * fixed dimension index (sampler/dimensions.h), so a sample is a pure function of (seed, pixel, sample index,
 * dimension): passes of any size give the same image as one long run, and quasi-Monte
 * Carlo samplers can stratify each dimension (pair) across a pixel's samples.
 *
 * Interface used by the integrators:
 *   Sampler sampler_init(params, pixel, sample_index);
 *   float  sample_1d(const Sampler*, dimension);
 *   float2 sample_2d(const Sampler*, dimension);  -- dimensions (d, d+1) as one pair
 * Values are in [0, 1).
 *
 * Samplers (params->sampler, see docs/sampling.md):
 *   SAMPLER_INDEPENDENT  a counter-based hash per (pixel, sample, dimension)
 *   SAMPLER_STRATIFIED   jittered grid per pair, n strata per 1D dimension (stratified.cl)
 *   SAMPLER_LHS          Latin hypercube per dimension (lhs.cl)
 *   SAMPLER_SOBOL        shuffled, Owen-scrambled Sobol (0,2)-sequence per pair (sobol.cl)
 * Stratified and lhs divide among params->spp_total samples; for a sample index outside
 * [0, spp_total) (spp_total 0: not known) they fall back to independent sampling. */
#ifndef CLPT_SAMPLER_PIXEL_SAMPLER_CL
#define CLPT_SAMPLER_PIXEL_SAMPLER_CL

/* clang-format off: render_types.h must come first, it defines u32, which dimensions.h uses */
#include "shared/render_types.h"
/* clang-format on */
#include "sampler/dimensions.h"
#include "sampler/hash.cl"
#include "sampler/lhs.cl"
#include "sampler/sobol.cl"
#include "sampler/stratified.cl"

/* Salts that separate the keys of the different uses of a dimension index. */
#define SAMPLER_SALT_1D 0x3c6ef372u
#define SAMPLER_SALT_2D 0xa54ff53au

typedef struct Sampler {
  u32 type;         /* SamplerType actually used for this sample (after the fallback) */
  u32 key;          /* hash of (seed, pixel): the pixel's randomisation */
  u32 sample_index; /* index of this sample within the pixel */
  u32 spp_total;    /* samples the pixel will take; 0 if unknown */
  u32 grid_x;       /* stratified: columns of the 2D grid (a divisor of spp_total) */
  u32 sample_key;   /* independent: hash of (key, sample index), once per sample */
} Sampler;

static inline Sampler sampler_init(__constant const RenderParams* params, u32 pixel,
                                   u32 sample_index) {
  Sampler s;
  s.type = params->sampler;
  s.key = hash_u32(hash_u32(params->seed) ^ pixel);
  s.sample_index = sample_index;
  s.spp_total = params->spp_total;
  s.grid_x = 1u;
  s.sample_key = hash_u32(s.key + sample_index * 0x9e3779b9u);
  if (s.type == SAMPLER_STRATIFIED || s.type == SAMPLER_LHS) {
    /* Strata need the sample count; without it, or past it, sample independently. */
    if (sample_index >= s.spp_total)
      s.type = SAMPLER_INDEPENDENT;
    else if (s.type == SAMPLER_STRATIFIED)
      s.grid_x = stratified_grid_width(s.spp_total);
  } else if (s.type != SAMPLER_SOBOL) {
    s.type = SAMPLER_INDEPENDENT;
  }
  return s;
}

/* Independent sampling: a hash of (pixel key, sample index, dimension). */
static inline float independent_1d(const Sampler* s, u32 dimension) {
  const u32 h = hash_u32(s->sample_key ^ (dimension * 0x85ebca6bu));
  return u32_to_unit_float(hash_u32(h + dimension));
}

static inline float sample_1d(const Sampler* s, u32 dimension) {
  float v;
  switch (s->type) {
    case SAMPLER_STRATIFIED:
    case SAMPLER_LHS:
      v = stratified_1d(hash_combine(s->key ^ SAMPLER_SALT_1D, dimension), s->sample_index,
                        s->spp_total);
      break;
    case SAMPLER_SOBOL:
      v = sobol_1d(hash_combine(s->key ^ SAMPLER_SALT_1D, dimension), s->sample_index);
      break;
    default:
      v = independent_1d(s, dimension);
      break;
  }
  return fmin(v, 0x1.fffffep-1f);
}

static inline float2 sample_2d(const Sampler* s, u32 dimension) {
  float2 v;
  switch (s->type) {
    case SAMPLER_STRATIFIED:
      v = stratified_2d(hash_combine(s->key ^ SAMPLER_SALT_2D, dimension), s->sample_index,
                        s->spp_total, s->grid_x);
      break;
    case SAMPLER_LHS: /* two independent Latin hypercube dimensions */
      v = (float2)(lhs_1d(hash_combine(s->key ^ SAMPLER_SALT_1D, dimension), s->sample_index,
                          s->spp_total),
                   lhs_1d(hash_combine(s->key ^ SAMPLER_SALT_1D, dimension + 1u), s->sample_index,
                          s->spp_total));
      break;
    case SAMPLER_SOBOL:
      v = sobol_2d(hash_combine(s->key ^ SAMPLER_SALT_2D, dimension), s->sample_index);
      break;
    default:
      v = (float2)(independent_1d(s, dimension), independent_1d(s, dimension + 1u));
      break;
  }
  return fmin(v, (float2)(0x1.fffffep-1f));
}

#endif
