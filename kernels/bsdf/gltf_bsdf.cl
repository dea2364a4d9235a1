/* The glTF 2.0 BSDF (specification Appendix B) with KHR_materials_specular,
 * KHR_materials_transmission and KHR_materials_ior, in a local frame: +z is the shading
 * normal of the FRONT face, the outside of a closed volume whose inside has index p->ior.
 * wo points away from the surface (towards the viewer); it may lie on either side.
 *
 *   f = metallic                              x  metal:   GGX reflection, Schlick F0 = base
 *     + (1 - metallic)(1 - transmission)      x  plastic: Lambert base under a Schlick coat
 *     + (1 - metallic) transmission           x  glass:   Walter et al. 2007 dielectric
 *
 * plastic: coat F(c) = specular (F0 + (1 - F0)(1 - c)^5), F0 = min(F0(ior) specular_color, 1)
 *   (KHR_materials_specular); the coat is GGX reflection with F(wo.h); the diffuse layer is
 *   base / pi x (1 - max F(cos_o)) (1 - max F(cos_i)): light crosses the coat twice. glTF's
 *   fresnel_mix weights the base by 1 - max F(wo.h) instead; with h the half vector of a
 *   diffuse pair that does not conserve energy at grazing wo for smooth coats (the sum
 *   reaches ~1.7 at a mirror coat), while this form is reciprocal, <= 1 (tests/bsdf_test.cpp,
 *   BsdfEnergy), equal to glTF's at normal incidence up to F0^2, and exactly Lambert when
 *   specular = 0.
 * glass: reflection r(h) = min(tint F(wo.h, eta), 1) with the exact Fresnel F and
 *   tint = specular min(F0(ior) specular_color, 1) / F0(ior) (1 at the defaults), refraction
 *   base (1 - max r(h)) through the generalised half vector; total internal reflection
 *   inside; radiance is scaled by 1 / eta^2 on refraction in TRANSPORT_RADIANCE mode only.
 * All specular lobes share alpha = roughness^2 and the height-correlated Smith G2; below
 *   GGX_ALPHA_DELTA they are Dirac deltas: eval and pdf leave them out, and sampling flags
 *   them (is_delta) with the selection probability folded into the weight.
 *
 * anisotropy (KHR_materials_anisotropy): with strength s > 0 those lobes (the metal's, the
 *   plastic's coat, the glass's reflection and refraction; not the clearcoat or the sheen)
 *   are anisotropic GGX with alpha mix(alpha, 1, s^2) along the frame's x, which bsdf_frame
 *   turns to the anisotropy direction, and alpha across it (ggx_alpha_anisotropic); sampled
 *   by their stretched visible normals.
 * From the back (wo.z < 0) the opaque lobes are mirrored (a double-sided or closed opaque
 *   surface looks the same from both sides); the glass sees eta = 1 / ior.
 *
 * clearcoat (KHR_materials_clearcoat): a dielectric coat of weight c (ior 1.5, F0 = 0.04,
 *   the extension's fixed values) with its own GGX roughness over all of the above:
 *     f = c Fc(wo.h) D_c G2_c / (4 cos_o cos_i)  +  (1 - c Fc(cos_o)) (1 - c Fc(|cos_i|)) f_base,
 *   Fc Schlick's. The specification writes mix(base, coat, c Fc(NdotV)); attenuating the base
 *   once per crossing of the coat, as the plastic's own coat above, keeps f reciprocal and the
 *   albedo <= 1 (BsdfEnergy) and equals it at normal incidence up to (c F0)^2.
 *   The coat has its own normal nc (local, nc.z > 0: clearcoatNormalTexture, else the
 *   interpolated normal, which the base's normal map does not move): Fc, D_c, G2_c and the
 *   crossings' Fc take cosines with nc. nc is a shading normal of the coat's own: its lobe
 *   f_c = c Fc(wo.h) D_c(h) G2_c / (4 (wo.nc)(wi.nc)) is weighted by wi.nc, not by the base's
 *   |wi.z|, so the coat looks the same whatever normal map the base has (the specification's
 *   intent; a shared map is the coat's map alone). Light paths get Veach's adjoint of such a
 *   shading normal (1997 §5.3) once the caller's correction for the base's normal is
 *   applied, as refraction gets its eta by mode:
 *     radiance:   f_c (wi.nc)                          = c Fc D_c G2_c / (4 wo.nc),
 *     importance: f_c (wo.nc) |wi.z| / |wo.z|          = c Fc D_c G2_c |wi.z| / (4 wi.nc |wo.z|),
 *   so f_importance(a, b) / |b.z| = f_radiance(b, a) / |a.z| (BsdfReciprocity). In radiance
 *   mode the coat's albedo is its own in its frame (<= c). With nc = +z (bit for bit: no map
 *   anywhere) both are the form above.
 *
 * diffuse transmission (KHR_materials_diffuse_transmission): a share dt of the plastic's
 *   diffuse layer leaves through the far side instead, Lambertian with its own colour,
 *     f_dt = w_plastic dt color / pi (1 - max F(cos_o)) (1 - max F(|cos_i|)),  wi below,
 *   and the reflected diffuse layer keeps (1 - dt) of its weight. Symmetric in wo and wi and
 *   with no eta (the extension's thin surface), and its own cosine lobe in the mixture.
 *
 * iridescence (KHR_materials_iridescence): a thin film of weight k over the base. Each
 *   reflectance above (the metal's, the plastic's coat, the glass's r) becomes
 *   mix(F, R_film(cos, f0), k), R_film the film's RGB reflectance over a base of that lobe's
 *   f0 (kernels/bsdf/thin_film.cl); what the base transmits follows from it as before (the
 *   diffuse layer's 1 - max F, the glass's 1 - max r). The lobe probabilities keep Schlick's
 *   estimates: the film changes what a direction carries, not how it is sampled.
 *
 * sheen (KHR_materials_sheen): a layer of colour sc and roughness r between the clearcoat and
 *   all of the above, the capped Charlie lobe of kernels/bsdf/sheen.cl over the base scaled by
 *   the extension's albedo scaling, with the capped lobe's albedo E':
 *     f = sc f'_sheen(wo, wi) + min(1 - m E'(cos_o), 1 - m E'(|cos_i|)) f_base,  m = max3(sc),
 *   reflection only (the base's transmission is scaled alike). Symmetric, and sc E' + (1 -
 *   m E') <= 1 at every wo. The coat, when present, attenuates the sheen as it does the base.
 *
 * Sampling: one sample from a mixture of lobes, chosen by u_lobe with probabilities
 * proportional to estimates of each lobe's albedo at wo (Fresnel at cos_o, metallic,
 * transmission, the clearcoat's c Fc(cos_o), the sheen's sc E'(cos_o), the base's scaled by
 * 1 - c Fc(cos_o) and 1 - m E'(cos_o)): clearcoat (its GGX visible normals), sheen (uniform
 * hemisphere), diffuse (cosine), reflection (GGX visible normals,
 * Heitz 2018) and glass
 * (visible normals, then reflection with probability max r(h), else refraction, the
 * rescaled u_lobe deciding). pdf() is that mixture's density, sum_lobe p_lobe pdf_lobe, and
 * a non-delta sample's weight is eval / pdf at the sampled direction, so MIS sees exactly the
 * density the sampler has. A sample may be absorbed (weight 0, pdf_w 0): a reflection below
 * the horizon, a refraction under total internal reflection. */
