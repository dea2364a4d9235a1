/* Classic two-pass photon mapping (Jensen 1996; Jensen 2001, ch. 9), --integrator pm.
 * A camera ray is followed through delta scatterings to its first non-delta vertex x
 * (photon_visible_point), where the light it reflects is split by the path that brought it:
 *   L D(x)          direct light: NEE + one BSDF sample, by MIS (photon_direct);
 *   L S+ D(x)       caustics: the caustic map's estimate at x;
 *   L .* D S* D(x)  the rest: final gathering, N rays sampled from x's BSDF (each followed
 *                   through delta surfaces to a non-delta y) read the global map at y, which
 *                   holds every photon, so its estimate is all the light y reflects;
 *                   with --final-gather 0, the global map's photons at x itself that are not
 *                   direct (bounce >= 2) and not caustic.
 * With --final-gather-cache the final gather's diffuse part comes from an irradiance cache
 * (kernels/integrators/estimators/ic/diffuse_part.cl) whose records gathered from the global map
 * likewise (Jensen 2001, ch. 9); gather rays then sample only the rest of the BSDF (none on
 * a Lambertian surface), or all of it where no record covers x.
 * Each photon path class is counted once. The estimates are k-nearest-neighbour ones
 * (kernels/spatial/kdtree.cl, --knn, --pm-max-radius) with the --pm-filter kernel. A vertex
 * with both delta and non-delta lobes (a roughness-0 coat on a diffuse base) reflects only
 * emitters through its delta lobe: gather rays that pick it are dropped (they would need
 * a second visible point). */
#ifndef CLPT_INTEGRATORS_PHOTON_PM_RADIANCE_CL
#define CLPT_INTEGRATORS_PHOTON_PM_RADIANCE_CL

#include "integrators/estimators/ic/diffuse_part.cl"
#include "integrators/estimators/photon/estimate.cl"

/* Indirect light at vp by final gathering: the mean over N BSDF-sampled rays of the global
 * map's estimate where each ray (after delta bounces) meets a non-delta surface; without the
 * diffuse part kd when an irradiance cache holds it (ic_rest_weight). */
static inline float3 pm_final_gather(__constant const RenderParams* p,
                                     __constant const PmParams* pm, const SceneView* s,
                                     const Sampler* sampler, const PhotonMap* global_map,
                                     const VisiblePoint* vp, float3 kd, u32* rays) {
  const u32 n = pm->final_gather;
  float3 L = (float3)(0.0f);
  for (u32 j = 0; j < n; ++j) {
    const u32 stream = (j + 1u) * DIM_STREAMS_PER_BRANCH;
    const BsdfSample bs = bsdf_sample(
        &vp->sh, vp->wo, sample_2d(sampler, stream_dim(bounce_dim(vp->depth, DIM_BSDF_DIR), stream)),
        sample_1d(sampler, stream_dim(bounce_dim(vp->depth, DIM_BSDF_LOBE), stream)),
        TRANSPORT_RADIANCE);
    if (!(bs.pdf_w > 0.0f) || is_black(bs.weight) || bs.is_delta) continue;
    const float3 weight = ic_rest_weight(&vp->sh, &bs, kd);
    if (is_black(fabs(weight))) continue;
    const float3 org = offset_ray_origin_towards(vp->sh.p, vp->sh.ng, bs.wi);
    VisiblePoint g;
    if (!photon_visible_point(p, s, sampler, &vp->sh, org, bs.wi, vp->depth + 1u, stream,
                              VP_EMISSION_NONE, rays, &g))
      continue;
    L += weight * g.beta * pm_estimate(p, global_map, &g, 1u, 0);
  }
  return L / (float)max(n, 1u);
}

static inline float3 pm_radiance(__constant const RenderParams* p, __constant const PmParams* pm,
                                 const SceneView* s,
                                 const Sampler* sampler, const PhotonMap* global_map,
                                 const PhotonMap* caustic_map, const IcCache* cache, float3 org,
                                 float3 dir, u32* rays, IcCounts* counts) {
  VisiblePoint vp;
  if (!photon_visible_point(p, s, sampler, 0, org, dir, 0u, 0u, VP_EMISSION_ALL, rays, &vp))
    return vp.L;
  float3 R = photon_direct(p, s, sampler, &vp, rays);
  R += pm_estimate(p, caustic_map, &vp, 2u, 0);
  if (pm->final_gather == 0u)
    R += pm_estimate(p, global_map, &vp, 2u, 1);
  else {
    float3 kd;
    const float3 e = ic_diffuse_irradiance(p, cache, &vp.sh, vp.wo, vp.depth, counts, &kd);
    if (!is_black(kd)) R += kd * e;
    R += pm_final_gather(p, pm, s, sampler, global_map, &vp, kd, rays);
  }
  return vp.L + vp.beta * R;
}

#endif
