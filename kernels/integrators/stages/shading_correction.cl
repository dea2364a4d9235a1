/* Veach's correction for shading normals on light paths (Veach 1997, section 5.3): a vertex
 * that carries importance (BSDF evaluated and sampled in TRANSPORT_IMPORTANCE mode, wo
 * towards the light) multiplies |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|), with the normal the BSDF
 * shades with (bsdf_frame: the shading normal, or the geometric one where wo is below it).
 * Used by every light-side path: the walk (stages/walk.cl), camera connections (lt, bdpt)
 * and bdpt's light vertices. */
#ifndef CLPT_INTEGRATORS_STAGES_SHADING_CORRECTION_CL
#define CLPT_INTEGRATORS_STAGES_SHADING_CORRECTION_CL

#include "bsdf/bsdf.cl"

static inline float shading_correction(const SurfaceHit* sh, float3 wo, float3 wi) {
  const BsdfFrame f = bsdf_frame(sh, wo);
  const float den = fabs(dot(wo, sh->ng)) * fabs(dot(wi, f.n));
  if (!(den > 0.0f)) return 0.0f;
  return fabs(dot(wo, f.n)) * fabs(dot(wi, sh->ng)) / den;
}

#endif
