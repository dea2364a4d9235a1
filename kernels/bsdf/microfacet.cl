/* The Trowbridge-Reitz (GGX) microfacet distribution, in a local frame with +z the
 * macro-surface normal; alpha = roughness^2 (glTF). Isotropic (one alpha) and anisotropic
 * (alpha.x along the frame's x, alpha.y along y: KHR_materials_anisotropy) forms; the
 * anisotropic ones (ggx_*_2) take the isotropic path when alpha.x == alpha.y, so an isotropic
 * material computes the same bits through either.
 *   ggx_d        normal distribution D(h) (per steradian of h, projected area normalised);
 *   ggx_lambda   Smith's Lambda for a direction (either side: only |tan theta| matters);
 *   ggx_g1, ggx_g2   masking, and height-correlated masking-shadowing
 *                G2 = 1 / (1 + Lambda(wo) + Lambda(wi)) (Heitz 2014, eq. 99), used for
 *                reflection and, as in pbrt-v4, for transmission;
 *   warp_ggx_vndf / _pdf / _invert   the distribution of visible normals D_wo(h) =
 *                G1(wo) max(0, wo.h) D(h) / wo.z, sampled by Heitz 2018 ("Sampling the GGX
 *                Distribution of Visible Normals", JCGT 7(4)), as a warp.cl-style triple.
 * The anisotropic forms stretch the isotropic ones (Heitz 2014, sec. 5.3 and 2018):
 *   D(h) = 1 / (pi ax ay (h.x^2/ax^2 + h.y^2/ay^2 + h.z^2)^2),
 *   Lambda(w) with alpha^2 tan^2 -> (ax^2 w.x^2 + ay^2 w.y^2) / w.z^2,
 *   VNDF: the view direction stretched by (ax, ay, 1), the sampled normal unstretched.
 * tests/bsdf_test.cpp checks the VNDF triples (chi-square and round trip, isotropic and
 * anisotropic) and every BSDF built on them. */
#ifndef CLPT_BSDF_MICROFACET_CL
#define CLPT_BSDF_MICROFACET_CL

#include "core/math.cl"
#include "core/warp.cl"

/* Below this alpha the specular lobes are treated as Dirac deltas (perfect mirror and
 * refraction): roughness < 0.0316. GGX at alpha 1e-3 is ~0.1 degree wide, sharper than any
 * pixel footprint, and its D peaks at ~3e5, still far from float trouble. */
#define GGX_ALPHA_DELTA 1e-3f

static inline float ggx_alpha(float roughness) {
  const float r = clamp(roughness, 0.0f, 1.0f);
  return r * r;
}

/* D(h) = 1 / (pi alpha^2 cos^4 (1 + tan^2 / alpha^2)^2), written with the components of h so
 * no 1 - cos^2 cancels near the peak. 0 for h below the surface. */
static inline float ggx_d(float3 h, float alpha) {
  if (h.z <= 0.0f) return 0.0f;
  const float a2 = alpha * alpha;
  const float t = (h.x * h.x + h.y * h.y) / a2 + h.z * h.z;
  return 1.0f / (PI_F * a2 * t * t);
}

/* Lambda(w) = (sqrt(1 + alpha^2 tan^2) - 1) / 2 = a / (2 (1 + sqrt(1 + a))), a = alpha^2 tan^2,
 * the second form without cancellation near the normal. */
static inline float ggx_lambda(float3 w, float alpha) {
  const float z2 = w.z * w.z;
  if (!(z2 > 0.0f)) return INFINITY;
  const float a = alpha * alpha * (w.x * w.x + w.y * w.y) / z2;
  return a / (2.0f * (1.0f + sqrt(1.0f + a)));
}

static inline float ggx_g1(float3 w, float alpha) { return 1.0f / (1.0f + ggx_lambda(w, alpha)); }

static inline float ggx_g2(float3 wo, float3 wi, float alpha) {
  return 1.0f / (1.0f + ggx_lambda(wo, alpha) + ggx_lambda(wi, alpha));
}

/* The frame of Heitz 2018 around the stretched view direction vh. */
static inline void ggx_vndf_frame(float3 vh, float3* t1, float3* t2) {
  const float len2 = vh.x * vh.x + vh.y * vh.y;
  *t1 = len2 > 0.0f ? (float3)(-vh.y, vh.x, 0.0f) * rsqrt(len2) : (float3)(1.0f, 0.0f, 0.0f);
  *t2 = cross(vh, *t1);
}

/* ---- Anisotropic forms: alpha = (alpha along x, alpha along y). ---- */

static inline float ggx_d_2(float3 h, float2 alpha) {
  if (alpha.x == alpha.y) return ggx_d(h, alpha.x);
  if (h.z <= 0.0f) return 0.0f;
  const float hx = h.x / alpha.x, hy = h.y / alpha.y;
  const float t = hx * hx + hy * hy + h.z * h.z;
  return 1.0f / (PI_F * alpha.x * alpha.y * t * t);
}

