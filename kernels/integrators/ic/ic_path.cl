/* The image of the irradiance cache (--integrator ic): a camera path as pt's, with the
 * indirect diffuse light at its first non-delta vertex x read from the cache.
 *
 * From the camera the path passes delta-only vertices (mirrors, smooth glass) as pt does,
 * collecting the emission it sees with weight 1, to the first vertex x with a smooth lobe.
 * At x, with kd = bsdf_diffuse_factor (the Lambertian part, gltf_diffuse_factor):
 *     L(x) = Le + direct (NEE + one BSDF sample, MIS as pt)
 *          + kd E_cache(x)                                   indirect, diffuse part
 *          + (f - kd) |cos| / pdf  L_ind(y)                   indirect, the rest: path traced
 * where y is the vertex the BSDF sample finds and L_ind(y) = NEE(y) + pt's continuation from
 * y: y's radiance without y's own emission, which is x's direct light. The same L_ind is
 * what a record's hemisphere rays average (kernels/integrators/ic/records.cl), so the cache
 * stands for exactly the kd term. The rest is the whole BSDF on glossy or metal surfaces (kd
 * = 0) and the coat's share of a plastic; it is 0 on a Lambertian surface, where the BSDF
 * sample only finds direct light. Scattering off a glossy lobe continues by pt rather than
 * reading the cache at its next diffuse hit: records exist only where camera paths placed
 * them (ic_place), and a pt continuation has no bias to explain.
 *
 * Where no record covers x (a point the placement passes did not reach, as a path through
 * glass that refracted where the placement's path reflected), kd is taken as 0 and the
 * whole BSDF is path traced: unbiased there, at pt's cost. */
#ifndef CLPT_INTEGRATORS_IC_IC_PATH_CL
#define CLPT_INTEGRATORS_IC_IC_PATH_CL

#include "integrators/estimators/ic/diffuse_part.cl"
#include "integrators/estimators/path_trace.cl"

/* Follows a camera walk (its ray not yet traced) through delta-only vertices to the first
 * vertex with a smooth lobe, at depth < max_depth. *L gains the emission seen on the way
 * (times the throughput), *travelled the distance. 0: the path ended first. */
static inline int ic_first_vertex(__constant const RenderParams* p, const SceneView* s,
                                  const Sampler* sampler, PathWalk* w, float3* L, float* travelled,
                                  u32* rays) {
  for (;;) {
    if (!walk_next(s, sampler, w, rays)) {
      *L += w->beta * nee_emission_escaped(p, s, w->dir, w->pdf_w, w->delta);
      return 0;
    }
    *travelled += w->hit.t;
    *L += w->beta * nee_emission_hit(p, s, &w->sh, w->wo, w->hit.t, w->pdf_w, w->delta);
    if (w->depth >= p->max_depth) return 0;
    if (bsdf_has_smooth_lobe(&w->sh)) return 1;
    const BsdfSample bs = walk_sample_bsdf(sampler, w);
    if (!walk_scatter(p, s, sampler, w, &bs)) return 0;
  }
}

/* L_ind at the vertex a walk has just reached (bounce w->depth): NEE there plus pt's
 * continuation, without the vertex's own emission; 0 when no bounce is left. Not weighted
 * by w->beta. */
static inline float3 ic_indirect_at(__constant const RenderParams* p, const SceneView* s,
                                    const Sampler* sampler, const PathWalk* w, u32* rays) {
  if (w->depth >= p->max_depth) return (float3)(0.0f);
  return nee_direct(p, s, sampler, &w->sh, w->wo, offset_ray_origin(w->sh.p, w->sh.ng), w->depth,
                    w->stream, rays) +
         pt_continue(p, s, sampler, &w->sh, w->wo, w->depth, (float2)(w->cone_width, w->cone_spread),
                     w->channel, w->stream, 0u, rays);
}

/* The pixel footprint at the end of a camera path `travelled` long. */
static inline float ic_footprint(__constant const IcParams* ic, float travelled) {
  return ic->footprint_per_distance * travelled + ic->footprint_constant;
}

/* Radiance of one camera sample. */
static inline float3 ic_radiance(__constant const RenderParams* p, const SceneView* s,
                                 const IcCache* cache, const Sampler* sampler, float3 org,
                                 float3 dir,
                                 u32* rays, IcCounts* counts) {
  PathWalk w = walk_from_camera(p, org, dir, 0u, 0u);
  float3 L = (float3)(0.0f);
  float travelled = 0.0f;
  if (!ic_first_vertex(p, s, sampler, &w, &L, &travelled, rays)) return L;
  L += w.beta * nee_direct(p, s, sampler, &w.sh, w.wo, offset_ray_origin(w.sh.p, w.sh.ng),
                           w.depth, w.stream, rays);
  float3 kd;
  const float3 e = ic_diffuse_irradiance(p, cache, &w.sh, w.wo, w.depth, counts, &kd);
  if (!is_black(kd)) L += w.beta * kd * e;
  /* One BSDF sample: its emission is direct light (MIS-weighted as pt's), what lies beyond
   * it the indirect light the cache does not hold. The walk carries only the medium's
   * transmittance from here (beta 1, sample weight 1, no roulette); the two weights apply
   * apart. */
  const SurfaceHit x = w.sh;
  const BsdfSample bs = walk_sample_bsdf(sampler, &w);
  if (!(bs.pdf_w > 0.0f) || is_black(bs.weight)) return L;
  const float3 rest = ic_rest_weight(&x, &bs, kd);
  const float3 beta_x = w.beta;
  BsdfSample along = bs;
  along.weight = (float3)(1.0f);
  w.beta = (float3)(1.0f);
  w.roulette = WALK_RR_NONE;
  walk_scatter(p, s, sampler, &w, &along);
  if (!walk_next(s, sampler, &w, rays))
    return L + beta_x * bs.weight * w.beta * nee_emission_escaped(p, s, w.dir, w.pdf_w, w.delta);
  L += beta_x * bs.weight * w.beta * nee_emission_hit(p, s, &w.sh, w.wo, w.hit.t, w.pdf_w, w.delta);
  if (is_black(fabs(rest))) return L;
  return L + beta_x * rest * w.beta * ic_indirect_at(p, s, sampler, &w, rays);
}

#endif