#ifndef CLPT_BSDF_GLTF_BSDF_CL
#define CLPT_BSDF_GLTF_BSDF_CL

#include "bsdf/bsdf_params.h"
#include "bsdf/fresnel.cl"
#include "bsdf/microfacet.cl"
#include "bsdf/sheen.cl"
#include "bsdf/thin_film.cl"
#include "core/warp.cl"

typedef struct BsdfSample {
  float3 wi;
  float3 weight; /* f |cos| / pdf_w; delta lobes: their reflectance / selection probability */
  float pdf_w;   /* the mixture's solid-angle density at wi; delta: the discrete probability */
  int is_delta;  /* wi came from a Dirac lobe: no MIS, no NEE through it */
} BsdfSample;

/* A lobe whose albedo estimate is tiny still gets this share of its weight, so that a lobe
 * with some f (black metal, F0 = 0 coat) is never given probability 0. */
#define GLTF_LOBE_FLOOR 0.02f

typedef struct GltfLobes {
  float2 alpha;      /* the base's GGX alphas along the frame's x and y (equal: isotropic) */
  int delta;         /* alpha.x < GGX_ALPHA_DELTA (x is the wider axis) */
  float eta;         /* glass: index of wi's side over wo's when refracting */
  float w_plastic;   /* (1 - metallic)(1 - transmission) */
  float w_glass;     /* (1 - metallic) transmission */
  float w_metal;     /* metallic */
  float3 f0;         /* coat: min(F0(ior) specular_color, 1) */
  float3 glass_tint; /* scales the glass's exact Fresnel */
  float p_diffuse, p_reflect, p_glass, p_coat, p_dtrans, p_sheen;
  float dt;          /* diffuse transmission: the plastic's diffuse share that crosses */
  float coat;        /* clearcoat weight c in [0, 1] */
  float alpha_c;     /* clearcoat GGX alpha */
  int coat_delta;    /* alpha_c < GGX_ALPHA_DELTA */
  int coat_tilted;   /* the coat's normal is not +z (bsdf_coat_normal gives exactly +z otherwise) */
  float3 nc, tc, bc; /* the coat's frame: its normal, and tangents where tilted */
  float cos_oc;      /* wo's cosine with the coat's normal, clamped to [0, 1] */
  float sheen_m;     /* sheen: the colour's largest component, 0 without a sheen */
  SheenLobe sheen;   /* the sheen lobe at wo (set where sheen_m > 0) */
  float sheen_keep_o; /* 1 - m E'(cos_o): the base's share under the sheen, on wo's side */
  float irid;        /* iridescence weight k in [0, 1] */
  float irid_ior, irid_d; /* the film's index and thickness (nm) */
  int outside;       /* wo on the front side */
} GltfLobes;

static inline float avg3(float3 c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }

/* Iridescence: the reflectance F of a lobe whose base has normal-incidence reflectance f0,
 * blended with the thin film's over that base by the weight k, mix(F, R_film, k), at the
 * outside cosine c (the extension's rule; F is kept exactly where k = 0). */
