/* Unidirectional path tracing: next-event estimation towards the area lights combined with
 * BSDF sampling by multiple importance sampling (Veach 1997, power heuristic), and Russian
 * roulette on the path throughput.
 * Depth counts bounces: emission seen directly is depth 0, light reflected once is depth 1.
 * A path contributes every depth from 0 to max_depth. */
#ifndef CLPT_INTEGRATORS_PATH_TRACE_CL
#define CLPT_INTEGRATORS_PATH_TRACE_CL

#include "bsdf/bsdf.cl"
#include "core/ray.cl"
#include "light/area_light.cl"
#include "sampler/sampler.cl"
#include "shared/render_types.h"

inline float3 pt_radiance(const SceneView* s, __constant const RenderParams* params,
                          const Sampler* sampler, float3 org, float3 dir, u32* rays) {
  float3 L = (float3)(0.0f);
  float3 beta = (float3)(1.0f);
  float pdf_prev = 0.0f; /* solid-angle pdf of the BSDF sample that produced `dir` */
  bool from_camera = true;

  for (u32 depth = 0;; ++depth) {
    Hit hit;
    ++*rays;
    if (!intersect_closest(s, org, dir, INFINITY, &hit)) break; /* no environment yet */
    SurfaceHit sh = surface_at(s, &hit, org, dir);
    const float3 wo = -dir;

    /* Emission found by the camera ray or by BSDF sampling. */
    const float3 Le = light_radiance(s, sh.material, sh.ng, wo);
    if (!is_black(Le)) {
      float w = 1.0f;
      if (!from_camera) {
        const float pdf_light = light_pdf_w(s, sh.triangle, hit.t, fabs(dot(sh.ng, wo)));
        w = mis_power(pdf_prev, pdf_light);
      }
      L += beta * Le * w;
    }
    if (depth >= params->max_depth) break;

    bsdf_orient(&sh, wo);
    const float3 org_next = offset_ray_origin(sh.p, sh.ng);

    /* Next-event estimation: one shadow ray to a point on a light. */
    if (s->num_emitters > 0u) {
      const LightSample ls =
          light_illuminate(s, sh.p, sample_1d(sampler, bounce_dim(depth, DIM_LIGHT_SELECT)),
                           sample_2d(sampler, bounce_dim(depth, DIM_LIGHT_POINT)));
      if (ls.pdf_w > 0.0f && !is_black(ls.Le)) {
        const float3 f = bsdf_eval_cos(s, &sh, wo, ls.wi);
        if (!is_black(f)) {
          ++*rays;
          /* The shadow ray stops just short of the light sample so it does not hit the light. */
          if (!intersect_any(s, org_next, ls.wi, ls.dist * (1.0f - 1e-4f))) {
            const float w = mis_power(ls.pdf_w, bsdf_pdf_w(s, &sh, wo, ls.wi));
            L += beta * f * ls.Le * (w / ls.pdf_w);
          }
        }
      }
    }

    /* BSDF sampling continues the path. */
    const BsdfSample bs = bsdf_sample(s, &sh, wo, sample_2d(sampler, bounce_dim(depth, DIM_BSDF_DIR)));
    if (!(bs.pdf_w > 0.0f) || is_black(bs.weight)) break;
    beta *= bs.weight;
    pdf_prev = bs.pdf_w;
    from_camera = false;

    if (depth + 1u >= params->rr_depth) {
      const float survive = fmin(1.0f, max_component(beta));
      if (sample_1d(sampler, bounce_dim(depth, DIM_RR)) >= survive) break;
      beta /= survive;
    }
    org = org_next;
    dir = bs.wi;
  }
  return L;
}

#endif
