/* The camera side of photon mapping (pm and sppm): a ray is followed through delta
 * scatterings (mirrors, smooth glass) and glossy ones (photon_glossy: no diffuse lobe,
 * roughness below PHOTON_GLOSSY_ROUGHNESS) to its first other vertex, the "visible point"
 * where photon density estimates are made (Jensen 2001, ch. 9; Hachisuka and Jensen 2009).
 * A density estimate blurs over the kernel's footprint, which a sharp glossy lobe cannot
 * hide: at rough glass (roughness 0.3) pm was 13 % off (docs/TESTING.md), so glossy vertices
 * are path traced through instead, as SPPM implementations commonly do.
 *
 * Emission seen on the way is kept when asked for (VP_EMISSION_ALL: camera paths): after
 * delta bounces with weight 1, nothing else can find it; at a glossy vertex the light is
 * found by NEE and by the continuing BSDF sample, combined by MIS exactly as the path tracer
 * does. pm's gather rays (VP_EMISSION_NONE) pass glossy vertices like delta ones: the light
 * of L G+ D paths is the caustic map's, whose photons count glossy scatterings as caustic.
 * The irradiance cache's photon-gathering records, which have no caustic map, keep all but
 * the first hit's (VP_EMISSION_BEYOND_FIRST): the record's point finds that light itself,
 * as direct light. Also: direct light at a visible point, by NEE and one BSDF sample
 * combined by MIS as in pt.
 *
 * Depth counts bounces as in pt: a vertex at depth d has d scatterings before it, and a
 * photon stored at its path's b-th hit has made b - 1 bounces, so at depth d photons with
 * b <= max_depth - d make paths of at most max_depth bounces. */
#ifndef CLPT_INTEGRATORS_PHOTON_VISIBLE_POINT_CL
#define CLPT_INTEGRATORS_PHOTON_VISIBLE_POINT_CL

#include "integrators/estimators/photon/glossy.cl"
#include "integrators/stages/direct_light.cl"
#include "integrators/stages/walk.cl"

typedef struct VisiblePoint {
  SurfaceHit sh;  /* normals oriented to wo */
  float3 wo;
  float3 beta;     /* throughput from the ray's origin to here */
  float3 L;        /* emission found on the way, weighted by the throughput */
  u32 depth;       /* bounces before this vertex */
  float t_first;   /* the distance to the ray's first hit (INFINITY: none) */
} VisiblePoint;

/* Which emission photon_visible_point collects on its way. */
#define VP_EMISSION_NONE 0
#define VP_EMISSION_ALL 1
#define VP_EMISSION_BEYOND_FIRST 2 /* all but the first hit's (and the first ray's escape) */

/* Follows org, dir (a pixel's ray with depth 0 and from = 0, or a ray leaving vertex `from`
 * at depth `depth` - 1) to the first vertex neither delta nor glossy. Returns 0 when there is
 * none within max_depth (escaped, absorbed, or only delta and glossy surfaces); vp->L is valid
 * either way. Dimensions from bounce `depth` of `stream`. */
static inline int photon_visible_point(__constant const RenderParams* p, const SceneView* s,
                                       const Sampler* sampler, const SurfaceHit* from, float3 org,
                                       float3 dir, u32 depth, u32 stream, int emission, u32* rays,
                                       VisiblePoint* vp) {
  vp->beta = (float3)(1.0f);
  vp->L = (float3)(0.0f);
  vp->t_first = INFINITY;
  int add_emission = emission == VP_EMISSION_ALL;
  PathWalk w = walk_from_ray(from ? from->p : org, org, dir, (float3)(1.0f),
                             from ? volume_medium(s, from, dir) : MEDIUM_NONE, depth, stream,
                             TRANSPORT_RADIANCE, WALK_RR_PATH);
  /* A pixel's ray carries its cone, as pt's does: the visible point reads its textures over
   * the pixel's footprint (the cone goes on through mirrors and refractions, and ends at a
   * glossy scattering). Gather rays and the cache's records read full resolution. */
  if (!from && depth == 0u) camera_pixel_cone(p, &w.cone_width, &w.cone_spread);
  for (;;) {
    if (!walk_next(s, sampler, &w, rays)) {
      if (add_emission) vp->L += w.beta * nee_emission_escaped(p, s, w.dir, w.pdf_w, w.delta);
      return 0;
    }
    if (!(vp->t_first < INFINITY)) vp->t_first = w.hit.t;
    if (add_emission)
      vp->L += w.beta * nee_emission_hit(p, s, &w.sh, w.wo, w.hit.t, w.pdf_w, w.delta);
    add_emission = emission != VP_EMISSION_NONE;
    if (w.depth >= p->max_depth) return 0;
    const int glossy = photon_glossy(&w.sh);
    if (bsdf_has_smooth_lobe(&w.sh) && !glossy) {
      vp->sh = w.sh;
      vp->wo = w.wo;
      vp->beta = w.beta;
      vp->depth = w.depth;
      return 1;
    }
    if (glossy && add_emission)
      vp->L += w.beta * nee_direct(p, s, sampler, &w.sh, w.wo, offset_ray_origin(w.sh.p, w.sh.ng),
                                   w.depth, w.stream, rays);
    const BsdfSample bs = walk_sample_bsdf(sampler, &w);
    if (!walk_scatter(p, s, sampler, &w, &bs)) return 0;
  }
}

/* Direct light reflected at a visible point (not weighted by its throughput): NEE plus one
 * BSDF-sampled ray that finds emitters and the environment, MIS-weighted as in pt (--direct,
 * --mis, --light-samples). When that sample picks a delta lobe of a mixed material (a
 * roughness-0 coat over a diffuse base), the light it finds has weight 1: NEE cannot. */
static inline float3 photon_direct(__constant const RenderParams* p, const SceneView* s,
                                   const Sampler* sampler, const VisiblePoint* vp, u32* rays) {
  const SurfaceHit* sh = &vp->sh;
  float3 L = nee_direct(p, s, sampler, sh, vp->wo, offset_ray_origin(sh->p, sh->ng), vp->depth,
                       0u, rays);
  const BsdfSample bs = camera_scatter_sample(
      p, s, sh, vp->wo, sample_2d(sampler, bounce_dim(vp->depth, DIM_BSDF_DIR)),
      sample_1d(sampler, bounce_dim(vp->depth, DIM_BSDF_LOBE)));
  if (!(bs.pdf_w > 0.0f) || is_black(bs.weight)) return L;
  const float3 org = offset_ray_origin_towards(sh->p, sh->ng, bs.wi);
  Hit hit;
  ++*rays;
  if (!intersect_closest(s, org, bs.wi, INFINITY, &hit))
    return L + bs.weight * nee_emission_escaped(p, s, bs.wi, bs.pdf_w, bs.is_delta);
  const float3 tr = volume_transmittance(s, sh, bs.wi, hit.t);
  const SurfaceHit lh = surface_shade(s, &hit, org, bs.wi);
  return L + bs.weight * tr *
                 nee_emission_hit(p, s, &lh, -bs.wi, hit.t, bs.pdf_w, bs.is_delta);
}

#endif
