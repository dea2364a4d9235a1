/* The local geometry of a ray hit: position, normals, uv and material. */
#ifndef CLPT_CORE_SURFACE_CL
#define CLPT_CORE_SURFACE_CL

#include "core/hit.cl"
#include "core/math.cl"
#include "core/scene_view.cl"
#include "geometry/vertex_attributes.cl"
#include "bsdf/bsdf_params.h"

typedef struct SurfaceHit {
  float3 p;
  float3 ng;          /* geometric normal, from the winding (front side), unit */
  float3 ns;          /* shading normal, on the same side as ng, unit */
  float2 uv;
  float2 uv1;         /* TEXCOORD_1 (0 without) */
  float4 color;       /* COLOR_0, linear RGBA (1 without) */
  float4 tangent;     /* interpolated tangent xyz and bitangent sign w; zero: none */
  float2 tex_lod;     /* per UV set, log2 of the texture footprint's width in UV units
                       * (surface_texture_lod); -INFINITY: none (full resolution) */
  u32 triangle;
  u32 material;
  u32 front;          /* 1 when the ray arrived on the front (winding) side */
  u32 flipped;        /* 1 while ng and ns are the front face's negated (bsdf_orient
                       * turned them to a back-side wo); 0 while they are the front face's */
  BsdfParams bsdf;    /* resolved by material_resolve (kernels/material/material.cl) */
  float3 emission;    /* emitted radiance of the material at this point (front side) */
} SurfaceHit;

static inline void triangle_vertices(const SceneView* s, u32 tri, float3* p0, float3* p1,
                                     float3* p2) {
  const Triangle t = s->triangles[tri];
  *p0 = vertex_position(s, t.v[0]);
  *p1 = vertex_position(s, t.v[1]);
  *p2 = vertex_position(s, t.v[2]);
}

static inline float triangle_area(const SceneView* s, u32 tri) {
  float3 p0, p1, p2;
  triangle_vertices(s, tri, &p0, &p1, &p2);
  return 0.5f * length(cross(p1 - p0, p2 - p0));
}

/* Geometric normal of a triangle from its winding; an arbitrary unit vector if degenerate. */
static inline float3 safe_normal(float3 n) {
  const float len = length(n);
  return len > 0.0f && isfinite(len) ? n / len : (float3)(0.0f, 0.0f, 1.0f);
}

/* The hit's surface, written to *out (the walk's own vertex: a SurfaceHit returned by value
 * was built aside and then copied, 320 bytes, on PoCL). */
static inline void surface_at_to(const SceneView* s, const Hit* hit, float3 org, float3 dir,
                                 SurfaceHit* out) {
  const Triangle t = s->triangles[hit->triangle];
  const Vertex v0 = s->vertices[t.v[0]], v1 = s->vertices[t.v[1]], v2 = s->vertices[t.v[2]];
  const float b1 = hit->b1, b2 = hit->b2, b0 = 1.0f - b1 - b2;
  const float3 p0 = vload3(0, v0.p), p1 = vload3(0, v1.p), p2 = vload3(0, v2.p);
  /* Interpolating the vertices is more accurate than org + t * dir far from the origin. */
  out->p = b0 * p0 + b1 * p1 + b2 * p2;
  out->ng = safe_normal(cross(p1 - p0, p2 - p0));
  const float3 n = b0 * vload3(0, v0.n) + b1 * vload3(0, v1.n) + b2 * vload3(0, v2.n);
  const float n_len = length(n);
  out->ns = (n_len > 1e-12f && isfinite(n_len)) ? n / n_len : out->ng;
  if (dot(out->ns, out->ng) < 0.0f) out->ns = -out->ns;
  out->uv = b0 * (float2)(v0.u, v0.v) + b1 * (float2)(v1.u, v1.v) + b2 * (float2)(v2.u, v2.v);
  hit_extra(s, &t, b1, b2, &out->uv1, &out->color);
  out->tangent = hit_tangent(s, &t, b1, b2);
  out->tex_lod = (float2)(-INFINITY);
  out->triangle = hit->triangle;
  out->material = t.material;
  out->front = dot(out->ng, dir) < 0.0f ? 1u : 0u;
  out->flipped = 0u;
}

static inline SurfaceHit surface_at(const SceneView* s, const Hit* hit, float3 org, float3 dir) {
  SurfaceHit sh;
  surface_at_to(s, hit, org, dir, &sh);
  return sh;
}

/* The texture footprint at sh of a ray cone `width` wide there (world units, across the
 * ray of direction dir): per UV set, log2 of its width in UV units (Akenine-Moller et al.
 * 2019, "Texture Level of Detail Strategies for Real-Time Ray Tracing", Ray Tracing Gems
 * ch. 20). On the surface the cone's section is an ellipse 1 / |cos| longer along the
 * slope; the level follows its area, a width of width / sqrt(|cos|). The UV scale is the
 * triangle's, sqrt(UV area / world area); a triangle without UV area gives -INFINITY. */
static inline float2 surface_texture_lod(const SceneView* s, const SurfaceHit* sh, float3 dir,
                                         float width) {
  const Triangle t = s->triangles[sh->triangle];
  const Vertex v0 = s->vertices[t.v[0]], v1 = s->vertices[t.v[1]], v2 = s->vertices[t.v[2]];
  const float3 p0 = vload3(0, v0.p);
  const float world2 = length(cross(vload3(0, v1.p) - p0, vload3(0, v2.p) - p0));
  const float cos_t = fmax(fabs(dot(sh->ng, dir)), 1e-4f);
  if (!(world2 > 0.0f) || !(width > 0.0f)) return (float2)(-INFINITY);
  const float base = log2(width) - 0.5f * log2(cos_t) - 0.5f * log2(world2);
  const float2 a0 = (float2)(v1.u - v0.u, v1.v - v0.v), b0 = (float2)(v2.u - v0.u, v2.v - v0.v);
  float2 lod;
  lod.x = base + 0.5f * log2(fabs(a0.x * b0.y - a0.y * b0.x));
  lod.y = -INFINITY;
  if (scene_has_vertex_extra(s)) {
    const float2 u0 = vload2(0, s->vertex_extra[t.v[0]].uv1);
    const float2 a1 = vload2(0, s->vertex_extra[t.v[1]].uv1) - u0, b1 = vload2(0, s->vertex_extra[t.v[2]].uv1) - u0;
    lod.y = base + 0.5f * log2(fabs(a1.x * b1.y - a1.y * b1.x));
  }
  return lod;
}

#endif
