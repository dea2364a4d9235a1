/* The surface BSDF at a hit: the glTF BSDF of kernels/bsdf/gltf_bsdf.cl on the hit's
 * resolved parameters (sh->bsdf), in world space. Directions are world space; wo points away
 * from the surface towards the viewer.
 *
 * The local frame's +z is the shading normal of the front face (the outside of the closed
 * volume the surface bounds); whether wo is outside comes from sh->front, set by
 * surface_at from the ray. That works whether or not bsdf_orient has flipped the normals.
 * Geometric-side checks: a direction the shading frame calls a reflection must be on wo's
 * side of the geometric normal, a transmission on the other side; otherwise f = 0, so no
 * light leaks through shading normals. When wo itself is on the wrong side of the shading
 * hemisphere, the geometric normal shades. Cosines are taken with the shading normal. */
#ifndef CLPT_BSDF_BSDF_CL
#define CLPT_BSDF_BSDF_CL

#include "bsdf/gltf_bsdf.cl"
#include "geometry/surface.cl"

/* Orients the hit's normals to wo's side (sh->front keeps the side the ray arrived from,
 * sh->flipped whether the normals now face the back). */
static inline void bsdf_orient(SurfaceHit* sh, float3 wo) {
  if (dot(sh->ng, wo) < 0.0f) {
    sh->ng = -sh->ng;
    sh->ns = -sh->ns;
    sh->flipped ^= 1u;
  }
}

/* The shading frame at sh for wo: tangents t, b and the front-face normal n; t along the
 * anisotropy direction when the BSDF has one, else any (make_basis). */
typedef struct BsdfFrame {
  float3 t, b, n;
  float3 nc; /* the clearcoat's normal in this frame, nc.z > 0; exactly +z where it is n */
  float go;  /* dot(ng, wo) with ng as stored in sh */
} BsdfFrame;

static inline float3 bsdf_to_local(const BsdfFrame* f, float3 w) {
  return (float3)(dot(w, f->t), dot(w, f->b), dot(w, f->n));
}

/* The clearcoat's normal in frame f: (0, 0, 1) exactly when it is the frame's normal (no coat,
 * or no map on the coat's normal and none on the base's), else the stored normal in f, kept
 * above the tangent plane as a normal map is. */
static inline float3 bsdf_coat_normal(const SurfaceHit* sh, const BsdfFrame* f) {
  if (!(sh->bsdf.clearcoat > 0.0f) || all(sh->bsdf.clearcoat_n == f->n)) return (float3)(0.0f, 0.0f, 1.0f);
  float3 nc = bsdf_to_local(f, sh->bsdf.clearcoat_n);
  if (nc.z < 1e-3f) nc.z = 1e-3f;
  nc = normalize(nc);
  return nc.x == 0.0f && nc.y == 0.0f ? (float3)(0.0f, 0.0f, 1.0f) : nc;
}

static inline BsdfFrame bsdf_frame(const SurfaceHit* sh, float3 wo) {
  BsdfFrame f;
  f.go = dot(sh->ng, wo);
  /* ng and ns are on one side, the front one unless bsdf_orient flipped them. That is read
   * from sh alone, not guessed from wo: a reverse density (wo and wi swapped, as
   * bidirectional MIS asks for) has wo on the other side after a refraction. */
  const float sign = sh->flipped ? -1.0f : 1.0f;
  const float3 ng_front = sign * sh->ng;
  f.n = sign * sh->ns;
  if (dot(f.n, wo) * dot(ng_front, wo) <= 0.0f) f.n = ng_front;
  bool oriented = false;
  if (sh->bsdf.anisotropy > 0.0f) {
    /* An anisotropic BSDF is oriented: x along the anisotropy direction, made orthogonal
     * to n (which may be the geometric normal here, or the stored direction rounded). */
    const float3 t = sh->bsdf.anisotropy_t - f.n * dot(f.n, sh->bsdf.anisotropy_t);
    const float tl2 = dot(t, t);
    if (tl2 > 1e-12f) {
      f.t = t * rsqrt(tl2);
      f.b = cross(f.n, f.t);
      oriented = true;
    }
  }
  if (!oriented) make_basis(f.n, &f.t, &f.b);
  f.nc = bsdf_coat_normal(sh, &f);
  return f;
}

static inline float3 bsdf_to_world(const BsdfFrame* f, float3 w) {
  return w.x * f->t + w.y * f->b + w.z * f->n;
}