static inline float3 gltf_iridescent(const GltfLobes* L, float3 F, float3 f0, float c) {
  if (!(L->irid > 0.0f)) return F;
  return mix(F, thin_film_reflectance(c, L->irid_ior, L->irid_d, f0), L->irid);
}

/* The plastic's coat and the metal's reflectance at cos(wo, h) = c. */
static inline float3 gltf_coat(const BsdfParams* p, const GltfLobes* L, float c) {
  return p->specular * gltf_iridescent(L, fresnel_schlick(L->f0, c), L->f0, c);
}
static inline float3 gltf_metal(const BsdfParams* p, const GltfLobes* L, float c) {
  return gltf_iridescent(L, fresnel_schlick(p->base_color, c), p->base_color, c);
}

/* The clearcoat's reflectance c Fc(x), and the share 1 - c Fc(x) of light that crosses it;
 * x is a cosine with the coat's normal (gltf_coat_cos). */
static inline float gltf_clearcoat_f(const GltfLobes* L, float x) {
  return L->coat * (0.04f + 0.96f * fresnel_schlick_weight(x));
}
static inline float gltf_clearcoat_pass(const GltfLobes* L,
                                        float x) { return 1.0f - gltf_clearcoat_f(L, x); }

/* The cosine of w (either side, mirrored up) with the coat's normal, clamped to [0, 1]: a
 * direction the tilted coat sees edge-on or from behind crosses it at grazing incidence. */
static inline float gltf_coat_cos(const GltfLobes* L, float3 w) {
  if (!L->coat_tilted) return fabs(w.z);
  return clamp(dot((float3)(w.x, w.y, fabs(w.z)), L->nc), 0.0f, 1.0f);
}

/* w in the coat's frame (its normal as +z). */
static inline float3 gltf_to_coat(const GltfLobes* L, float3 w) {
  if (!L->coat_tilted) return w;
  return (float3)(dot(w, L->tc), dot(w, L->bc), dot(w, L->nc));
}
static inline float3 gltf_from_coat(const GltfLobes* L, float3 w) {
  if (!L->coat_tilted) return w;
  return w.x * L->tc + w.y * L->bc + w.z * L->nc;
}

/* The glass's reflectance at cos(wo, h) = c on wo's side. A film sits on the outside: seen
 * from inside, it is evaluated at the cosine of the same wave outside, so that reflectance
 * (and with it transmission, 1 - r) is the same from both sides of a pair, as the exact
 * Fresnel term's is (a lossless stack reflects equally from both sides). */
static inline float3 gltf_glass_r(const GltfLobes* L, float c) {
  const float F = fresnel_dielectric(c, L->eta);
  float3 r = (float3)(F);
  if (L->irid > 0.0f && F < 1.0f) {
    float c_out = c;
    if (!L->outside) {
      const float ci = clamp(c, 0.0f, 1.0f);
      c_out = sqrt(fmax(0.0f, 1.0f - (1.0f - ci * ci) / (L->eta * L->eta)));
    }
    const float ior = L->outside ? L->eta : 1.0f / L->eta;
    r = gltf_iridescent(L, r, (float3)(fresnel_f0_from_ior(ior)), c_out);
  }
  return fmin(L->glass_tint * r, (float3)(1.0f));
}

/* Weights and lobe probabilities at wo (mirrored up: wo.z = |wo.z|), on the given side, with
 * the coat's normal nc (local, nc.z > 0; +z when the coat shares the shading normal). */
