/* Vertex attributes at a point of a triangle (barycentrics b1, b2 of v[1], v[2]): the first
 * UV set from the vertices, and the optional attributes (TEXCOORD_1, COLOR_0, TANGENT) from
 * the VertexExtra buffer when the scene has one (info->flags & SCENE_VERTEX_EXTRA). */
#ifndef CLPT_CORE_VERTEX_ATTRIBUTES_CL
#define CLPT_CORE_VERTEX_ATTRIBUTES_CL

#include "core/scene_view.cl"

static inline bool scene_has_vertex_extra(const SceneView* s) {
  return s->info != 0 && (s->info->flags & SCENE_VERTEX_EXTRA) != 0u;
}

static inline float2 hit_uv0(const SceneView* s, const Triangle* t, float b1, float b2) {
  __global const Vertex* v0 = &s->vertices[t->v[0]];
  __global const Vertex* v1 = &s->vertices[t->v[1]];
  __global const Vertex* v2 = &s->vertices[t->v[2]];
  const float b0 = 1.0f - b1 - b2;
  return b0 * (float2)(v0->u, v0->v) + b1 * (float2)(v1->u, v1->v) + b2 * (float2)(v2->u, v2->v);
}

/* TEXCOORD_1 and COLOR_0; (0, 0) and (1, 1, 1, 1) without a VertexExtra buffer. */
static inline void hit_extra(const SceneView* s, const Triangle* t, float b1, float b2, float2* uv1,
                             float4* color) {
  if (!scene_has_vertex_extra(s)) {
    *uv1 = (float2)(0.0f);
    *color = (float4)(1.0f);
    return;
  }
  __global const VertexExtra* e0 = &s->vertex_extra[t->v[0]];
  __global const VertexExtra* e1 = &s->vertex_extra[t->v[1]];
  __global const VertexExtra* e2 = &s->vertex_extra[t->v[2]];
  const float b0 = 1.0f - b1 - b2;
  *uv1 = b0 * vload2(0, e0->uv1) + b1 * vload2(0, e1->uv1) + b2 * vload2(0, e2->uv1);
  *color = b0 * vload4(0, e0->color) + b1 * vload4(0, e1->color) + b2 * vload4(0, e2->color);
}

/* Interpolated tangent (xyz, not normalised) and bitangent sign (w, +-1); zero when the
 * scene or the vertices have none. */
static inline float4 hit_tangent(const SceneView* s, const Triangle* t, float b1, float b2) {
  if (!scene_has_vertex_extra(s)) return (float4)(0.0f);
  const float4 t0 = vload4(0, s->vertex_extra[t->v[0]].tangent);
  const float4 t1 = vload4(0, s->vertex_extra[t->v[1]].tangent);
  const float4 t2 = vload4(0, s->vertex_extra[t->v[2]].tangent);
  const float b0 = 1.0f - b1 - b2;
  const float3 xyz = b0 * t0.xyz + b1 * t1.xyz + b2 * t2.xyz;
  const float w = b0 * t0.w + b1 * t1.w + b2 * t2.w;
  return (float4)(xyz, w < 0.0f ? -1.0f : 1.0f);
}

#endif
