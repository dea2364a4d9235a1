/* Which vertices photon mapping treats as glossy (docs/concepts/photon-mapping.md): the
 * camera side path traces through them rather than estimating density there
 * (kernels/integrators/estimators/photon/visible_point.cl), and the photon side stores no photon at
 * them and counts them, like delta scatterings, towards caustic paths
 * (kernels/integrators/photon/photon_trace.cl). */
#ifndef CLPT_PHOTON_GLOSSY_CL
#define CLPT_PHOTON_GLOSSY_CL

#include "bsdf/bsdf.cl"

/* Glossy: no diffuse lobe (metal or glass alone) and a GGX roughness below the threshold, but
 * not a delta. */
#define PHOTON_GLOSSY_ROUGHNESS 0.5f
static inline bool photon_glossy(const SurfaceHit* sh) {
  const float m = clamp(sh->bsdf.metallic, 0.0f, 1.0f), t = clamp(sh->bsdf.transmission, 0.0f, 1.0f);
  return (1.0f - m) * (1.0f - t) < 1e-4f && sh->bsdf.roughness < PHOTON_GLOSSY_ROUGHNESS &&
         bsdf_has_smooth_lobe(sh);
}

#endif
