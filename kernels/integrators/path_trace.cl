/* Unidirectional path tracing with every estimator choice of the toolkit (issue 3):
 *   direct light:  --direct mis (NEE and BSDF sampling combined by MIS), light (NEE only),
 *                  bsdf (emission found by scattering only); --mis power|balance;
 *                  --light-samples N shadow rays per vertex (multi-sample MIS, Veach 1997 §9.2:
 *                  the NEE technique counts N samples);
 *   next direction: --hemisphere bsdf|cosine|uniform;
 *   termination:   Russian roulette from --rr-depth, throughput-based or fixed absorption;
 *   branching:     --branching K continuations from the first hit, each weighted 1/K.
 * Depth counts bounces: emission seen directly is depth 0, light reflected once is depth 1.
 * A path contributes every depth from 0 to max_depth. */
#ifndef CLPT_INTEGRATORS_PATH_TRACE_CL
#define CLPT_INTEGRATORS_PATH_TRACE_CL

#include "bsdf/bsdf.cl"
#include "core/ray.cl"
#include "integrators/russian_roulette.cl"
#include "light/light.cl"
#include "material/material.cl"
#include "material/volume.cl"
#include "sampler/sampler.cl"
#include "shared/render_types.h"

/* The MIS weight of a technique with `n_this` samples of density pdf_this against one with
 * n_other samples of density pdf_other. */
inline float pt_mis_weight(__constant const RenderParams* p, float n_this, float pdf_this,
                           float n_other, float pdf_other) {
  const float a = n_this * pdf_this, b = n_other * pdf_other;
  if (!(a > 0.0f)) return 0.0f;
  if (p->mis == MIS_BALANCE) return a / (a + b);
  return (a * a) / (a * a + b * b);
}

/* Density with which the integrator picks the next direction wi at this vertex (non-delta
 * part). --hemisphere cosine|uniform sample only the upper hemisphere of the shading normal
 * on wo's side: they never find transmission or delta (mirror, smooth glass) lobes, so such
 * materials lose that light under them; they are for studying diffuse sampling. */
inline float pt_scatter_pdf(__constant const RenderParams* p, const SceneView* s,
                            const SurfaceHit* sh, float3 wo, float3 wi) {
  if (p->hemisphere == HEMISPHERE_UNIFORM) return warp_uniform_hemisphere_pdf(dot(sh->ns, wi));
  if (p->hemisphere == HEMISPHERE_COSINE) return warp_cosine_hemisphere_pdf(dot(sh->ns, wi));
  return bsdf_pdf_w(sh, wo, wi);
}

/* Picks the next direction; weight = f * |cos| / pdf. u_lobe picks the BSDF's lobe. */
inline BsdfSample pt_scatter_sample(__constant const RenderParams* p, const SceneView* s,
                                    const SurfaceHit* sh, float3 wo, float2 u, float u_lobe) {
  if (p->hemisphere == HEMISPHERE_BSDF) return bsdf_sample(sh, wo, u, u_lobe, TRANSPORT_RADIANCE);
  BsdfSample bs;
  bs.is_delta = 0;
  float3 h;
  if (p->hemisphere == HEMISPHERE_UNIFORM) {
    h = warp_uniform_hemisphere(u);
    bs.pdf_w = warp_uniform_hemisphere_pdf(h.z);
  } else {
    h = warp_cosine_hemisphere(u);
    bs.pdf_w = warp_cosine_hemisphere_pdf(h.z);
  }
  bs.wi = to_world(h, sh->ns);
  const float3 f = bsdf_eval_cos(sh, wo, bs.wi, TRANSPORT_RADIANCE);
  bs.weight = bs.pdf_w > 0.0f ? f / bs.pdf_w : (float3)(0.0f);
  return bs;
}

/* Next-event estimation at a vertex: light_samples shadow rays, each weighted 1/N. */
inline float3 pt_direct(__constant const RenderParams* p, const SceneView* s, const Sampler* sampler,
                        const SurfaceHit* sh, float3 wo, float3 org, u32 depth, u32 stream,
                        u32* rays) {
  float3 L = (float3)(0.0f);
  /* Delta lights (point, spot, directional) have no other technique: --direct bsdf still
   * samples them here, and only them. */
  if (s->num_lights == 0u) return L;
  if (p->direct == DIRECT_BSDF && !(s->info->flags & SCENE_DELTA_LIGHTS)) return L;
  if (!bsdf_has_smooth_lobe(sh)) return L; /* only delta lobes: a light sample has f = 0 */
  const u32 n = max(p->light_samples, 1u);
  for (u32 j = 0; j < n; ++j) {
    const LightSample ls = light_illuminate(
        s, sh->p, sample_1d(sampler, stream_dim(bounce_dim(depth, DIM_LIGHT_SELECT), stream + j)),
        sample_2d(sampler, stream_dim(bounce_dim(depth, DIM_LIGHT_POINT), stream + j)));
    if (!(ls.pdf_w > 0.0f) || is_black(ls.Le)) continue;
    if (p->direct == DIRECT_BSDF && !ls.is_delta) continue;
    const float3 f = bsdf_eval_cos(sh, wo, ls.wi, TRANSPORT_RADIANCE);
    if (is_black(f)) continue;
    ++*rays;
    /* org leaves on wo's side; a transmitted light sample leaves from the other side. */
    if (light_sample_occluded(s, dot(ls.wi, sh->ng) >= 0.0f ? org : offset_ray_origin(sh->p, -sh->ng), &ls)) continue;
    const float w = p->direct != DIRECT_MIS || ls.is_delta
                        ? 1.0f
                        : pt_mis_weight(p, (float)n, ls.pdf_w, 1.0f, pt_scatter_pdf(p, s, sh, wo, ls.wi));
    L += f * ls.Le * (w / (ls.pdf_w * (float)n));
  }
  return L;
}

