/* KHR_materials_sheen's lobe, in a local frame with +z the normal and both directions above:
 * the "Charlie" distribution of Conty and Kulla 2017 ("Production Friendly Microfacet Sheen
 * BRDF"), with their fitted Lambda in the height-correlated G2, as the extension's
 * implementation notes define it (sheen colour 1, roughness r, a = r^2):
 *     D(h) = (2 + 1/a) sin(theta_h)^(1/a) / (2 pi),
 *     f(wo, wi) = D(h) / ((1 + Lambda(wo) + Lambda(wi)) 4 cos_o cos_i).
 * The fitted Lambda is not a Smith Lambda of D, and the lobe's albedo E(cos_o) exceeds 1 at
 * grazing views of smooth sheens (2.3 at cos 0.02, r 0.05; scripts/gen_sheen_table.py). clpt
 * uses the lobe capped symmetrically, reciprocal and with albedo at most 1:
 *     f'(wo, wi) = f(wo, wi) / max(1, E(cos_o), E(cos_i)),
 * identical to f wherever E <= 1 on both sides (at every angle for roughness 0.28 and above).
 * E and the capped lobe's albedo E' come from the tables of kernels/bsdf/sheen_table.h,
 * bilinear in (sqrt(cos), sqrt(r - SHEEN_R_MIN)). Roughness below SHEEN_R_MIN (0.03) reads as
 * SHEEN_R_MIN.
 *
 * Sampling: uniform over the hemisphere, as Conty and Kulla suggest: the lobe is broad, and
 * its f cos_i is largest at grazing wi, where a cosine lobe would hardly sample it. */
#ifndef CLPT_BSDF_SHEEN_CL
#define CLPT_BSDF_SHEEN_CL

#include "bsdf/sheen_table.h"
#include "core/math.cl"
#include "core/warp.cl"

static inline float sheen_clamp_roughness(float r) { return clamp(r, SHEEN_R_MIN, 1.0f); }

/* Bilinear lookup in one of sheen_table.h's tables at cosine mu and (clamped) roughness r. */
static inline float sheen_table_lookup(__constant const float* table, float mu, float r) {
  const float x = sqrt(clamp(mu, 0.0f, 1.0f)) * (float)(SHEEN_TABLE_MU - 1);
  const float y = sqrt(clamp((r - SHEEN_R_MIN) / (1.0f - SHEEN_R_MIN), 0.0f, 1.0f)) * (float)(SHEEN_TABLE_R - 1);
  const int i = min((int)x, SHEEN_TABLE_MU - 2), j = min((int)y, SHEEN_TABLE_R - 2);
  const float fx = x - (float)i, fy = y - (float)j;
  __constant const float* row0 = table + j * SHEEN_TABLE_MU + i;
  __constant const float* row1 = row0 + SHEEN_TABLE_MU;
  return mix(mix(row0[0], row0[1], fx), mix(row1[0], row1[1], fx), fy);
}

/* E(mu): the extension's lobe's albedo; E'(mu): the capped lobe's (what the base under the
 * sheen is scaled by). r clamped. */
static inline float sheen_albedo_raw(float mu, float r) { return sheen_table_lookup(sheen_e, mu, r); }
static inline float sheen_albedo(float mu, float r) { return sheen_table_lookup(sheen_e_capped, mu, r); }

/* Conty and Kulla's fitted exponent l(x) and Lambda(cos). */
static inline float sheen_l(float x, float a) {
  const float t = (1.0f - a) * (1.0f - a);
  const float A = mix(21.5473f, 25.3245f, t), B = mix(3.82987f, 3.32435f, t);
  const float C = mix(0.19823f, 0.16801f, t), D = mix(-1.97760f, -1.27393f, t);
  const float E = mix(-4.32054f, -4.85967f, t);
  return A / (1.0f + B * pow(x, C)) + D * x + E;
}

static inline float sheen_lambda(float c, float a) {
  c = fmin(fabs(c), 1.0f); /* a unit vector's z may round above 1: pow(1 - c) of a negative */
  return c < 0.5f ? exp(sheen_l(c, a)) : exp(2.0f * sheen_l(0.5f, a) - sheen_l(1.0f - c, a));
}

/* The Charlie distribution at sin^2(theta_h) = s2. */
static inline float sheen_d(float s2, float a) {
  const float inv_a = 1.0f / a;
  return (2.0f + inv_a) * pow(fmax(s2, 0.0f), 0.5f * inv_a) * (0.5f * INV_PI_F);
}

/* f'(wo, wi) cos_i of the capped lobe (sheen colour 1), r clamped; wo.z, wi.z > 0, e_o =
 * sheen_albedo_raw(wo.z, r) (the caller's, once per vertex). */
static inline float sheen_eval_cos(float3 wo, float3 wi, float r, float e_o) {
  if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return 0.0f;
  const float a = r * r;
  const float3 h = normalize(wo + wi);
  const float g2 = 1.0f / (1.0f + sheen_lambda(wo.z, a) + sheen_lambda(wi.z, a));
  const float cap = fmax(1.0f, fmax(e_o, sheen_albedo_raw(wi.z, r)));
  const float f = sheen_d(h.x * h.x + h.y * h.y, a) * g2 / (4.0f * wo.z * cap);
  return f > 1e-30f ? f : 0.0f; /* sin^(1/a) underflows to denormals away from the lobe */
}

/* The lobe's sampling: uniform over wo's hemisphere (+z). */
static inline float3 sheen_sample(float2 u) { return warp_uniform_hemisphere(u); }
static inline float sheen_pdf(float3 wi) { return wi.z > 0.0f ? 0.5f * INV_PI_F : 0.0f; }

#endif
