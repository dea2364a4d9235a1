/* The part of a vertex's light an irradiance cache stands for, for the image kernels that
 * read one (ic: ic_path.cl; pm --final-gather-cache: photon/pm_radiance.cl). At a vertex x
 * with kd = bsdf_diffuse_factor (the Lambertian part of the BSDF), the indirect light splits
 * into kd E(x), with E the irradiance the cache interpolates, and the rest of the BSDF,
 * (f - kd) |cos| / pdf per BSDF sample, which the integrator estimates as it would without a
 * cache (ic: one path traced sample; pm: its final gather rays). Where no record covers x,
 * kd counts as 0 and the whole BSDF is sampled: unbiased there, at the cost of the method
 * without a cache. */
#ifndef CLPT_INTEGRATORS_IC_DIFFUSE_PART_CL
#define CLPT_INTEGRATORS_IC_DIFFUSE_PART_CL

#include "bsdf/bsdf.cl"
#include "integrators/estimators/ic/lookup.cl"
#include "shared/render_types.h"

/* An image kernel's cache arguments: the cache, the pixels that placed a record
 * (--ic-show-records) and three lookup counters per pixel (IcCounts). */
#define IC_IMAGE_ARGS IC_CACHE_ARGS, __global const u32 *marks, __global u32 *lookup_counts

/* Lookup counters of one work-item: lookups, records they interpolated, lookups that found
 * none. */
typedef struct IcCounts {
  u32 lookups, used, misses;
} IcCounts;

/* Adds a work-item's counters to its pixel's (only when it looked up: a kernel bound to no
 * cache has no per-pixel counters). */
static inline void ic_store_counts(__global u32* lookup_counts, u32 pixel, const IcCounts* c) {
  if (c->lookups == 0u) return;
  lookup_counts[3u * pixel] += c->lookups;
  lookup_counts[3u * pixel + 1u] += c->used;
  lookup_counts[3u * pixel + 2u] += c->misses;
}

/* E(x) at vertex sh (normals oriented to wo) with `depth` bounces before it, and in *kd the
 * diffuse factor the cache stands for there: the light it adds is kd E. Both 0 where the
 * cache does not stand for x (no bounce left for indirect light, no diffuse part, no record
 * covering x, or an empty cache). */
static inline float3 ic_diffuse_irradiance(__constant const RenderParams* p, const IcCache* cache,
                                           const SurfaceHit* sh, float3 wo, u32 depth,
                                           IcCounts* counts,
                                           float3* kd) {
  *kd = (float3)(0.0f);
  if (depth + 1u >= p->max_depth || cache->ic->record_count == 0u) return (float3)(0.0f);
  const float3 f = bsdf_diffuse_factor(sh, wo);
  if (is_black(f)) return (float3)(0.0f);
  ++counts->lookups;
  const IcEstimate est = ic_lookup(cache, sh->p, sh->ns, depth);
  counts->used += est.records;
  if (!(est.weight > 0.0f)) {
    ++counts->misses;
    return (float3)(0.0f);
  }
  *kd = f;
  return est.e;
}

/* (f - kd) |cos| / pdf for BSDF sample bs at sh: the part of bs's weight the cache does not
 * stand for. kd is constant over wo's side, so it only counts for directions there. */
static inline float3 ic_rest_weight(const SurfaceHit* sh, const BsdfSample* bs, float3 kd) {
  if (bs->is_delta || is_black(kd)) return bs->weight;
  if (gltf_is_lambert(&sh->bsdf)) return (float3)(0.0f); /* f = kd exactly */
  const float c = dot(sh->ns, bs->wi);
  if (!(c > 0.0f) || !(dot(sh->ng, bs->wi) > 0.0f)) return bs->weight;
  return bs->weight - kd * (c / bs->pdf_w);
}

#endif
