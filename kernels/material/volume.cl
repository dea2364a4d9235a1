/* KHR_materials_volume: Beer-Lambert absorption inside closed meshes. A ray that leaves a
 * surface of a volume material towards its inside (against the outward, winding-side
 * normal) travels through the medium until the next hit, and keeps
 *   attenuation_color ^ (t / attenuation_distance)
 * of its throughput over distance t (the extension's definition of the two parameters).
 * Scattering inside the medium and nested media are not modelled; a mesh that is not closed
 * has no inside for a ray that escapes it (no absorption). */
#ifndef CLPT_MATERIAL_VOLUME_CL
#define CLPT_MATERIAL_VOLUME_CL

#include "geometry/surface.cl"

/* No medium: the ray travels outside every volume. */
#define MEDIUM_NONE 0xffffffffu

/* The medium a ray leaving surface sh in direction wi travels in: sh's material when it has a
 * volume and wi points inside (against the outward normal: the front face's, ng unless
 * bsdf_orient flipped it), else MEDIUM_NONE. */
static inline u32 volume_medium(const SceneView* s, const SurfaceHit* sh, float3 wi) {
  const __global Material* m = &s->materials[sh->material];
  if (!(m->flags & MATERIAL_VOLUME)) return MEDIUM_NONE;
  const float3 outward = sh->flipped ? -sh->ng : sh->ng;
  if (!(dot(wi, outward) < 0.0f)) return MEDIUM_NONE;
  return sh->material;
}

/* The fraction of throughput left after distance t inside `medium` (not MEDIUM_NONE). */
static inline float3 medium_transmittance(const SceneView* s, u32 medium, float t) {
  const __global Material* m = &s->materials[medium];
  const float3 c = clamp(vload3(0, m->attenuation_color), 0.0f, 1.0f);
  return pow(c, (float3)(t / m->attenuation_distance));
}

/* Both in one: the transmittance over distance t of a ray leaving sh in direction wi. */
static inline float3 volume_transmittance(const SceneView* s, const SurfaceHit* sh, float3 wi,
                                          float t) {
  const u32 medium = volume_medium(s, sh, wi);
  return medium == MEDIUM_NONE ? (float3)(1.0f) : medium_transmittance(s, medium, t);
}

#endif
