/* The scene as a kernel sees it: a private struct of __global pointers, built once at the
 * start of each kernel from its arguments (OpenCL 1.2 cannot pass pointer structs as
 * arguments, but a private one is fine). Every kernel takes the scene buffers first, as
 * SCENE_KERNEL_ARGS declares them, and builds its view with SCENE_VIEW(); the host binds
 * them in the same order in one place (SceneBuffers::bind). */
#ifndef CLPT_CORE_SCENE_VIEW_CL
#define CLPT_CORE_SCENE_VIEW_CL

#include "shared/scene_types.h"

typedef struct SceneView {
  __global const BvhNode* nodes;
  __global const Triangle* triangles;      /* leaf order */
  __global const Vertex* vertices;
  __global const VertexExtra* vertex_extra; /* valid when info->flags & SCENE_VERTEX_EXTRA */
  __global const Material* materials;
  __global const Texture* textures;
  __global const u32* texels;              /* RGBA8 texels of all textures */
  __global const Light* lights;
  __global const int* triangle_light;      /* per triangle: index into lights, or -1 */
  __global const float4* env_texels;       /* environment map, row-major, top row first */
  __global const float* env_cdf;           /* environment sampling distribution */
  __global const SceneInfo* info;
  u32 num_lights;
  u32 flags; /* info->flags (SceneFlags), kept private: the traversal tests SCENE_ALPHA */
} SceneView;

/* The scene arguments every kernel starts with, in SceneBuffers::bind order. */
#define SCENE_KERNEL_ARGS                                                                    \
  __global const BvhNode *scene_nodes, __global const Triangle *scene_triangles,             \
      __global const Vertex *scene_vertices, __global const VertexExtra *scene_vertex_extra, \
      __global const Material *scene_materials, __global const Texture *scene_textures,      \
      __global const u32 *scene_texels, __global const Light *scene_lights,                  \
      __global const int *scene_triangle_light, __global const float4 *scene_env_texels,     \
      __global const float *scene_env_cdf, __global const SceneInfo *scene_info

#define SCENE_VIEW()                                                                         \
  scene_view(scene_nodes, scene_triangles, scene_vertices, scene_vertex_extra,               \
             scene_materials, scene_textures, scene_texels, scene_lights,                    \
             scene_triangle_light, scene_env_texels, scene_env_cdf, scene_info)

inline SceneView scene_view(__global const BvhNode* nodes, __global const Triangle* triangles,
                            __global const Vertex* vertices,
                            __global const VertexExtra* vertex_extra,
                            __global const Material* materials, __global const Texture* textures,
                            __global const u32* texels, __global const Light* lights,
                            __global const int* triangle_light, __global const float4* env_texels,
                            __global const float* env_cdf, __global const SceneInfo* info) {
  SceneView s;
  s.nodes = nodes;
  s.triangles = triangles;
  s.vertices = vertices;
  s.vertex_extra = vertex_extra;
  s.materials = materials;
  s.textures = textures;
  s.texels = texels;
  s.lights = lights;
  s.triangle_light = triangle_light;
  s.env_texels = env_texels;
  s.env_cdf = env_cdf;
  s.info = info;
  s.num_lights = info ? info->num_lights : 0u; /* test kernels may pass no info */
  s.flags = info ? info->flags : 0u;
  return s;
}

inline float3 vertex_position(const SceneView* s, u32 i) {
  return vload3(0, s->vertices[i].p);
}

#endif
