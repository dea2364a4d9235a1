/* Fresnel reflectance.
 *   fresnel_schlick:     Schlick's approximation F0 + (1 - F0)(1 - cos)^5 (glTF 2.0,
 *                        Appendix B), for the opaque dielectric's coat and for metals;
 *   fresnel_dielectric:  the exact unpolarised reflectance of a smooth boundary between two
 *                        dielectrics, with total internal reflection, for transmission. */
#ifndef CLPT_BSDF_FRESNEL_CL
#define CLPT_BSDF_FRESNEL_CL

#include "core/math.cl"

/* (1 - cos)^5, cos clamped to [0, 1]. */
static inline float fresnel_schlick_weight(float cos_theta) {
  const float m = clamp(1.0f - cos_theta, 0.0f, 1.0f);
  const float m2 = m * m;
  return m2 * m2 * m;
}

static inline float3 fresnel_schlick(float3 f0, float cos_theta) {
  return f0 + ((float3)(1.0f) - f0) * fresnel_schlick_weight(cos_theta);
}

/* Reflectance at normal incidence of a boundary with relative index of refraction ior. */
static inline float fresnel_f0_from_ior(float ior) {
  const float r = (ior - 1.0f) / (ior + 1.0f);
  return r * r;
}

/* Exact Fresnel reflectance for light arriving at cosine cos_i >= 0 (with the microfacet or
 * surface normal, on the incident side) at a boundary with eta = eta_t / eta_i (the index of
 * the far side over the near side). 1 under total internal reflection. Symmetric: the
 * transmitted direction, seen from the other side with 1 / eta, has the same reflectance. */
static inline float fresnel_dielectric(float cos_i, float eta) {
  cos_i = clamp(cos_i, 0.0f, 1.0f);
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return 1.0f;
  const float cos_t = sqrt(1.0f - sin2_t);
  const float r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (r_parl * r_parl + r_perp * r_perp);
}

/* Snell's law: the direction refracted from w (pointing away from the boundary, w.n > 0)
 * into the far side, with eta = eta_t / eta_i; false under total internal reflection. */
static inline bool refract_dir(float3 w, float3 n, float eta, float3* wt) {
  const float cos_i = dot(w, n);
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return false;
  const float cos_t = sqrt(1.0f - sin2_t);
  *wt = -w / eta + (cos_i / eta - cos_t) * n;
  return true;
}

#endif