static inline GltfLobes gltf_lobes(const BsdfParams* p, float3 nc, float3 wo, bool outside) {
  GltfLobes L;
  const float cos_o = wo.z;
  L.coat_tilted = nc.x != 0.0f || nc.y != 0.0f;
  L.nc = L.coat_tilted ? nc : (float3)(0.0f, 0.0f, 1.0f);
  L.tc = (float3)(1.0f, 0.0f, 0.0f);
  L.bc = (float3)(0.0f, 1.0f, 0.0f);
  if (L.coat_tilted) make_basis(L.nc, &L.tc, &L.bc);
  L.cos_oc = gltf_coat_cos(&L, wo);
  L.alpha = ggx_alpha_anisotropic(p->roughness, p->anisotropy);
  L.delta = L.alpha.x < GGX_ALPHA_DELTA;
  const float ior = fmax(p->ior, 1.0f);
  L.eta = outside ? ior : 1.0f / ior;
  L.outside = outside;
  L.irid = clamp(p->iridescence, 0.0f, 1.0f);
  L.irid_ior = fmax(p->iridescence_ior, 1.0f);
  L.irid_d = fmax(p->iridescence_thickness, 0.0f);
  const float m = clamp(p->metallic, 0.0f, 1.0f), t = clamp(p->transmission, 0.0f, 1.0f);
  L.w_metal = m;
  L.w_plastic = (1.0f - m) * (1.0f - t);
  L.w_glass = (1.0f - m) * t;
  const float f0_ior = fresnel_f0_from_ior(ior);
  const float3 spec_color = fmax(p->specular_color, (float3)(0.0f));
  L.f0 = fmin(f0_ior * spec_color, (float3)(1.0f));
  L.glass_tint = p->specular * (f0_ior > 0.0f ? L.f0 / f0_ior : spec_color);

  L.dt = clamp(p->diffuse_transmission, 0.0f, 1.0f);
  const float coat = max_component(gltf_coat(p, &L, cos_o));
  const float e_d = L.w_plastic * (1.0f - L.dt) * avg3(p->base_color) * (1.0f - coat);
  const float e_t = L.dt > 0.0f ? L.w_plastic * L.dt * avg3(p->diffuse_transmission_color) * (1.0f - coat) : 0.0f;
  const float e_r =
      L.w_plastic * p->specular * fmax(max_component(fresnel_schlick(L.f0, cos_o)), GLTF_LOBE_FLOOR) +
      L.w_metal * fmax(avg3(fresnel_schlick(p->base_color, cos_o)), GLTF_LOBE_FLOOR);
  const float r_g = max_component(gltf_glass_r(&L, cos_o));
  const float e_g = L.w_glass * fmax(r_g + (1.0f - r_g) * avg3(p->base_color), GLTF_LOBE_FLOOR);
  L.coat = clamp(p->clearcoat, 0.0f, 1.0f);
  L.alpha_c = ggx_alpha(p->clearcoat_roughness);
  L.coat_delta = L.alpha_c < GGX_ALPHA_DELTA;
  /* The sheen's albedo, and the share of the base beneath it. */
  const float3 sc = clamp(p->sheen_color, 0.0f, 1.0f);
  L.sheen_m = max_component(sc);
  L.sheen_keep_o = 1.0f;
  float e_s = 0.0f;
  if (L.sheen_m > 0.0f) {
    L.sheen = sheen_lobe(cos_o, p->sheen_roughness);
    L.sheen_keep_o = fmax(1.0f - L.sheen_m * L.sheen.e_o.y, 0.0f);
    e_s = fmax(avg3(sc) * L.sheen.e_o.y, L.sheen_m * GLTF_LOBE_FLOOR);
  }
  /* The base lobes are seen through the sheen and the coat: their estimates shrink by what
   * these reflect. */
  const float pass = gltf_clearcoat_pass(&L, L.cos_oc);
  const float base = pass * L.sheen_keep_o;
  /* A coat wo sees from behind (tilted away) reflects nothing: never chosen then. */
  const float e_c = L.coat > 0.0f && L.cos_oc > 0.0f
                        ? fmax(gltf_clearcoat_f(&L, L.cos_oc), L.coat * GLTF_LOBE_FLOOR)
                        : 0.0f;
  float sum = base * (fmax(e_d, 0.0f) + fmax(e_t, 0.0f) + fmax(e_r, 0.0f) + fmax(e_g, 0.0f)) + e_c;
  if (e_s > 0.0f) sum += pass * e_s; /* (a separate sum: without a sheen, the bits of before) */
  if (!(sum > 0.0f)) {
    L.p_diffuse = L.p_reflect = L.p_glass = L.p_coat = L.p_dtrans = L.p_sheen = 0.0f;
  } else {
    L.p_diffuse = base * fmax(e_d, 0.0f) / sum;
    L.p_dtrans = base * fmax(e_t, 0.0f) / sum;
    L.p_reflect = base * fmax(e_r, 0.0f) / sum;
    L.p_glass = base * fmax(e_g, 0.0f) / sum;
    L.p_sheen = pass * e_s / sum;
    L.p_coat = e_c / sum;
  }
  return L;
}

/* The microfacet normal of a refraction pair (wo above, wi below, after mirroring), on wo's
 * side, or 0 when the pair cannot refract through any microfacet (Walter et al. 2007, eq. 16). */
static inline float3 gltf_transmission_half(float3 wo, float3 wi, float eta) {
  float3 h = wo + eta * wi;
  const float len2 = dot(h, h);
  if (!(len2 > 1e-12f)) return (float3)(0.0f);
  h *= rsqrt(len2);
  if (h.z < 0.0f) h = -h;
  if (!(dot(wo, h) > 0.0f) || !(dot(wi, h) < 0.0f)) return (float3)(0.0f);
  return h;
}

/* Combined reflectance of the three specular reflection lobes at cos(wo, h) = c. */
static inline float3 gltf_reflectance(const BsdfParams* p, const GltfLobes* L, float c) {
  float3 F = L->w_metal * gltf_metal(p, L, c);
  if (L->w_plastic > 0.0f) F += L->w_plastic * gltf_coat(p, L, c);
  if (L->w_glass > 0.0f) F += L->w_glass * gltf_glass_r(L, c);
  return F;
}

