/* The scene as a kernel sees it: a private struct of __global pointers, built once at the
 * start of each kernel from its arguments (OpenCL 1.2 cannot pass pointer structs as
 * arguments, but a private one is fine). Every kernel takes the scene buffers in the
 * order of scene_view(); the host binds them in that order in one place
 * (SceneBuffers::bind). */
#ifndef CLPT_CORE_SCENE_VIEW_CL
#define CLPT_CORE_SCENE_VIEW_CL

#include "shared/scene_types.h"

typedef struct SceneView {
  __global const BvhNode* nodes;
  __global const Triangle* triangles; /* leaf order */
  __global const Vertex* vertices;
  __global const Material* materials;
  __global const Emitter* emitters;
  __global const int* triangle_emitter; /* per triangle: index into emitters, or -1 */
  u32 num_emitters;
} SceneView;

inline SceneView scene_view(__global const BvhNode* nodes, __global const Triangle* triangles,
                            __global const Vertex* vertices, __global const Material* materials,
                            __global const Emitter* emitters,
                            __global const int* triangle_emitter, u32 num_emitters) {
  SceneView s;
  s.nodes = nodes;
  s.triangles = triangles;
  s.vertices = vertices;
  s.materials = materials;
  s.emitters = emitters;
  s.triangle_emitter = triangle_emitter;
  s.num_emitters = num_emitters;
  return s;
}

inline float3 vertex_position(const SceneView* s, u32 i) {
  return vload3(0, s->vertices[i].p);
}

#endif
