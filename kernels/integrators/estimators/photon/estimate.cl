/* A photon map's radiance estimate at a visible point (Jensen 2001, ch. 7 and 9): the k
 * nearest photons (kernels/spatial/kdtree.cl, --knn, --pm-max-radius) weighted by the
 * --pm-filter kernel (density.cl). pm reads its global and caustic maps through it; the
 * irradiance cache's records read a global map through it where they gather from photons
 * (kernels/integrators/ic/records.cl). */
#ifndef CLPT_INTEGRATORS_PHOTON_ESTIMATE_CL
#define CLPT_INTEGRATORS_PHOTON_ESTIMATE_CL

#include "integrators/estimators/photon/density.cl"
#include "integrators/estimators/photon/visible_point.cl"
#include "spatial/kdtree.cl"

typedef struct PhotonMap {
  __global const KdNode* nodes; /* heap-ordered kd-tree over photons */
  __global const Photon* photons;
  u32 count;
  u32 knn;          /* how its estimates read it (PhotonLookup) */
  float max_radius;
  u32 filter;
} PhotonMap;

static inline PhotonMap photon_map(__global const KdNode* nodes, __global const Photon* photons,
                                   u32 count, __constant const PhotonLookup* lookup) {
  PhotonMap m;
  m.nodes = nodes;
  m.photons = photons;
  m.count = count;
  m.knn = lookup->knn;
  m.max_radius = lookup->max_radius;
  m.filter = lookup->filter;
  return m;
}

/* The radiance vp reflects towards vp->wo from the k photons of `map` nearest to it (within
 * the maximum radius), counting those of bounce >= min_bounce that make paths within
 * max_depth, without caustic photons when exclude_caustic. Jensen's radius: the k-th
 * photon's distance, or the maximum radius when fewer photons lie within it. k, the maximum
 * radius and the filter are the map's (PhotonLookup). */
static inline float3 pm_estimate(__constant const RenderParams* p, const PhotonMap* map,
                                 const VisiblePoint* vp, u32 min_bounce, int exclude_caustic) {
  KdNeighbor heap[PM_KNN_MAX];
  const u32 k = clamp(map->knn, 1u, PM_KNN_MAX);
  const float max_r2 = map->max_radius * map->max_radius;
  const u32 count = kd_knn(map->nodes, map->count, vp->sh.p, k, max_r2, heap, map->photons);
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
    L += photon_reflected(&vp->sh, &shading, ph) * photon_kernel(map->filter, heap[i].d2, r2);
  }
  return L;
}

#endif
