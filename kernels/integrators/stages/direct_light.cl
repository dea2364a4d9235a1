/* Direct light at a camera-side vertex, the stage pt, pm and sppm share (issue 3's estimator
 * toolkit): next-event estimation with --light-samples N shadow rays, and the weights of
 * emission that a scattered ray finds instead, combined by MIS (--direct mis|light|bsdf,
 * --mis power|balance; multi-sample MIS, Veach 1997 section 9.2: the NEE technique counts N
 * samples). Also the camera side's choice of the next direction (--hemisphere), whose density
 * the MIS weights need. Dimensions: bounce `depth` of dimension stream `stream`
 * (sampler/dimensions.h). */
#ifndef CLPT_INTEGRATORS_STAGES_DIRECT_LIGHT_CL
#define CLPT_INTEGRATORS_STAGES_DIRECT_LIGHT_CL

#include "bsdf/bsdf.cl"
#include "core/ray.cl"
#include "light/light.cl"
#include "sampler/sampler.cl"
#include "shared/render_types.h"

/* The MIS weight of a technique with `n_this` samples of density pdf_this against one with
 * n_other samples of density pdf_other. */
static inline float nee_mis_weight(__constant const RenderParams* p, float n_this, float pdf_this,
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
static inline float camera_scatter_pdf(__constant const RenderParams* p, const SceneView* s,
                            const SurfaceHit* sh, float3 wo, float3 wi) {
  if (p->hemisphere == HEMISPHERE_UNIFORM) return warp_uniform_hemisphere_pdf(dot(sh->ns, wi));
  if (p->hemisphere == HEMISPHERE_COSINE) return warp_cosine_hemisphere_pdf(dot(sh->ns, wi));
  return bsdf_pdf_w(sh, wo, wi);
}

/* Picks the next direction; weight = f * |cos| / pdf. u_lobe picks the BSDF's lobe. */
static inline BsdfSample camera_scatter_sample(__constant const RenderParams* p, const SceneView* s,
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

/* f |cos| at a light sample's direction wi in xyz, and in w the density with which
 * camera_scatter_sample picks wi: one frame and one set of lobes serve both with the BSDF's
 * own sampling (the default, --hemisphere bsdf). */
static inline float4 nee_eval(__constant const RenderParams* p, const SceneView* s,
                              const SurfaceHit* sh, float3 wo, float3 wi) {
  if (p->hemisphere == HEMISPHERE_BSDF) return bsdf_eval_cos_pdf(sh, wo, wi, TRANSPORT_RADIANCE);
  return (float4)(bsdf_eval_cos(sh, wo, wi, TRANSPORT_RADIANCE), camera_scatter_pdf(p, s, sh, wo, wi));
}

/* Next-event estimation at a vertex: light_samples shadow rays, each weighted 1/N. The
 * shadow ray is set up first and traced last, after the BSDF: across the shading only its
 * seven values stay live, and across the tracing only the contribution (GPU registers:
 * Intel's dg2 compiler spilled 53 values in pt_render with the tracing between the BSDF's
 * value and its density). */
static inline float3 nee_direct(__constant const RenderParams* p, const SceneView* s,
                                const Sampler* sampler,
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
    /* org leaves on wo's side; a transmitted light sample leaves from the other side. */
    const ShadowRay shadow = light_sample_shadow_ray(
        dot(ls.wi, sh->ng) >= 0.0f ? org : offset_ray_origin(sh->p, -sh->ng), &ls);
    const float4 f = nee_eval(p, s, sh, wo, ls.wi);
    if (is_black(f.xyz)) continue;
    const float w = p->direct != DIRECT_MIS || ls.is_delta
                        ? 1.0f
                        : nee_mis_weight(p, (float)n, ls.pdf_w, 1.0f, f.w);
    const float3 fLe = f.xyz * ls.Le;
    const float scale = w / (ls.pdf_w * (float)n);
    ++*rays;
    if (shadow_ray_occluded(s, &shadow)) continue;
    L += fLe * scale;
  }
  return L;
}

/* Emission found by a scattered ray that hit emitter triangle sh->triangle at distance t,
 * weighted against NEE; after a delta bounce NEE could not have found it: weight 1. */
static inline float3 nee_emission_hit(__constant const RenderParams* p, const SceneView* s,
                                        const SurfaceHit* sh, float3 wo, float t, float pdf_scatter,
                                        int after_delta) {
  const float3 Le = light_radiance(s, sh, wo);
  if (after_delta) return Le;
  if (is_black(Le) || p->direct == DIRECT_LIGHT) return (float3)(0.0f);
  if (p->direct == DIRECT_BSDF) return Le;
  const float pdf_light = light_pdf_w(s, sh->triangle, t, fabs(dot(sh->ng, wo)));
  return Le * nee_mis_weight(p, 1.0f, pdf_scatter, (float)max(p->light_samples, 1u), pdf_light);
}

/* Radiance of the environment seen by a scattered ray that escaped in direction dir, weighted
 * against NEE of the environment light. */
static inline float3 nee_emission_escaped(__constant const RenderParams* p, const SceneView* s,
                                          float3 dir,
                                  float pdf_scatter, int after_delta) {
  if (!env_present(s)) return (float3)(0.0f);
  const float3 Le = env_radiance(s, dir);
  if (after_delta || p->direct == DIRECT_BSDF) return Le;
  if (p->direct == DIRECT_LIGHT) return (float3)(0.0f);
  return Le * nee_mis_weight(p, 1.0f, pdf_scatter, (float)max(p->light_samples, 1u),
                            light_env_pdf_w(s, dir));
}

#endif