/* f_base |wi.z| (the lobes under the clearcoat) with wo.z > 0 (mirrored). */
static inline float3 gltf_eval_base_up(const BsdfParams* p, const GltfLobes* L, float3 wo,
                                       float3 wi,
                                       int mode) {
  if (wi.z > 0.0f) {
    float3 f = (float3)(0.0f);
    if (L->w_plastic > 0.0f) {
      const float3 d = (1.0f - max_component(gltf_coat(p, L, wo.z))) *
                       (1.0f - max_component(gltf_coat(p, L, wi.z))) * INV_PI_F *
                       p->base_color;
      f += L->w_plastic * (1.0f - L->dt) * d;
    }
    if (!L->delta) {
      const float3 h = normalize(wo + wi);
      f += gltf_reflectance(p, L, dot(wo, h)) *
           (ggx_d_2(h, L->alpha) * ggx_g2_2(wo, wi, L->alpha) / (4.0f * wo.z * wi.z));
    }
    return f * wi.z;
  }
  if (!(wi.z < 0.0f)) return (float3)(0.0f);
  float3 f = (float3)(0.0f);
  if (L->dt > 0.0f && L->w_plastic > 0.0f) {
    /* Diffuse transmission: the diffuse layer's Lambertian share dt leaves through the far
     * side, through the coat there (symmetric in wo and wi: no eta, a thin surface). */
    const float3 d = (1.0f - max_component(gltf_coat(p, L, wo.z))) *
                     (1.0f - max_component(gltf_coat(p, L, -wi.z))) * INV_PI_F *
                     p->diffuse_transmission_color;
    f += L->w_plastic * L->dt * d * (-wi.z);
  }
  if (!L->delta && L->w_glass > 0.0f) {
    const float3 h = gltf_transmission_half(wo, wi, L->eta);
    if (h.z == 0.0f) return f;
    const float wo_h = dot(wo, h), wi_h = dot(wi, h);
    const float3 T = p->base_color * (1.0f - max_component(gltf_glass_r(L, wo_h)));
    const float denom = wo_h + L->eta * wi_h;
    /* Radiance: Walter's eta_o^2 / (eta_i wi.h + eta_o wo.h)^2 = 1 / (eta wi.h + wo.h)^2;
     * importance (the adjoint) has eta_i^2 in place of eta_o^2. */
    float k = ggx_d_2(h, L->alpha) * ggx_g2_2(wo, wi, L->alpha) * fabs(wi_h) * wo_h /
              (wo.z * denom * denom);
    if (mode == TRANSPORT_IMPORTANCE) k *= L->eta * L->eta;
    f += L->w_glass * T * k;
  }
  return f;
}

/* The clearcoat's GGX reflection f_coat |wi.z| (non-delta coats), wo.z > 0; with a normal of
 * its own, the mode's form above. */
static inline float3 gltf_coat_eval_up(const GltfLobes* L, float3 wo, float3 wi, int mode) {
  if (!(L->coat > 0.0f) || L->coat_delta || !(wi.z > 0.0f)) return (float3)(0.0f);
  const float3 h = normalize(wo + wi);
  if (!L->coat_tilted)
    return (float3)(gltf_clearcoat_f(L, dot(wo, h)) * ggx_d(h, L->alpha_c) *
                    ggx_g2(wo, wi, L->alpha_c) / (4.0f * wo.z));
  const float3 wo_c = gltf_to_coat(L, wo), wi_c = gltf_to_coat(L, wi);
  if (!(wo_c.z > 0.0f) || !(wi_c.z > 0.0f)) return (float3)(0.0f);
  const float x = gltf_clearcoat_f(L, dot(wo, h)) * ggx_d(gltf_to_coat(L, h), L->alpha_c) *
                  ggx_g2(wo_c, wi_c, L->alpha_c);
  return (float3)(mode == TRANSPORT_IMPORTANCE ? x * wi.z / (4.0f * wi_c.z * wo.z) : x / (4.0f * wo_c.z));
}

/* The base's share under the sheen for the pair: min(1 - m E'(cos_o), 1 - m E'(|cos_i|)),
 * from e_i = sheen_albedos(|cos_i|). */
static inline float gltf_sheen_keep(const GltfLobes* L, float2 e_i) {
  return fmin(L->sheen_keep_o, fmax(1.0f - L->sheen_m * e_i.y, 0.0f));
}

/* f |wi.z| with wo.z > 0 (mirrored): the coat, and the sheen and the base seen through it. */
static inline float3 gltf_eval_up(const BsdfParams* p, const GltfLobes* L, float3 wo, float3 wi,
                                  int mode) {
  float3 f = gltf_eval_base_up(p, L, wo, wi, mode);
  if (L->sheen_m > 0.0f) {
    const float2 e_i = sheen_albedos(fabs(wi.z), L->sheen.r);
    f *= gltf_sheen_keep(L, e_i);
    f += clamp(p->sheen_color, 0.0f, 1.0f) * sheen_eval_cos(&L->sheen, wo, wi, e_i);
  }
  if (!(L->coat > 0.0f)) return f;
  f *= gltf_clearcoat_pass(L, L->cos_oc) * gltf_clearcoat_pass(L, gltf_coat_cos(L, wi));
  return f + gltf_coat_eval_up(L, wo, wi, mode);
}

/* The base lobes' part of the mixture's density, wo.z > 0. */
static inline float gltf_pdf_base_up(const GltfLobes* L, float3 wo, float3 wi) {
  if (wi.z > 0.0f) {
    float pdf = L->p_diffuse * warp_cosine_hemisphere_pdf(wi.z);
    if (!L->delta && L->p_reflect + L->p_glass > 0.0f) {
      const float3 h = normalize(wo + wi);
      const float wo_h = dot(wo, h);
      const float p_r = L->p_glass > 0.0f ? max_component(gltf_glass_r(L, wo_h)) : 0.0f;
      pdf += (L->p_reflect + L->p_glass * p_r) * warp_ggx_vndf_pdf_2(wo, h, L->alpha) /
             (4.0f * wo_h);
    }
    return pdf;
  }
  if (!(wi.z < 0.0f)) return 0.0f;
  float pdf = L->p_dtrans > 0.0f ? L->p_dtrans * warp_cosine_hemisphere_pdf(-wi.z) : 0.0f;
  if (!L->delta && L->p_glass > 0.0f) {
    const float3 h = gltf_transmission_half(wo, wi, L->eta);
    if (h.z == 0.0f) return pdf;
    const float wo_h = dot(wo, h), wi_h = dot(wi, h);
    const float p_t = 1.0f - max_component(gltf_glass_r(L, wo_h));
    const float denom = wo_h + L->eta * wi_h;
    pdf += L->p_glass * p_t * warp_ggx_vndf_pdf_2(wo, h, L->alpha) * L->eta * L->eta *
           fabs(wi_h) / (denom * denom);
  }
  return pdf;
}