/* Whether the geometric normal agrees with the shading frame about the side of wi. */
static inline bool bsdf_sides_agree(const BsdfFrame* f, const SurfaceHit* sh, float3 wo_l,
                                    float3 wi_l,
                                    float3 wi) {
  const float gi = dot(sh->ng, wi);
  return (wo_l.z * wi_l.z > 0.0f) ? (gi * f->go > 0.0f) : (gi * f->go < 0.0f);
}

/* f(wo, wi) |cos(ns, wi)| of the non-delta lobes. */
static inline float3 bsdf_eval_cos(const SurfaceHit* sh, float3 wo, float3 wi, int mode) {
  const BsdfFrame f = bsdf_frame(sh, wo);
  const float3 wo_l = bsdf_to_local(&f, wo), wi_l = bsdf_to_local(&f, wi);
  if (!bsdf_sides_agree(&f, sh, wo_l, wi_l, wi)) return (float3)(0.0f);
  return gltf_bsdf_eval(&sh->bsdf, f.nc, wo_l, wi_l, mode);
}

/* bsdf_eval_cos in xyz and, wherever that is not 0, bsdf_pdf_w in w: one frame and one set
 * of lobes for both (next-event estimation's MIS weight needs both). All 0 where the
 * geometric sides disagree. */
static inline float4 bsdf_eval_cos_pdf(const SurfaceHit* sh, float3 wo, float3 wi, int mode) {
  const BsdfFrame f = bsdf_frame(sh, wo);
  const float3 wo_l = bsdf_to_local(&f, wo), wi_l = bsdf_to_local(&f, wi);
  if (!bsdf_sides_agree(&f, sh, wo_l, wi_l, wi)) return (float4)(0.0f);
  return gltf_bsdf_eval_pdf(&sh->bsdf, f.nc, wo_l, wi_l, mode);
}

/* f(wo, wi) of the non-delta lobes without the cosine: photon density estimation, whose
 * photons' flux per area already holds the cosine at their arrival. The frame f =
 * bsdf_frame(sh, wo) and wo_l = wo in it are made once for all the photons of an estimate. */
static inline float3 bsdf_eval_in_frame(const SurfaceHit* sh, const BsdfFrame* f, float3 wo_l,
                                        float3 wi,
                                        int mode) {
  const float3 wi_l = bsdf_to_local(f, wi);
  const float c = fabs(wi_l.z);
  if (!(c > 1e-6f) || !bsdf_sides_agree(f, sh, wo_l, wi_l, wi)) return (float3)(0.0f);
  return gltf_bsdf_eval(&sh->bsdf, f->nc, wo_l, wi_l, mode) / c;
}

/* gltf_diffuse_factor at wo: the diffuse layer's f for directions on wo's side, its coat
 * term at wi left out. */
static inline float3 bsdf_diffuse_factor(const SurfaceHit* sh, float3 wo) {
  const BsdfFrame f = bsdf_frame(sh, wo);
  return gltf_diffuse_factor(&sh->bsdf, f.nc, bsdf_to_local(&f, wo));
}

/* Density of bsdf_sample at wi (solid angle), the delta lobes left out. */
static inline float bsdf_pdf_w(const SurfaceHit* sh, float3 wo, float3 wi) {
  const BsdfFrame f = bsdf_frame(sh, wo);
  return gltf_bsdf_pdf(&sh->bsdf, f.nc, bsdf_to_local(&f, wo), bsdf_to_local(&f, wi));
}

/* Whether the BSDF has a non-delta lobe: NEE and MIS apply only then. */
static inline bool bsdf_has_smooth_lobe(const SurfaceHit* sh) {
  return gltf_bsdf_has_smooth_lobe(&sh->bsdf);
}

/* A direction from the BSDF's lobe mixture (u: within the lobe, u_lobe: which lobe). A
 * direction on the wrong geometric side keeps its pdf but gets weight 0. */
static inline BsdfSample bsdf_sample(const SurfaceHit* sh, float3 wo, float2 u, float u_lobe,
                                     int mode) {
  const BsdfFrame f = bsdf_frame(sh, wo);
  const float3 wo_l = bsdf_to_local(&f, wo);
  BsdfSample bs = gltf_bsdf_sample(&sh->bsdf, f.nc, wo_l, u, u_lobe, mode);
  const float3 wi_l = bs.wi;
  bs.wi = bsdf_to_world(&f, wi_l);
  if (!bsdf_sides_agree(&f, sh, wo_l, wi_l, bs.wi)) bs.weight = (float3)(0.0f);
  return bs;
}

#endif
