/* Material evaluation at a surface point: the glTF material's factors (and, once textures
 * exist, its textures and the vertex colour) resolved into the BSDF inputs and emission. */
#ifndef CLPT_MATERIAL_MATERIAL_CL
#define CLPT_MATERIAL_MATERIAL_CL

#include "core/surface.cl"

inline void material_resolve(const SceneView* s, SurfaceHit* sh) {
  const __global Material* m = &s->materials[sh->material];
  sh->bsdf.base_color = vload3(0, m->base_color);
  sh->bsdf.specular_color = vload3(0, m->specular_color);
  sh->bsdf.metallic = m->metallic;
  sh->bsdf.roughness = m->roughness;
  sh->bsdf.specular = m->specular;
  sh->bsdf.transmission = m->transmission;
  sh->bsdf.ior = m->ior;
  sh->emission = (m->flags & MATERIAL_EMISSIVE) ? vload3(0, m->emission) : (float3)(0.0f);
}

/* The hit's surface with its material resolved: what integrators shade with. */
inline SurfaceHit surface_shade(const SceneView* s, const Hit* hit, float3 org, float3 dir) {
  SurfaceHit sh = surface_at(s, hit, org, dir);
  material_resolve(s, &sh);
  return sh;
}

#endif
