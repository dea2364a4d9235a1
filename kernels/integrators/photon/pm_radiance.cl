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
 * Each photon path class is counted once. The estimates are k-nearest-neighbour ones
 * (kernels/spatial/kdtree.cl, --knn, --pm-max-radius) with the --pm-filter kernel. A vertex
 * with both delta and non-delta lobes (a roughness-0 coat on a diffuse base) reflects only
 * emitters through its delta lobe: gather rays that pick it are dropped (they would need
 * a second visible point). */
#ifndef CLPT_INTEGRATORS_PHOTON_PM_RADIANCE_CL
#define CLPT_INTEGRATORS_PHOTON_PM_RADIANCE_CL

#include "integrators/photon/visible_point.cl"
#include "integrators/photon/density.cl"
#include "spatial/kdtree.cl"

typedef struct PhotonMap {
  __global const KdNode* nodes; /* heap-ordered kd-tree over photons */
  __global const Photon* photons;
  u32 count;
} PhotonMap;

/* The radiance vp reflects towards vp->wo from the k photons of `map` nearest to it (within
 * the maximum radius), counting those of bounce >= min_bounce that make paths within
 * max_depth, without caustic photons when exclude_caustic. Jensen's radius: the k-th
 * photon's distance, or the maximum radius when fewer photons lie within it. */
inline float3 pm_estimate(__constant const RenderParams* p, const PhotonMap* map,
                          const VisiblePoint* vp, u32 min_bounce, int exclude_caustic) {
  KdNeighbor heap[PM_KNN_MAX];
  const u32 k = clamp(p->knn, 1u, PM_KNN_MAX);
  const float max_r2 = p->pm_max_radius * p->pm_max_radius;
  const u32 count = kd_knn(map->nodes, map->count, vp->sh.p, k, max_r2, heap);
  if (count == 0u) return (float3)(0.0f);
  const float r2 = count == k ? heap[0].d2 : max_r2;
  const u32 max_bounce = p->max_depth - vp->depth;
  const PhotonShading shading = photon_shading(&vp->sh, vp->wo);
  float3 L = (float3)(0.0f);
  for (u32 i = 0; i < count; ++i) {
    __global const Photon* ph = map->photons + heap[i].index;
    const u32 b = photon_bounce(ph->flags);
    if (b < min_bounce || b > max_bounce) continue;
    if (exclude_caustic && (ph->flags & PHOTON_CAUSTIC)) continue;
    if (!photon_on_surface(&vp->sh, ph)) continue;
    L += photon_reflected(&vp->sh, &shading, ph) * photon_kernel(p->pm_filter, heap[i].d2, r2);
  }
  return L;
}

/* Indirect light at vp by final gathering: the mean over N BSDF-sampled rays of the global
 * map's estimate where each ray (after delta bounces) meets a non-delta surface. */
inline float3 pm_final_gather(__constant const RenderParams* p, const SceneView* s,
                              const Sampler* sampler, const PhotonMap* global_map,
                              const VisiblePoint* vp, u32* rays) {
  const u32 n = p->final_gather;
  float3 L = (float3)(0.0f);
  for (u32 j = 0; j < n; ++j) {
    const u32 stream = (j + 1u) * DIM_STREAMS_PER_BRANCH;
    const BsdfSample bs = bsdf_sample(
        &vp->sh, vp->wo, sample_2d(sampler, stream_dim(bounce_dim(vp->depth, DIM_BSDF_DIR), stream)),
        sample_1d(sampler, stream_dim(bounce_dim(vp->depth, DIM_BSDF_LOBE), stream)),
        TRANSPORT_RADIANCE);
    if (!(bs.pdf_w > 0.0f) || is_black(bs.weight) || bs.is_delta) continue;
    const float3 org = offset_ray_origin_towards(vp->sh.p, vp->sh.ng, bs.wi);
    VisiblePoint g;
    if (!photon_visible_point(p, s, sampler, &vp->sh, org, bs.wi, vp->depth + 1u, stream, 0,
                              rays, &g))
      continue;
    L += bs.weight * g.beta * pm_estimate(p, global_map, &g, 1u, 0);
  }
  return L / (float)max(n, 1u);
}

inline float3 pm_radiance(__constant const RenderParams* p, const SceneView* s,
                          const Sampler* sampler, const PhotonMap* global_map,
                          const PhotonMap* caustic_map, float3 org, float3 dir, u32* rays) {
  VisiblePoint vp;
  if (!photon_visible_point(p, s, sampler, 0, org, dir, 0u, 0u, 1, rays, &vp)) return vp.L;
  float3 R = photon_direct(p, s, sampler, &vp, rays);
  R += pm_estimate(p, caustic_map, &vp, 2u, 0);
  if (p->final_gather == 0u)
    R += pm_estimate(p, global_map, &vp, 2u, 1);
  else
    R += pm_final_gather(p, s, sampler, global_map, &vp, rays);
  return vp.L + vp.beta * R;
}

#endif