/* The mixture's density with wo.z > 0 (mirrored). */
static inline float gltf_pdf_up(const GltfLobes* L, float3 wo, float3 wi) {
  float coat = 0.0f;
  if (L->p_coat > 0.0f && !L->coat_delta && wi.z > 0.0f) {
    const float3 h = normalize(wo + wi);
    coat = L->p_coat * warp_ggx_vndf_pdf(gltf_to_coat(L, wo), gltf_to_coat(L, h), L->alpha_c) /
           (4.0f * dot(wo, h));
  }
  const float sheen = L->p_sheen > 0.0f ? L->p_sheen * sheen_pdf(wi) : 0.0f;
  return coat + sheen + gltf_pdf_base_up(L, wo, wi);
}

/* Mirrors w through the tangent plane when flip. */
static inline float3 gltf_flip(float3 w, bool flip) { return flip ? (float3)(w.x, w.y, -w.z) : w; }

/* A purely Lambertian surface (metallic 0, no transmission, specular 0: the project's own
 * scenes, and many exported ones): the mixture has the diffuse lobe alone, with factor
 * (1 - 0)(1 - 0) = 1. These shortcuts give what the general path gives, without the lobe
 * set-up (BsdfLambertLimit compares them with the closed form). */
static inline bool gltf_is_lambert(const BsdfParams* p) {
  return !(p->specular > 0.0f) && !(p->metallic > 0.0f) && !(p->transmission > 0.0f) &&
         !(p->clearcoat > 0.0f) && !(p->diffuse_transmission > 0.0f) &&
         !(max_component(p->sheen_color) > 0.0f);
}

/* The layered lobes' evaluation, density and sampling below are out of line (CLPT_NOINLINE):
 * a kernel evaluates the BSDF at many call sites (next-event estimation, MIS, bdpt's
 * connections and reverse densities), and NVIDIA's compiler, which inlines every call, made a
 * copy of the whole layer stack at each of them. The Lambertian shortcuts stay inline. */
CLPT_NOINLINE float3 gltf_eval_layered(const BsdfParams* p, float3 nc, float3 wo, float3 wi,
                                       int mode) {
  const bool flip = wo.z < 0.0f;
  const GltfLobes L = gltf_lobes(p, nc, gltf_flip(wo, flip), !flip);
  return gltf_eval_up(p, &L, gltf_flip(wo, flip), gltf_flip(wi, flip), mode);
}

/* f(wo, wi) |wi.z| of the non-delta lobes; nc is the coat's normal in the local frame
 * (nc.z > 0; (0, 0, 1) when the coat shares the shading normal or there is no coat). From the
 * back (wo.z < 0) the mirrored surface keeps nc: the back is the front's mirror image. */
static inline float3 gltf_bsdf_eval(const BsdfParams* p, float3 nc, float3 wo, float3 wi, int mode) {
  if (wo.z == 0.0f) return (float3)(0.0f);
  if (gltf_is_lambert(p))
    return wo.z * wi.z > 0.0f ? p->base_color * (INV_PI_F * fabs(wi.z)) : (float3)(0.0f);
  return gltf_eval_layered(p, nc, wo, wi, mode);
}

/* The Lambertian factor kd(wo) of the diffuse layer with the layers' cos_i terms left out:
 * w_plastic (1 - max F(cos_o)) (1 - c Fc(cos_o)) (1 - m E'(cos_o)) base / pi, so that
 * f_diffuse(wo, wi) = kd(wo) (1 - max F(cos_i)) (1 - c Fc(cos_i)) min(1, sheen's at cos_i)
 * <= kd(wo) on wo's side. The irradiance cache stands for kd E and path traces the rest,
 * f - kd (kernels/integrators/ic/ic_path.cl); for a Lambertian surface the rest is 0. */
static inline float3 gltf_diffuse_factor(const BsdfParams* p, float3 nc, float3 wo) {
  if (wo.z == 0.0f) return (float3)(0.0f);
  if (gltf_is_lambert(p)) return p->base_color * INV_PI_F;
  const GltfLobes L = gltf_lobes(p, nc, gltf_flip(wo, wo.z < 0.0f), wo.z > 0.0f);
  if (!(L.w_plastic > 0.0f)) return (float3)(0.0f);
  return (L.w_plastic * (1.0f - L.dt) * (1.0f - max_component(gltf_coat(p, &L, fabs(wo.z)))) *
          gltf_clearcoat_pass(&L, L.cos_oc) * L.sheen_keep_o * INV_PI_F) *
         p->base_color;
}

