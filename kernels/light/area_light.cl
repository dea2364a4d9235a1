/* Emissive triangles as area lights. A point is chosen uniformly on the triangle's area
 * (pdf_a = 1 / area); emission is one-sided (front face, counter-clockwise winding) unless
 * the material is double-sided. */
#ifndef CLPT_LIGHT_AREA_LIGHT_CL
#define CLPT_LIGHT_AREA_LIGHT_CL

#include "geometry/surface.cl"
#include "core/warp.cl"
#include "light/light_types.cl"
#include "material/material.cl"

/* Emitted radiance of triangle `tri` at barycentrics (b1, b2), front side: the emission
 * factor times the emissive texture at that point (kernels/material/material.cl), so NEE
 * sees the same radiance as a ray that hits the point. */
static inline float3 area_light_emission(const SceneView* s, u32 tri, float b1, float b2) {
  return material_emission_at(s, tri, b1, b2);
}

/* Whether emission leaves towards w from a surface with geometric normal ng. */
static inline bool area_light_faces(const SceneView* s, u32 material, float3 ng, float3 w) {
  return (s->materials[material].flags & MATERIAL_DOUBLE_SIDED) || dot(ng, w) > 0.0f;
}

/* Radiance a ray sees when it hits the surface sh, leaving towards wo = the ray's -dir
 * (sh->emission is resolved at the hit point, textures included). The side is the one the
 * ray arrived on (sh->front, from surface_at), so the answer does not depend on whether
 * bsdf_orient has turned the normals to wo yet: dot(ng, wo) > 0 is sh->front exactly. */
static inline float3 area_light_radiance(const SceneView* s, const SurfaceHit* sh, float3 wo) {
  if (is_black(sh->emission)) return (float3)(0.0f);
  if (!sh->front && !(s->materials[sh->material].flags & MATERIAL_DOUBLE_SIDED)) return (float3)(0.0f);
  return sh->emission;
}

/* Solid-angle density at a point dist away of choosing a point of triangle `tri` seen under
 * cosine cos_light (selection not included). */
static inline float area_light_pdf_w(const SceneView* s, u32 tri, float dist, float cos_light) {
  if (!(cos_light > 0.0f)) return 0.0f;
  const float area = triangle_area(s, tri);
  if (!(area > 0.0f)) return 0.0f;
  return dist * dist / (area * cos_light);
}

/* A point of triangle `tri` as seen from p. ls->pdf_w excludes the selection probability. */
static inline LightSample area_light_illuminate(const SceneView* s, u32 tri, float3 p, float2 u) {
  LightSample ls = light_sample_none(p);
  float3 p0, p1, p2;
  triangle_vertices(s, tri, &p0, &p1, &p2);
  const float2 b = warp_uniform_triangle(u);
  const float3 c = cross(p1 - p0, p2 - p0);
  const float area = 0.5f * length(c);
  if (!(area > 0.0f)) return ls;
  const float3 ng = c / (2.0f * area);
  ls.p = (1.0f - b.x - b.y) * p0 + b.x * p1 + b.y * p2;
  ls.n = ng;
  const float3 d = ls.p - p;
  const float dist2 = dot(d, d);
  if (!(dist2 > 0.0f)) return ls;
  ls.dist = sqrt(dist2);
  ls.wi = d / ls.dist;
  const float cos_light = fabs(dot(ng, ls.wi));
  if (!(cos_light > 0.0f)) return ls;
  if (!area_light_faces(s, s->triangles[tri].material, ng, -ls.wi)) return ls;
  ls.Le = area_light_emission(s, tri, b.x, b.y);
  ls.pdf_w = dist2 / (area * cos_light);
  return ls;
}

/* A ray leaving triangle `tri`: a uniform point, a cosine-distributed direction about the
 * front normal (either side with probability 1/2 when double-sided). */
static inline LightEmission area_light_emit(const SceneView* s, u32 tri, float2 u_pos,
                                            float2 u_dir) {
  LightEmission e;
  e.pdf_a = 0.0f;
  e.pdf_w = 0.0f;
  e.is_delta_pos = 0;
  e.is_delta_dir = 0;
  e.Le = (float3)(0.0f);
  e.cos_light = 0.0f;
  float3 p0, p1, p2;
  triangle_vertices(s, tri, &p0, &p1, &p2);
  const float3 c = cross(p1 - p0, p2 - p0);
  const float area = 0.5f * length(c);
  e.p = p0;
  e.dir = (float3)(0.0f, 0.0f, 1.0f);
  if (!(area > 0.0f)) return e;
  float3 ng = c / (2.0f * area);
  const float2 b = warp_uniform_triangle(u_pos);
  e.p = (1.0f - b.x - b.y) * p0 + b.x * p1 + b.y * p2;
  float side_pdf = 1.0f;
  float2 ud = u_dir;
  if (s->materials[s->triangles[tri].material].flags & MATERIAL_DOUBLE_SIDED) {
    side_pdf = 0.5f;
    if (ud.x < 0.5f) {
      ud.x *= 2.0f;
    } else {
      ud.x = 2.0f * ud.x - 1.0f;
      ng = -ng;
    }
    ud.x = fmin(ud.x, 0x1.fffffep-1f);
  }
  const float3 h = warp_cosine_hemisphere(ud);
  e.dir = to_world(h, ng);
  e.cos_light = h.z;
  e.pdf_a = 1.0f / area;
  e.pdf_w = side_pdf * warp_cosine_hemisphere_pdf(h.z);
  e.Le = area_light_emission(s, tri, b.x, b.y);
  return e;
}

#endif
