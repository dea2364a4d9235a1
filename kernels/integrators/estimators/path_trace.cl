/* Unidirectional path tracing with every estimator choice of the toolkit (issue 3):
 *   direct light:  --direct mis (NEE and BSDF sampling combined by MIS), light (NEE only),
 *                  bsdf (emission found by scattering only); --mis power|balance;
 *                  --light-samples N shadow rays per vertex (multi-sample MIS, Veach 1997 §9.2:
 *                  the NEE technique counts N samples);
 *   next direction: --hemisphere bsdf|cosine|uniform;
 *   termination:   Russian roulette from --rr-depth, throughput-based or fixed absorption;
 *   branching:     --branching K continuations from the first hit, each weighted 1/K.
 * Depth counts bounces: emission seen directly is depth 0, light reflected once is depth 1.
 * A path contributes every depth from first_depth to max_depth: pt's pixels 0 on, the chains of
 * PSSMLT 2 on where the direct light (depths 0 and 1) is rendered apart (--mlt-direct). NEE at
 * a vertex and the emission its scattered ray finds are one depth's two techniques, so a cut
 * between depths keeps every MIS pair on one side of it. */
#ifndef CLPT_INTEGRATORS_PATH_TRACE_CL
#define CLPT_INTEGRATORS_PATH_TRACE_CL

#include "integrators/stages/direct_light.cl"
#include "integrators/stages/walk.cl"

/* The camera side's next direction at the walk's vertex, in the walk's dimensions. */
static inline BsdfSample pt_scatter_sample(__constant const RenderParams* p, const SceneView* s,
                                           const Sampler* sampler, const PathWalk* w) {
  return camera_scatter_sample(p, s, &w->sh, w->wo, sample_2d(sampler, walk_dim(w, DIM_BSDF_DIR)),
                               sample_1d(sampler, walk_dim(w, DIM_BSDF_LOBE)));
}

/* Continues a path from vertex `sh` (normals oriented to wo, at bounce `depth`, reached
 * with the ray cone `cone` and dispersion channel `channel`, with the throughput up to it
 * folded out: the result is to be multiplied by the caller's beta).
 * Returns the radiance it gathers from bounce max(depth + 1, first_depth) on. */
static inline float3 pt_continue_walk(__constant const RenderParams* p, const SceneView* s,
                                      const Sampler* sampler, PathWalk* w, u32 first_depth,
                                      u32* rays) {
  float3 L = (float3)(0.0f);
  /* The next direction is picked before next-event estimation at each vertex (the dimensions
   * say which numbers it takes, not the order): after NEE only what walk_scatter reads of
   * the vertex stays live, not its whole BSDF (GPU registers). */
  BsdfSample bs = pt_scatter_sample(p, s, sampler, w);
  for (;;) {
    if (!walk_scatter(p, s, sampler, w, &bs)) break;
    /* The emission found at bounce w->depth is light of that depth, NEE there of the next. */
    if (!walk_next(s, sampler, w, rays)) {
      if (w->depth >= first_depth) L += w->beta * nee_emission_escaped(p, s, w->dir, w->pdf_w, w->delta);
      break;
    }
    if (w->depth >= first_depth)
      L += w->beta * nee_emission_hit(p, s, &w->sh, w->wo, w->hit.t, w->pdf_w, w->delta);
    if (w->depth >= p->max_depth) break;
    bs = pt_scatter_sample(p, s, sampler, w);
    if (w->depth + 1u >= first_depth)
      L += w->beta * nee_direct(p, s, sampler, &w->sh, w->wo, offset_ray_origin(w->sh.p, w->sh.ng),
                                w->depth, w->stream, rays);
  }
  return L;
}

/* pt_continue_walk from a walk standing at vertex sh (walk_at_vertex's arguments). */
static inline float3 pt_continue(__constant const RenderParams* p, const SceneView* s,
                                 const Sampler* sampler, const SurfaceHit* sh, float3 wo, u32 depth,
                                 float2 cone, u32 channel, u32 stream, u32 first_depth, u32* rays) {
  PathWalk w = walk_at_vertex(sh, wo, depth, cone, channel, stream);
  return pt_continue_walk(p, s, sampler, &w, first_depth, rays);
}

/* The radiance of a camera ray's path, depths first_depth to max_depth (see the file
 * comment). */
static inline float3 pt_radiance(const SceneView* s, __constant const RenderParams* p,
                                 const Sampler* sampler, float3 org, float3 dir, u32 first_depth,
                                 u32* rays) {
  PathWalk w = walk_from_camera(p, org, dir, 0u, 0u);
  /* Emission seen by the camera ray, surface or environment, has only one technique: no
   * weight. */
  if (!walk_next(s, sampler, &w, rays)) return first_depth == 0u ? env_radiance(s, dir) : (float3)(0.0f);
  float3 L = first_depth == 0u ? light_radiance(s, &w.sh, w.wo) : (float3)(0.0f);
  if (p->max_depth == 0u) return L;
  const float3 direct =
      first_depth <= 1u
          ? nee_direct(p, s, sampler, &w.sh, w.wo, offset_ray_origin(w.sh.p, w.sh.ng), 0u, 0u, rays)
          : (float3)(0.0f);
  const u32 k = max(p->branching, 1u);
  const u32 channel = w.channel;
  const float3 beta = w.beta;
  float3 indirect = (float3)(0.0f);
  if (k == 1u) { /* the one continuation goes on in w itself: no copy of its vertex */
    walk_restart_at_vertex(&w, 0u, 0u);
    indirect = pt_continue_walk(p, s, sampler, &w, first_depth, rays);
  } else {
    for (u32 b = 0; b < k; ++b)
      indirect += pt_continue(p, s, sampler, &w.sh, w.wo, 0u, (float2)(w.cone_width, w.cone_spread),
                              w.channel, b * DIM_STREAMS_PER_BRANCH, first_depth, rays);
  }
  if (channel == DISPERSION_NONE) return L + direct + indirect / (float)k;
  /* A dispersive glass at the first hit: its channel's weight (walk_disperse) on what it scatters. */
  return L + beta * (direct + indirect / (float)k);
}

#endif