CLPT_NOINLINE float gltf_pdf_layered(const BsdfParams* p, float3 nc, float3 wo, float3 wi) {
  const bool flip = wo.z < 0.0f;
  const GltfLobes L = gltf_lobes(p, nc, gltf_flip(wo, flip), !flip);
  return gltf_pdf_up(&L, gltf_flip(wo, flip), gltf_flip(wi, flip));
}

/* Density of gltf_bsdf_sample at wi, per steradian, the delta lobes left out. */
static inline float gltf_bsdf_pdf(const BsdfParams* p, float3 nc, float3 wo, float3 wi) {
  if (wo.z == 0.0f) return 0.0f;
  if (gltf_is_lambert(p)) return wo.z * wi.z > 0.0f ? warp_cosine_hemisphere_pdf(fabs(wi.z)) : 0.0f;
  return gltf_pdf_layered(p, nc, wo, wi);
}

/* gltf_bsdf_eval in xyz and gltf_bsdf_pdf in w at once, from one set of lobes: next-event
 * estimation's MIS weight needs both at a light sample's direction. */
CLPT_NOINLINE float4 gltf_eval_pdf_layered(const BsdfParams* p, float3 nc, float3 wo, float3 wi,
                                           int mode) {
  const bool flip = wo.z < 0.0f;
  const GltfLobes L = gltf_lobes(p, nc, gltf_flip(wo, flip), !flip);
  const float pdf = gltf_pdf_up(&L, gltf_flip(wo, flip), gltf_flip(wi, flip));
  return (float4)(gltf_eval_up(p, &L, gltf_flip(wo, flip), gltf_flip(wi, flip), mode), pdf);
}

static inline float4 gltf_bsdf_eval_pdf(const BsdfParams* p, float3 nc, float3 wo, float3 wi,
                                        int mode) {
  if (wo.z == 0.0f) return (float4)(0.0f);
  if (gltf_is_lambert(p)) {
    if (!(wo.z * wi.z > 0.0f)) return (float4)(0.0f);
    return (float4)(p->base_color * (INV_PI_F * fabs(wi.z)), warp_cosine_hemisphere_pdf(fabs(wi.z)));
  }
  return gltf_eval_pdf_layered(p, nc, wo, wi, mode);
}

/* Whether some lobe is not a Dirac delta (NEE and MIS make sense). */
static inline bool gltf_bsdf_has_smooth_lobe(const BsdfParams* p) {
  if (!(ggx_alpha_anisotropic(p->roughness, p->anisotropy).x < GGX_ALPHA_DELTA)) return true;
  if (p->clearcoat > 0.0f && !(ggx_alpha(p->clearcoat_roughness) < GGX_ALPHA_DELTA)) return true;
  if (max_component(p->sheen_color) > 0.0f) return true;
  return (1.0f - clamp(p->metallic, 0.0f, 1.0f)) * (1.0f - clamp(p->transmission, 0.0f, 1.0f)) *
             fmax(max_component(p->base_color),
                  p->diffuse_transmission * max_component(p->diffuse_transmission_color)) > 0.0f;
}

static inline BsdfSample gltf_absorbed(void) {
  BsdfSample bs;
  bs.wi = (float3)(0.0f, 0.0f, 1.0f);
  bs.weight = (float3)(0.0f);
  bs.pdf_w = 0.0f;
  bs.is_delta = 0;
  return bs;
}

/* The mirror direction of wo (mirrored frame), carrying every Dirac reflection at once: the
 * delta coat's c Fc(cos_o) (when it shares the normal) and, for a delta base, its reflection
 * seen through the coat twice. They share one discrete probability, whichever of their lobes
 * u_lobe picked. */
static inline BsdfSample gltf_mirror_sample(const BsdfParams* p, const GltfLobes* L, float3 wo,
                                            bool flip) {
  const float p_r = L->delta && L->p_glass > 0.0f ? max_component(gltf_glass_r(L, wo.z)) : 0.0f;
  const float base_p = L->delta ? L->p_reflect + L->p_glass * p_r : 0.0f;
  const bool coat_here = L->coat_delta && !L->coat_tilted;
  const float coat_p = coat_here ? L->p_coat : 0.0f;
  const float3 wi = (float3)(-wo.x, -wo.y, wo.z);
  const float3 base_f = L->delta ? gltf_reflectance(p, L, wo.z) *
                                       (gltf_clearcoat_pass(L, L->cos_oc) *
                                        gltf_clearcoat_pass(L, gltf_coat_cos(L, wi)) * L->sheen_keep_o)
                                 : (float3)(0.0f);
  const float3 coat_f = (float3)(coat_here ? gltf_clearcoat_f(L, wo.z) : 0.0f);
  BsdfSample bs;
  bs.pdf_w = base_p + coat_p;
  bs.wi = gltf_flip(wi, flip);
  bs.weight = (base_f + coat_f) / bs.pdf_w;
  bs.is_delta = 1;
  return bs;
}

/* A delta coat with a normal of its own: wo mirrored about nc, with the rough coat's limit
 * (gltf_coat_eval_up; wi.nc = wo.nc): c Fc(wo.nc), and in importance mode that times
 * wi.z / wo.z. A mirror direction under the surface is absorbed. */