/* Emission found by a scattered ray that hit emitter triangle sh->triangle at distance t,
 * weighted against NEE; after a delta bounce NEE could not have found it: weight 1. */
inline float3 pt_emission_by_scattering(__constant const RenderParams* p, const SceneView* s,
                                        const SurfaceHit* sh, float3 wo, float t, float pdf_scatter,
                                        int after_delta) {
  const float3 Le = light_radiance(s, sh, wo);
  if (after_delta) return Le;
  if (is_black(Le) || p->direct == DIRECT_LIGHT) return (float3)(0.0f);
  if (p->direct == DIRECT_BSDF) return Le;
  const float pdf_light = light_pdf_w(s, sh->triangle, t, fabs(dot(sh->ng, wo)));
  return Le * pt_mis_weight(p, 1.0f, pdf_scatter, (float)max(p->light_samples, 1u), pdf_light);
}

/* Radiance of the environment seen by a scattered ray that escaped in direction dir, weighted
 * against NEE of the environment light. */
inline float3 pt_emission_escaped(__constant const RenderParams* p, const SceneView* s, float3 dir,
                                  float pdf_scatter, int after_delta) {
  if (!env_present(s)) return (float3)(0.0f);
  const float3 Le = env_radiance(s, dir);
  if (after_delta || p->direct == DIRECT_BSDF) return Le;
  if (p->direct == DIRECT_LIGHT) return (float3)(0.0f);
  return Le * pt_mis_weight(p, 1.0f, pdf_scatter, (float)max(p->light_samples, 1u),
                            light_env_pdf_w(s, dir));
}

/* Continues a path from vertex `sh` (normals oriented to wo, at bounce `depth`, with the
 * throughput up to it folded out: the result is to be multiplied by the caller's beta).
 * Returns the radiance it gathers from bounce depth+1 on. */
inline float3 pt_continue(__constant const RenderParams* p, const SceneView* s,
                          const Sampler* sampler, SurfaceHit sh, float3 wo, u32 depth, u32 stream,
                          u32* rays) {
  float3 L = (float3)(0.0f), beta = (float3)(1.0f);
  for (;;) {
    const BsdfSample bs = pt_scatter_sample(
        p, s, &sh, wo, sample_2d(sampler, stream_dim(bounce_dim(depth, DIM_BSDF_DIR), stream)),
        sample_1d(sampler, stream_dim(bounce_dim(depth, DIM_BSDF_LOBE), stream)));
    if (!(bs.pdf_w > 0.0f) || is_black(bs.weight)) break;
    beta *= bs.weight;
    if (depth + 1u >= p->rr_depth) {
      const float survive = rr_survival(p, beta);
      if (!(sample_1d(sampler, stream_dim(bounce_dim(depth, DIM_RR), stream)) < survive)) break;
      beta /= survive;
    }
    /* Leave on wi's side of the surface (transmission goes through). */
    const float3 org = offset_ray_origin_towards(sh.p, sh.ng, bs.wi);
    Hit hit;
    ++*rays;
    if (!intersect_closest(s, org, bs.wi, INFINITY, &hit)) {
      L += beta * pt_emission_escaped(p, s, bs.wi, bs.pdf_w, bs.is_delta);
      break;
    }
    beta *= volume_transmittance(s, &sh, bs.wi, hit.t); /* inside a KHR_materials_volume */
    sh = surface_shade(s, &hit, org, bs.wi);
    wo = -bs.wi;
    L += beta * pt_emission_by_scattering(p, s, &sh, wo, hit.t, bs.pdf_w, bs.is_delta);
    if (++depth >= p->max_depth) break;
    bsdf_orient(&sh, wo);
    L += beta * pt_direct(p, s, sampler, &sh, wo, offset_ray_origin(sh.p, sh.ng), depth, stream, rays);
  }
  return L;
}

inline float3 pt_radiance(const SceneView* s, __constant const RenderParams* p,
                          const Sampler* sampler, float3 org, float3 dir, u32* rays) {
  Hit hit;
  ++*rays;
  /* Emission seen by the camera ray, surface or environment, has only one technique: no
   * weight. */
  if (!intersect_closest(s, org, dir, INFINITY, &hit)) return env_radiance(s, dir);
  SurfaceHit sh = surface_shade(s, &hit, org, dir);
  const float3 wo = -dir;
  float3 L = light_radiance(s, &sh, wo);
  if (p->max_depth == 0u) return L;
  bsdf_orient(&sh, wo);
  L += pt_direct(p, s, sampler, &sh, wo, offset_ray_origin(sh.p, sh.ng), 0u, 0u, rays);
  const u32 k = max(p->branching, 1u);
  float3 indirect = (float3)(0.0f);
  for (u32 b = 0; b < k; ++b)
    indirect += pt_continue(p, s, sampler, sh, wo, 0u, b * DIM_STREAMS_PER_BRANCH, rays);
  return L + indirect / (float)k;
}

#endif
