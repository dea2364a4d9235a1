/* The surface BSDF. In this slice: Lambertian diffuse with the glTF base colour as albedo.
 * Directions are world space; wo points away from the surface towards the viewer.
 * Scattering happens only on the side of the geometric normal that wo is on (no light
 * leaks through shading normals); cosines are taken with the shading normal. */
#ifndef CLPT_BSDF_BSDF_CL
#define CLPT_BSDF_BSDF_CL

#include "core/surface.cl"
#include "core/warp.cl"

typedef struct BsdfSample {
  float3 wi;
  float3 weight; /* f * |cos| / pdf_w */
  float pdf_w;
} BsdfSample;

/* Orients the hit's normals to the side wo comes from. */
inline void bsdf_orient(SurfaceHit* sh, float3 wo) {
  if (dot(sh->ng, wo) < 0.0f) {
    sh->ng = -sh->ng;
    sh->ns = -sh->ns;
  }
}

inline float3 bsdf_albedo(const SceneView* s, const SurfaceHit* sh) {
  return vload3(0, s->materials[sh->material].base_color);
}

/* f(wo, wi) * |cos(ns, wi)|, with normals oriented by bsdf_orient. */
inline float3 bsdf_eval_cos(const SceneView* s, const SurfaceHit* sh, float3 wo, float3 wi) {
  const float cos_i = dot(sh->ns, wi);
  if (dot(sh->ng, wi) <= 0.0f || cos_i <= 0.0f) return (float3)(0.0f);
  return bsdf_albedo(s, sh) * (INV_PI_F * cos_i);
}

inline float bsdf_pdf_w(const SceneView* s, const SurfaceHit* sh, float3 wo, float3 wi) {
  return warp_cosine_hemisphere_pdf(dot(sh->ns, wi));
}

inline BsdfSample bsdf_sample(const SceneView* s, const SurfaceHit* sh, float3 wo, float2 u) {
  BsdfSample bs;
  const float3 h = warp_cosine_hemisphere(u);
  bs.wi = to_world(h, sh->ns);
  bs.pdf_w = warp_cosine_hemisphere_pdf(h.z);
  /* f * cos / pdf = albedo for a Lambertian surface, when wi is above the geometric surface. */
  bs.weight = (bs.pdf_w > 0.0f && dot(sh->ng, bs.wi) > 0.0f) ? bsdf_albedo(s, sh) : (float3)(0.0f);
  return bs;
}

#endif