static inline BsdfSample gltf_coat_mirror_sample(const GltfLobes* L, float3 wo, bool flip, int mode) {
  const float3 wi = 2.0f * dot(wo, L->nc) * L->nc - wo;
  if (!(wi.z > 0.0f) || !(L->cos_oc > 0.0f)) return gltf_absorbed();
  BsdfSample bs;
  bs.pdf_w = L->p_coat;
  bs.wi = gltf_flip(wi, flip);
  float w = gltf_clearcoat_f(L, L->cos_oc) / L->p_coat;
  if (mode == TRANSPORT_IMPORTANCE) w *= wi.z / wo.z;
  bs.weight = (float3)(w);
  bs.is_delta = 1;
  return bs;
}

/* The layered lobes' sampling, wo_in.z != 0 (gltf_bsdf_sample). */
CLPT_NOINLINE BsdfSample gltf_sample_layered(const BsdfParams* p, float3 nc, float3 wo_in,
                                             float2 u, float u_lobe, int mode) {
  const bool flip = wo_in.z < 0.0f;
  const float3 wo = gltf_flip(wo_in, flip);
  const GltfLobes L = gltf_lobes(p, nc, wo, !flip);
  BsdfSample bs = gltf_absorbed();
  float3 wi;
  bool reflect = true; /* the side wi must end on; the other side absorbs the sample */
  if (u_lobe < L.p_coat) {
    if (L.coat_delta)
      return L.coat_tilted ? gltf_coat_mirror_sample(&L, wo, flip, mode) : gltf_mirror_sample(p, &L, wo, flip);
    const float3 h = gltf_from_coat(&L, warp_ggx_vndf(u, gltf_to_coat(&L, wo), L.alpha_c));
    wi = 2.0f * dot(wo, h) * h - wo;
  } else if ((u_lobe -= L.p_coat) < L.p_sheen) {
    wi = sheen_sample(u);
  } else if ((u_lobe -= L.p_sheen) < L.p_diffuse) {
    wi = warp_cosine_hemisphere(u);
  } else if (u_lobe < L.p_diffuse + L.p_dtrans) {
    wi = warp_cosine_hemisphere(u);
    wi.z = -wi.z;
    reflect = false;
  } else if (u_lobe < L.p_diffuse + L.p_dtrans + L.p_reflect || !(L.p_glass > 0.0f)) {
    if (!(L.p_reflect > 0.0f)) return bs;
    if (L.delta) return gltf_mirror_sample(p, &L, wo, flip); /* the glass's share too */
    const float3 h = warp_ggx_vndf_2(u, wo, L.alpha);
    wi = 2.0f * dot(wo, h) * h - wo;
  } else {
    const float v = fmin((u_lobe - L.p_diffuse - L.p_dtrans - L.p_reflect) / L.p_glass, 0x1.fffffep-1f);
    const float3 h = L.delta ? (float3)(0.0f, 0.0f, 1.0f) : warp_ggx_vndf_2(u, wo, L.alpha);
    const float wo_h = dot(wo, h);
    const float p_r = max_component(gltf_glass_r(&L, wo_h));
    if (v < p_r) {
      if (L.delta) return gltf_mirror_sample(p, &L, wo, flip);
      wi = 2.0f * wo_h * h - wo;
    } else {
      if (!refract_dir(wo, h, L.eta, &wi)) return bs;
      reflect = false;
      if (L.delta) {
        bs.pdf_w = L.p_glass * (1.0f - p_r);
        bs.wi = gltf_flip(wi, flip);
        bs.weight = (L.w_glass / L.p_glass) * gltf_clearcoat_pass(&L, L.cos_oc) *
                    gltf_clearcoat_pass(&L, gltf_coat_cos(&L, wi)) * p->base_color;
        if (L.sheen_m > 0.0f) bs.weight *= gltf_sheen_keep(&L, sheen_albedos(fabs(wi.z), L.sheen.r));
        if (mode == TRANSPORT_RADIANCE) bs.weight /= L.eta * L.eta;
        bs.is_delta = 1;
        return bs;
      }
    }
  }
  if (reflect ? !(wi.z > 0.0f) : !(wi.z < 0.0f)) return bs;
  const float pdf = gltf_pdf_up(&L, wo, wi);
  if (!(pdf > 0.0f)) return bs; /* e.g. a reflection below the horizon */
  bs.wi = gltf_flip(wi, flip);
  bs.pdf_w = pdf;
  bs.weight = gltf_eval_up(p, &L, wo, wi, mode) / pdf;
  return bs;
}

/* One direction from the lobe mixture: u picks the direction within the lobe, u_lobe the
 * lobe (and, rescaled, reflection or refraction within the glass lobe). */
static inline BsdfSample gltf_bsdf_sample(const BsdfParams* p, float3 nc, float3 wo_in, float2 u,
                                          float u_lobe, int mode) {
  if (wo_in.z == 0.0f) return gltf_absorbed();
  if (gltf_is_lambert(p)) {
    const float3 wi = warp_cosine_hemisphere(u);
    BsdfSample bs = gltf_absorbed();
    bs.pdf_w = warp_cosine_hemisphere_pdf(wi.z);
    if (!(bs.pdf_w > 0.0f)) return bs;
    bs.wi = gltf_flip(wi, wo_in.z < 0.0f);
    bs.weight = p->base_color;
    return bs;
  }
  return gltf_sample_layered(p, nc, wo_in, u, u_lobe, mode);
}

#endif
