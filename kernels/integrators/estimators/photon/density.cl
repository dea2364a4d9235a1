/* Photon density estimation (Jensen 2001, ch. 7): the radiance a surface point x reflects
 * towards wo, from the photons around it,
 *     L(x, wo) ~ sum_p f(x, wo, wi_p) Phi_p K(d_p),
 * with K a 2D kernel over the disc of radius r around x that integrates to 1:
 *     box           K = 1 / (pi r^2)                              (SPPM's estimate)
 *     cone (k = 1)  K = 3 / (pi r^2) (1 - d / r)                   (Jensen's cone filter)
 *     Epanechnikov  K = 2 / (pi r^2) (1 - d^2 / r^2)
 * A photon counts only where it lies on x's surface: its normal must be within about 37
 * degrees of x's, either way round (the same plane seen from either side; which side may
 * reflect is the BSDF's business, so transmission through rough glass is kept and light
 * from behind an opaque wall is not). Photons on a wall meeting x's at a corner are left
 * out without changing the disc's area, which is right: the plane through x meets the
 * sphere of radius r in that disc whatever else the sphere holds. */
#ifndef CLPT_PHOTON_DENSITY_CL
#define CLPT_PHOTON_DENSITY_CL

#include "bsdf/bsdf.cl"
#include "shared/photon_types.h"
#include "shared/render_types.h"

#define PHOTON_NORMAL_COS 0.8f

static inline float photon_kernel(u32 filter, float d2, float r2) {
  if (!(r2 > 0.0f) || d2 > r2) return 0.0f;
  const float inv_area = 1.0f / (M_PI_F * r2);
  if (filter == PHOTON_FILTER_CONE) return 3.0f * inv_area * (1.0f - sqrt(d2 / r2));
  if (filter == PHOTON_FILTER_EPANECHNIKOV) return 2.0f * inv_area * (1.0f - d2 / r2);
  return inv_area;
}

static inline u32 photon_bounce(u32 flags) { return (flags >> PHOTON_BOUNCE_SHIFT) & 0xffu; }

/* Whether a photon lies on the surface of hit sh (its normal check). */
static inline bool photon_on_surface(const SurfaceHit* sh, __global const Photon* ph) {
  return fabs(dot(vload3(0, ph->n), sh->ng)) >= PHOTON_NORMAL_COS;
}

/* x's BSDF towards wo, set up once per estimate for all its photons. */
typedef struct PhotonShading {
  BsdfFrame frame;
  float3 wo_local;
} PhotonShading;

static inline PhotonShading photon_shading(const SurfaceHit* sh, float3 wo) {
  PhotonShading s;
  s.frame = bsdf_frame(sh, wo);
  s.wo_local = bsdf_to_local(&s.frame, wo);
  return s;
}

/* wi rotated by the smallest rotation that takes unit vector a to unit vector b (dot(a, b)
 * > -1): Rodrigues' formula with k = a x b, c = a . b. */
static inline float3 rotate_between(float3 a, float3 b, float3 wi) {
  const float3 k = cross(a, b);
  const float c = dot(a, b);
  return wi * c + cross(k, wi) + k * (dot(k, wi) / (1.0f + c));
}

/* f(x, wo, wi_p) Phi_p for one photon on x's surface; sh's normals oriented to wo. The
 * photon's direction is carried from its own surface to x's first: rotated by the rotation
 * that takes its normal n_p (stored facing the side it lit) to x's normal on that side. On
 * a plane that changes nothing. On a curved surface it keeps a photon that arrived at a
 * grazing angle on a neighbouring facet on the side it lit: taken as it is, wi_p could lie
 * below x's tangent plane (x's BSDF gives 0: light lost, 0.35 % of a furnace's inner
 * sphere) or, for a photon inside a thin shell, above it (light leaking out through a lamp
 * shade: PhotonMapping.NoLightThroughAClosedShell). */
static inline float3 photon_reflected(const SurfaceHit* sh, const PhotonShading* s,
                                      __global const Photon* ph) {
  const float3 n_p = vload3(0, ph->n);
  const float3 n_x = dot(n_p, sh->ng) >= 0.0f ? sh->ng : -sh->ng;
  const float3 wi = rotate_between(n_p, n_x, vload3(0, ph->wi));
  return bsdf_eval_in_frame(sh, &s->frame, s->wo_local, wi, TRANSPORT_RADIANCE) *
         vload3(0, ph->power);
}

#endif
