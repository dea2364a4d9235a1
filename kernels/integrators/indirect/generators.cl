/* The lecture's three generators of one-bounce indirect paths x <- y <- light
 * (--integrator indirect1 --indirect receiver|source|surface; docs/concepts/indirect-generators.md).
 * Each is an estimator of the same integral over the surface points y that a light lights
 * directly,
 *   L1(x, wo) = integral over A of f_x(y -> x -> wo) G(x, y) V(x, y) L_direct(y -> x) dA(y),
 * the light reaching x after exactly one reflection at y, and they differ only in how y is
 * found and what that costs:
 *   receiver gathering  y where x's BSDF sample lands: L_direct(y) by next-event estimation.
 *                       Rays: 1 closest hit (x -> y), 1 shadow ray (y - light).
 *   source shooting     y where a ray emitted by a light lands; y connects to x.
 *                       Rays: 1 closest hit (light -> y), 1 shadow ray (y - x).
 *   surface sampling    y uniform over the scene's surface area, connected to x and to a light.
 *                       Rays: 2 shadow rays (x - y, y - light), no closest hit.
 * Source shooting and surface sampling carry G(x, y) = |cos_x| |cos_y| / d^2 in their
 * weights: unbounded where y comes close to x (the corners of a room), which is their
 * variance; receiver gathering's weight f |cos| / pdf is bounded, and its variance is
 * L_direct's (small lights).
 *
 * What all three count, so that they converge to one image: x is the camera ray's first hit
 * and y the next vertex; both need a smooth (non-delta) BSDF lobe, since a light sample or a
 * connection cannot pick a delta lobe's one direction (receiver gathering therefore drops the
 * samples its BSDF draws from a delta lobe); emission at x and at y is not counted (that is
 * x's emission and direct light); the environment counts as a light at y (NEE, light_emit)
 * and a receiver ray that escapes is direct light at x (0). Segment x - y takes the volume
 * transmittance of the medium it leaves x into (material/volume.cl), as bdpt's connections;
 * shadow rays to lights take none, as pt's next-event estimation.
 *
 * Dimensions (sampler/dimensions.h): x is bounce 0 (receiver: its BSDF direction and lobe),
 * y is bounce 1 (its light sample; source: the emitted ray's light, point and direction in
 * y's light-select, light-point and BSDF-direction dimensions; surface: the triangle in y's
 * BSDF-lobe dimension, the point in its BSDF-direction dimensions). */
#ifndef CLPT_INTEGRATORS_INDIRECT_GENERATORS_CL
#define CLPT_INTEGRATORS_INDIRECT_GENERATORS_CL

#include "bsdf/bsdf.cl"
#include "bvh/intersect.cl"
#include "core/ray.cl"
#include "core/warp.cl"
#include "integrators/stages/shading_correction.cl"
#include "light/light.cl"
#include "material/alpha.cl"
#include "material/material.cl"
#include "material/volume.cl"
#include "sampler/sampler.cl"
#include "shared/indirect_types.h"

/* Direct light at y towards wo (next-event estimation alone, one light sample, weight 1). */
static inline float3 indirect_light_at(const SceneView* s, const Sampler* sampler,
                                       const SurfaceHit* y,
                                       float3 wo, u32* rays) {
  if (s->num_lights == 0u) return (float3)(0.0f);
  const LightSample ls = light_illuminate(s, y->p, sample_1d(sampler, bounce_dim(1u, DIM_LIGHT_SELECT)),
                                          sample_2d(sampler, bounce_dim(1u, DIM_LIGHT_POINT)));
  if (!(ls.pdf_w > 0.0f) || is_black(ls.Le)) return (float3)(0.0f);
  const float3 f = bsdf_eval_cos(y, wo, ls.wi, TRANSPORT_RADIANCE);
  if (is_black(f)) return (float3)(0.0f);
  ++*rays;
  if (light_sample_occluded(s, offset_ray_origin_towards(y->p, y->ng, ls.wi), &ls))
    return (float3)(0.0f);
  return f * ls.Le / ls.pdf_w;
}

/* Whether the segment between surface points a and b (normals ng_a, ng_b) is blocked. */
static inline bool indirect_segment_occluded(const SceneView* s, float3 a, float3 ng_a, float3 b,
                                             float3 ng_b, u32* rays) {
  ++*rays;
  const float3 d = b - a;
  return segment_occluded(s, offset_ray_origin_towards(a, ng_a, d),
                          offset_ray_origin_towards(b, ng_b, -d));
}

/* Receiver gathering at x (oriented to wo). */
static inline float3 indirect_receiver(const SceneView* s, const Sampler* sampler,
                                       const SurfaceHit* x,
                                       float3 wo, u32* rays) {
  const BsdfSample bs = bsdf_sample(x, wo, sample_2d(sampler, bounce_dim(0u, DIM_BSDF_DIR)),
                                    sample_1d(sampler, bounce_dim(0u, DIM_BSDF_LOBE)),
                                    TRANSPORT_RADIANCE);
  if (bs.is_delta || !(bs.pdf_w > 0.0f) || is_black(bs.weight)) return (float3)(0.0f);
  const float3 org = offset_ray_origin_towards(x->p, x->ng, bs.wi);
  Hit hit;
  ++*rays;
  if (!intersect_closest(s, org, bs.wi, INFINITY, &hit)) return (float3)(0.0f);
  SurfaceHit y = surface_shade(s, &hit, org, bs.wi);
  bsdf_orient(&y, -bs.wi);
  if (!bsdf_has_smooth_lobe(&y)) return (float3)(0.0f);
  return bs.weight * volume_transmittance(s, x, bs.wi, hit.t) *
         indirect_light_at(s, sampler, &y, -bs.wi, rays);
}