static inline float ggx_lambda_2(float3 w, float2 alpha) {
  if (alpha.x == alpha.y) return ggx_lambda(w, alpha.x);
  const float z2 = w.z * w.z;
  if (!(z2 > 0.0f)) return INFINITY;
  const float ax = alpha.x * w.x, ay = alpha.y * w.y;
  const float a = (ax * ax + ay * ay) / z2;
  return a / (2.0f * (1.0f + sqrt(1.0f + a)));
}

static inline float ggx_g1_2(float3 w, float2 alpha) { return 1.0f / (1.0f + ggx_lambda_2(w, alpha)); }

static inline float ggx_g2_2(float3 wo, float3 wi, float2 alpha) {
  if (alpha.x == alpha.y) return ggx_g2(wo, wi, alpha.x);
  return 1.0f / (1.0f + ggx_lambda_2(wo, alpha) + ggx_lambda_2(wi, alpha));
}

/* A microfacet normal h visible from wo (wo.z > 0), with density warp_ggx_vndf_pdf_2: Heitz
 * 2018, the view stretched by (alpha.x, alpha.y, 1), the sampled normal unstretched. (With
 * equal alphas these are the isotropic method's operations, bit for bit.) */
static inline float3 warp_ggx_vndf_2(float2 u, float3 wo, float2 alpha) {
  const float3 vh = normalize((float3)(alpha.x * wo.x, alpha.y * wo.y, wo.z));
  float3 t1, t2;
  ggx_vndf_frame(vh, &t1, &t2);
  const float2 p = sqrt(u.x) * cos_sin_turns(u.y);
  const float p1 = p.x;
  float p2 = p.y;
  const float s = 0.5f * (1.0f + vh.z);
  p2 = (1.0f - s) * sqrt(fmax(0.0f, 1.0f - p1 * p1)) + s * p2;
  const float3 nh = p1 * t1 + p2 * t2 + sqrt(fmax(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
  return normalize((float3)(alpha.x * nh.x, alpha.y * nh.y, fmax(1e-6f, nh.z)));
}

/* Density of h per steradian of h: G1(wo) max(0, wo.h) D(h) / wo.z. */
static inline float warp_ggx_vndf_pdf_2(float3 wo, float3 h, float2 alpha) {
  const float wo_h = dot(wo, h);
  if (!(wo.z > 0.0f) || !(wo_h > 0.0f)) return 0.0f;
  return ggx_g1_2(wo, alpha) * wo_h * ggx_d_2(h, alpha) / wo.z;
}

/* The u that warp_ggx_vndf_2 maps to h (h visible from wo). */
static inline float2 warp_ggx_vndf_invert_2(float3 wo, float3 h, float2 alpha) {
  const float3 vh = normalize((float3)(alpha.x * wo.x, alpha.y * wo.y, wo.z));
  float3 t1, t2;
  ggx_vndf_frame(vh, &t1, &t2);
  const float3 nh = normalize((float3)(h.x / alpha.x, h.y / alpha.y, h.z));
  const float p1 = dot(nh, t1);
  const float s = 0.5f * (1.0f + vh.z);
  const float p2 = (dot(nh, t2) - (1.0f - s) * sqrt(fmax(0.0f, 1.0f - p1 * p1))) / s;
  return (float2)(clamp(p1 * p1 + p2 * p2, 0.0f, 1.0f), warp_azimuth_invert(p2, p1));
}

/* The isotropic warp: the anisotropic one with alpha.x = alpha.y. */
static inline float3 warp_ggx_vndf(float2 u, float3 wo, float alpha) {
  return warp_ggx_vndf_2(u, wo, (float2)(alpha));
}

static inline float warp_ggx_vndf_pdf(float3 wo, float3 h, float alpha) {
  return warp_ggx_vndf_pdf_2(wo, h, (float2)(alpha));
}

static inline float2 warp_ggx_vndf_invert(float3 wo, float3 h, float alpha) {
  return warp_ggx_vndf_invert_2(wo, h, (float2)(alpha));
}

/* KHR_materials_anisotropy's alphas for roughness r and strength s in [0, 1]: along the
 * anisotropy direction (x) mix(r^2, 1, s^2), across it (y) r^2. The narrow axis is kept at
 * GGX_ALPHA_DELTA or above when the wide one is not a delta: the extension's limit (r 0,
 * s > 0) is a lobe of zero width in one direction, a line no density can describe. */
static inline float2 ggx_alpha_anisotropic(float roughness, float strength) {
  const float a = ggx_alpha(roughness);
  const float s = clamp(strength, 0.0f, 1.0f);
  if (!(s > 0.0f)) return (float2)(a);
  const float at = mix(a, 1.0f, s * s);
  if (at < GGX_ALPHA_DELTA) return (float2)(a);
  return (float2)(at, fmax(a, GGX_ALPHA_DELTA));
}

#endif
