/* KHR_materials_volume: Beer-Lambert absorption inside closed meshes. A ray that leaves a
 * surface of a volume material towards its inside (against the outward, winding-side
 * normal) travels through the medium until the next hit, and keeps
 *   attenuation_color ^ (t / attenuation_distance)
 * of its throughput over distance t (the extension's definition of the two parameters).
 * Scattering inside the medium and nested media are not modelled; a mesh that is not closed
 * has no inside for a ray that escapes it (no absorption). */
#ifndef CLPT_MATERIAL_VOLUME_CL
#define CLPT_MATERIAL_VOLUME_CL

#include "core/surface.cl"

/* sh: the surface the ray leaves; its outward normal is the front face's, ng unless
 * bsdf_orient flipped it. */
inline float3 volume_transmittance(const SceneView* s, const SurfaceHit* sh, float3 wi, float t) {
  const __global Material* m = &s->materials[sh->material];
  if (!(m->flags & MATERIAL_VOLUME)) return (float3)(1.0f);
  const float3 outward = sh->flipped ? -sh->ng : sh->ng;
  if (!(dot(wi, outward) < 0.0f)) return (float3)(1.0f);
  const float3 c = clamp(vload3(0, m->attenuation_color), 0.0f, 1.0f);
  return pow(c, (float3)(t / m->attenuation_distance));
}

#endif