/* Source shooting: a ray from a light (as the light tracer's, light/light.cl) lands on y,
 * which connects to x. Its weight Le |cos_light| / (pdf_select pdf_a pdf_w) is the flux the
 * ray carries, as in lt_trace. */
static inline float3 indirect_source(const SceneView* s, const Sampler* sampler,
                                     const SurfaceHit* x,
                                     float3 wo, u32* rays) {
  if (s->num_lights == 0u) return (float3)(0.0f);
  const LightEmission e = light_emit(s, sample_1d(sampler, bounce_dim(1u, DIM_LIGHT_SELECT)),
                                     sample_2d(sampler, bounce_dim(1u, DIM_LIGHT_POINT)),
                                     sample_2d(sampler, bounce_dim(1u, DIM_BSDF_DIR)));
  if (!(e.pdf_a > 0.0f && e.pdf_w > 0.0f && e.pdf_select > 0.0f) || is_black(e.Le))
    return (float3)(0.0f);
  const float3 org = light_emission_origin(s, &e);
  Hit hit;
  ++*rays;
  if (!intersect_closest(s, org, e.dir, INFINITY, &hit)) return (float3)(0.0f);
  SurfaceHit y = surface_shade(s, &hit, org, e.dir);
  const float3 wo_y = -e.dir; /* towards the light */
  bsdf_orient(&y, wo_y);
  if (!bsdf_has_smooth_lobe(&y)) return (float3)(0.0f);
  const float3 d = x->p - y.p;
  const float dist2 = dot(d, d);
  if (!(dist2 > 0.0f)) return (float3)(0.0f);
  const float3 to_x = d * rsqrt(dist2);
  const float3 f_y = bsdf_eval_cos(&y, wo_y, to_x, TRANSPORT_IMPORTANCE) *
                     shading_correction(&y, wo_y, to_x);
  const float3 f_x = bsdf_eval_cos(x, wo, -to_x, TRANSPORT_RADIANCE);
  if (is_black(f_y) || is_black(f_x)) return (float3)(0.0f);
  if (indirect_segment_occluded(s, x->p, x->ng, y.p, y.ng, rays)) return (float3)(0.0f);
  const float3 flux = e.Le * (e.cos_light / (e.pdf_select * e.pdf_a * e.pdf_w));
  return flux * f_y * f_x * volume_transmittance(s, x, -to_x, sqrt(dist2)) / dist2;
}

/* Surface sampling: y uniform over the scene's area, from `cdf` (n + 1 values over the
 * leaf-order triangles in proportion to their areas); the density is the interval the
 * triangle was drawn with over its area, which is exactly how it was drawn. */
static inline float3 indirect_surface(const SceneView* s, __constant const IndirectParams* ip,
                                      __global const float* cdf, const Sampler* sampler,
                                      const SurfaceHit* x, float3 wo, u32* rays) {
  if (ip->triangles == 0u) return (float3)(0.0f);
  const u32 tri = cdf_find_interval(cdf, ip->triangles, sample_1d(sampler, bounce_dim(1u, DIM_BSDF_LOBE)));
  const float p_tri = cdf[tri + 1u] - cdf[tri];
  const float area = triangle_area(s, tri);
  if (!(p_tri > 0.0f && area > 0.0f)) return (float3)(0.0f);
  const float2 b = warp_uniform_triangle(sample_2d(sampler, bounce_dim(1u, DIM_BSDF_DIR)));
  float3 p0, p1, p2;
  triangle_vertices(s, tri, &p0, &p1, &p2);
  const float3 d = (1.0f - b.x - b.y) * p0 + b.x * p1 + b.y * p2 - x->p;
  const float dist2 = dot(d, d);
  if (!(dist2 > 0.0f)) return (float3)(0.0f);
  const float dist = sqrt(dist2);
  const float3 dir = d / dist; /* from x towards y */
  if (alpha_hole(s, tri, b.x, b.y, x->p, dir)) return (float3)(0.0f);
  Hit hit;
  hit.t = dist;
  hit.b1 = b.x;
  hit.b2 = b.y;
  hit.triangle = tri;
  SurfaceHit y = surface_shade(s, &hit, x->p, dir);
  bsdf_orient(&y, -dir);
  if (!bsdf_has_smooth_lobe(&y)) return (float3)(0.0f);
  const float3 f_x = bsdf_eval_cos(x, wo, dir, TRANSPORT_RADIANCE);
  if (is_black(f_x)) return (float3)(0.0f);
  const float cos_y = fabs(dot(y.ng, dir));
  if (!(cos_y > 0.0f)) return (float3)(0.0f);
  const float3 L_y = indirect_light_at(s, sampler, &y, -dir, rays);
  if (is_black(L_y)) return (float3)(0.0f);
  if (indirect_segment_occluded(s, x->p, x->ng, y.p, y.ng, rays)) return (float3)(0.0f);
  const float pdf_a = p_tri / area;
  return f_x * L_y * volume_transmittance(s, x, dir, dist) * (cos_y / (dist2 * pdf_a));
}

#endif
