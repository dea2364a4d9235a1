/* Light tracing (--integrator lt; Veach 1997 §10.2, pbrt-v3 §16.3's t = 1 strategies): a path
 * starts on a light (light_emit), and every vertex on a surface with a non-delta lobe connects
 * to the camera through a shadow ray, splatting its contribution into the pixel it projects
 * to (kernels/film/splat.cl). The light itself connects too (an area light seen directly);
 * delta lights and the environment cannot be seen directly, and nothing is seen through a
 * delta surface next to the camera (a mirror or smooth glass the camera looks at): those
 * paths have no light-tracing strategy.
 *
 * Normalisation (docs/concepts/light-tracing.md): with N = spp * width * height light paths,
 * the estimate of pixel j (the mean radiance over the pixel, as pt estimates it) is
 *   I_j = (1 / N) sum of beta f |cos| We_j cos_cam / d^2,  We_j = 1 / (A_pixel cos^4),
 * and A_pixel = A / (width * height), so each splat is beta f |cos| * weight with
 * camera_connect's weight (whole film area A) and the film divides the sums by spp like pt.
 *
 * Light vertices carry importance: the BSDF is evaluated and sampled in TRANSPORT_IMPORTANCE
 * mode with wo towards the light, and each vertex multiplies the shading-normal correction
 * |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|) (Veach 1997 §5.3). Depth counts bounces as in pt: the
 * light seen directly is depth 0, a vertex k bounces after the light connects at depth k. */
#ifndef CLPT_INTEGRATORS_LIGHT_TRACE_CL
#define CLPT_INTEGRATORS_LIGHT_TRACE_CL

#include "camera/camera_importance.cl"
#include "film/splat_filter.cl"
#include "integrators/stages/walk.cl"
#include "light/light.cl"

/* Connects surface vertex sh (oriented to wo, towards the light) to the camera and splats
 * beta * f * weight. */
static inline void lt_connect_surface(__constant const RenderParams* p, const SceneView* s,
                                      const SurfaceHit* sh, float3 wo, float3 beta, float2 u_lens,
                                      __global float4* splat, u32* rays) {
  const CameraConnection c = camera_connect(&p->camera, p->width, p->height, sh->p, u_lens);
  if (!c.valid) return;
  film_splat_prefetch(p, splat, c.raster);
  const float3 wi = c.wi; /* from the vertex towards the camera */
  const float3 f = bsdf_eval_cos(sh, wo, wi, TRANSPORT_IMPORTANCE) * shading_correction(sh, wo, wi);
  if (is_black(f)) return;
  ++*rays;
  const float3 org = offset_ray_origin_towards(sh->p, sh->ng, wi);
  if (intersect_any(s, org, wi, c.dist * (1.0f - 1e-4f))) return;
  film_splat_at(p, splat, c.raster, beta * f * c.weight);
}

/* One light path. */
static inline void lt_trace(__constant const RenderParams* p, const SceneView* s,
                            const Sampler* sampler,
                            __global float4* splat, u32* rays) {
  if (s->num_lights == 0u) return;
  const LightEmission e =
      light_emit(s, sample_1d(sampler, bounce_dim(0u, DIM_LIGHT_SELECT)),
                 sample_2d(sampler, DIM_LT_EMIT_POS), sample_2d(sampler, DIM_LT_EMIT_DIR));
  if (!(e.pdf_a > 0.0f && e.pdf_w > 0.0f && e.pdf_select > 0.0f) || is_black(e.Le)) return;
  const __global Light* light = &s->lights[e.light];
  float3 org = e.p;
  if (light->type == LIGHT_TRIANGLE) {
    float3 p0, p1, p2;
    triangle_vertices(s, light->triangle, &p0, &p1, &p2);
    const float3 ng = safe_normal(cross(p1 - p0, p2 - p0));
    /* Vertex 0: the light seen directly (s = 1, t = 1). Le is the same in every direction
     * it emits towards: Le |cos| / (pdf_select pdf_a) times the camera's weight. */
    const CameraConnection c = camera_connect(&p->camera, p->width, p->height, e.p,
                                              sample_2d(sampler, bounce_dim(0u, DIM_LT_LENS)));
    if (c.valid && area_light_faces(s, s->triangles[light->triangle].material, ng, c.wi)) {
      film_splat_prefetch(p, splat, c.raster);
      const float3 to_cam = c.wi;
      ++*rays;
      if (!intersect_any(s, offset_ray_origin_towards(e.p, ng, to_cam), to_cam,
                         c.dist * (1.0f - 1e-4f)))
        film_splat_at(p, splat, c.raster,
                   e.Le * (fabs(dot(ng, to_cam)) * c.weight / (e.pdf_select * e.pdf_a)));
    }
    org = offset_ray_origin_towards(e.p, ng, e.dir);
  }
  if (p->max_depth == 0u) return;
  /* The emitted flux of the path; the walk's beta holds the BSDF weights (which Russian
   * roulette looks at like pt's throughput). */
  const float3 emitted = e.Le * (e.cos_light / (e.pdf_select * e.pdf_a * e.pdf_w));
  PathWalk w = walk_from_light(e.p, org, e.dir, (float3)(1.0f), 0u, WALK_RR_PATH);
  while (walk_next(s, sampler, &w, rays)) {
    if (bsdf_has_smooth_lobe(&w.sh))
      lt_connect_surface(p, s, &w.sh, w.wo, emitted * w.beta,
                         sample_2d(sampler, walk_dim(&w, DIM_LT_LENS)), splat, rays);
    if (w.depth >= p->max_depth) break;
    const BsdfSample bs = walk_sample_bsdf(sampler, &w);
    if (!walk_scatter(p, s, sampler, &w, &bs)) break;
  }
}

#endif
