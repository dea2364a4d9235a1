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
 * E and the capped lobe's albedo E' come from the table of kernels/bsdf/sheen_table.h,
 * bilinear in (sqrt(cos), sqrt(r - SHEEN_R_MIN)), both from one lookup. Roughness below SHEEN_R_MIN (0.03) reads as
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

/* (E, E') at cosine mu and (clamped) roughness r: bilinear in sheen_table.h's nodes. */
static inline float2 sheen_albedos(float mu, float r) {
  const float x = sqrt(clamp(mu, 0.0f, 1.0f)) * (float)(SHEEN_TABLE_MU - 1);
  const float y = sqrt(clamp((r - SHEEN_R_MIN) / (1.0f - SHEEN_R_MIN), 0.0f, 1.0f)) * (float)(SHEEN_TABLE_R - 1);
  const int i = min((int)x, SHEEN_TABLE_MU - 2), j = min((int)y, SHEEN_TABLE_R - 2);
  const float fx = x - (float)i, fy = y - (float)j;
  const int k = j * SHEEN_TABLE_MU + i;
  const float2 a = vload2(k, sheen_albedo_table), b = vload2(k + 1, sheen_albedo_table);
  const float2 c = vload2(k + SHEEN_TABLE_MU, sheen_albedo_table);
  const float2 d = vload2(k + SHEEN_TABLE_MU + 1, sheen_albedo_table);
  return mix(mix(a, b, fx), mix(c, d, fx), fy);
}

/* x^y for x >= 0, y > 0, as exp2(y log2 x): the lobe's powers, where pow's general cases cost
 * (measured on PoCL: the lobe's pow calls were a quarter of ToyCar's render time). */
static inline float sheen_pow(float x, float y) { return exp2(y * log2(x)); }

/* Conty and Kulla's fitted exponent l(x) (the extension's), here in base 2 (l log2(e)):
 * Lambda(cos) = exp(l(cos)) below cos 0.5, exp(2 l(0.5) - l(1 - cos)) above. */
static inline float sheen_l2(float x, float a) {
  const float t = (1.0f - a) * (1.0f - a);
  const float A = mix(21.5473f, 25.3245f, t), B = mix(3.82987f, 3.32435f, t);
  const float C = mix(0.19823f, 0.16801f, t), D = mix(-1.97760f, -1.27393f, t);
  const float E = mix(-4.32054f, -4.85967f, t);
  return M_LOG2E_F * (A / (1.0f + B * sheen_pow(x, C)) + D * x + E);
}

/* What the lobe needs of a vertex: its roughness and E(cos_o) (the sampling mixture's and the
 * base's), set once per vertex; the rest is the evaluation's. */
typedef struct SheenLobe {
  float r, a;      /* roughness (clamped) and a = r^2 */
  float l2_half;   /* sheen_l2(0.5) */
  float2 e_o;      /* (E, E') at cos_o */
} SheenLobe;

static inline SheenLobe sheen_lobe(float cos_o, float roughness) {
  SheenLobe s;
  s.r = sheen_clamp_roughness(roughness);
  s.a = s.r * s.r;
  s.l2_half = sheen_l2(0.5f, s.a);
  s.e_o = sheen_albedos(cos_o, s.r);
  return s;
}

static inline float sheen_lambda(const SheenLobe* s, float c) {
  c = fmin(fabs(c), 1.0f); /* a unit vector's z may round above 1: log2 of a negative 1 - c */
  return exp2(c < 0.5f ? sheen_l2(c, s->a) : 2.0f * s->l2_half - sheen_l2(1.0f - c, s->a));
}

/* The Charlie distribution at sin^2(theta_h) = s2. */
static inline float sheen_d(float s2, float a) {
  const float inv_a = 1.0f / a;
  return (2.0f + inv_a) * sheen_pow(fmax(s2, 0.0f), 0.5f * inv_a) * (0.5f * INV_PI_F);
}

/* f'(wo, wi) cos_i of the capped lobe (sheen colour 1); wo.z, wi.z > 0; e_i = (E, E') at
 * wi.z (sheen_albedos, which the caller also needs for the base beneath). */
static inline float sheen_eval_cos(const SheenLobe* s, float3 wo, float3 wi, float2 e_i) {
  if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return 0.0f;
  const float3 h = normalize(wo + wi);
  const float g2 = 1.0f / (1.0f + sheen_lambda(s, wo.z) + sheen_lambda(s, wi.z));
  const float cap = fmax(1.0f, fmax(s->e_o.x, e_i.x));
  const float f = sheen_d(h.x * h.x + h.y * h.y, s->a) * g2 / (4.0f * wo.z * cap);
  return f > 1e-30f ? f : 0.0f; /* sin^(1/a) underflows to denormals away from the lobe */
}

/* The lobe's sampling: uniform over wo's hemisphere (+z). */
static inline float3 sheen_sample(float2 u) { return warp_uniform_hemisphere(u); }
static inline float sheen_pdf(float3 wi) { return wi.z > 0.0f ? 0.5f * INV_PI_F : 0.0f; }

#endif
