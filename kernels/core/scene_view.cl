/* The scene as a kernel sees it: a private struct of __global pointers, built once at the
 * start of each kernel from its arguments (OpenCL 1.2 cannot pass pointer structs as
 * arguments, but a private one is fine). Every kernel takes the scene buffers first, as
 * SCENE_KERNEL_ARGS declares them, and builds its view with SCENE_VIEW(); the host binds
 * them in the same order in one place (SceneBuffers::bind). The list of buffers is
 * written once, in shared/scene_arrays.h. */
#ifndef CLPT_CORE_SCENE_VIEW_CL
#define CLPT_CORE_SCENE_VIEW_CL

#include "shared/scene_arrays.h"
#include "shared/scene_types.h"

#define SCENE_VIEW_FIELD(type, name, what) __global const type* name;
typedef struct SceneView {
  SCENE_ARRAYS(SCENE_VIEW_FIELD)
  u32 num_lights;
  u32 flags; /* info->flags (SceneFlags), kept private: the traversal tests SCENE_ALPHA */
} SceneView;
#undef SCENE_VIEW_FIELD

/* The scene arguments every kernel starts with, in SceneBuffers::bind order. The list ends
 * with a comma: `__kernel void k(SCENE_KERNEL_ARGS __constant const RenderParams* p)`. */
#define SCENE_KERNEL_ARG(type, name, what) __global const type* scene_##name,
#define SCENE_KERNEL_ARGS SCENE_ARRAYS(SCENE_KERNEL_ARG)

#define SCENE_VIEW_ARG(type, name, what) scene_##name,
#define SCENE_VIEW() scene_view(SCENE_ARRAYS(SCENE_VIEW_ARG) 0)

#define SCENE_VIEW_PARAM(type, name, what) __global const type* name,
#define SCENE_VIEW_SET(type, name, what) s.name = name;
static inline SceneView scene_view(SCENE_ARRAYS(SCENE_VIEW_PARAM) int end_of_list) {
  SceneView s;
  SCENE_ARRAYS(SCENE_VIEW_SET)
  s.num_lights = info ? info->num_lights : 0u; /* test kernels may pass no info */
  s.flags = info ? info->flags : 0u;
  return s;
}
#undef SCENE_VIEW_PARAM
#undef SCENE_VIEW_SET

static inline float3 vertex_position(const SceneView* s, u32 i) {
  return vload3(0, s->vertices[i].p);
}

#endif
