/* Emissive triangles as area lights, with the three verbs every integrator needs:
 *   light_illuminate: sample a point on a light as seen from a shading point (NEE),
 *   light_radiance:   the radiance a ray sees when it hits an emitter,
 *   light_pdf_w:      the solid-angle density light_illuminate has for that hit (for MIS).
 * An emitter is chosen in proportion to its power through an alias table built on the host,
 * then a point uniformly on its area. Emission is one-sided (front face, counter-clockwise
 * winding) unless the material is double-sided. */
#ifndef CLPT_LIGHT_AREA_LIGHT_CL
#define CLPT_LIGHT_AREA_LIGHT_CL

#include "core/surface.cl"
#include "core/warp.cl"

typedef struct LightSample {
  float3 p;      /* point on the light */
  float3 wi;     /* unit direction from the shading point to p */
  float dist;    /* distance to p */
  float3 Le;     /* emitted radiance towards the shading point */
  float pdf_w;   /* solid-angle density at the shading point, 0 if the sample is invalid */
} LightSample;

inline float3 material_emission(const SceneView* s, u32 material) {
  return vload3(0, s->materials[material].emission);
}

/* Radiance leaving the emitter triangle `tri` with geometric normal ng towards direction w. */
inline float3 light_radiance(const SceneView* s, u32 material, float3 ng, float3 w) {
  const __global Material* m = &s->materials[material];
  if (!(m->flags & MATERIAL_EMISSIVE)) return (float3)(0.0f);
  if (!(m->flags & MATERIAL_DOUBLE_SIDED) && dot(ng, w) <= 0.0f) return (float3)(0.0f);
  return vload3(0, m->emission);
}

inline u32 light_select(const SceneView* s, float u) {
  const float scaled = u * (float)s->num_lights;
  const u32 slot = min((u32)scaled, s->num_lights - 1u);
  const __global Light* e = &s->lights[slot];
  return (scaled - (float)slot) < e->alias_threshold ? slot : e->alias;
}

inline LightSample light_illuminate(const SceneView* s, float3 p, float u_select, float2 u_point) {
  LightSample ls;
  ls.pdf_w = 0.0f;
  ls.Le = (float3)(0.0f);
  ls.p = p;
  ls.wi = (float3)(0.0f, 0.0f, 1.0f);
  ls.dist = 0.0f;
  if (s->num_lights == 0u) return ls;
  const u32 e = light_select(s, u_select);
  const u32 tri = s->lights[e].triangle;
  float3 p0, p1, p2;
  triangle_vertices(s, tri, &p0, &p1, &p2);
  const float2 b = warp_uniform_triangle(u_point);
  const float3 c = cross(p1 - p0, p2 - p0);
  const float area = 0.5f * length(c);
  if (!(area > 0.0f)) return ls;
  const float3 ng = c / (2.0f * area);
  ls.p = (1.0f - b.x - b.y) * p0 + b.x * p1 + b.y * p2;
  const float3 d = ls.p - p;
  const float dist2 = dot(d, d);
  if (!(dist2 > 0.0f)) return ls;
  ls.dist = sqrt(dist2);
  ls.wi = d / ls.dist;
  const float cos_light = fabs(dot(ng, ls.wi));
  if (!(cos_light > 0.0f)) return ls;
  ls.Le = light_radiance(s, s->triangles[tri].material, ng, -ls.wi);
  ls.pdf_w = s->lights[e].pdf_select / area * dist2 / cos_light;
  return ls;
}

/* Density of light_illuminate, in solid angle at a point `dist` away, for a ray that hit
 * emitter triangle `tri` (leaf order) under cosine cos_light at the light. */
inline float light_pdf_w(const SceneView* s, u32 tri, float dist, float cos_light) {
  const int e = s->triangle_light[tri];
  if (e < 0 || !(cos_light > 0.0f)) return 0.0f;
  const float area = triangle_area(s, tri);
  if (!(area > 0.0f)) return 0.0f;
  return s->lights[e].pdf_select / area * dist * dist / cos_light;
}

#endif
