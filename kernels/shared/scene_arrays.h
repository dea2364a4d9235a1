/* The scene's device buffers, written once, in kernel argument order (as Cycles'
 * kernel/data_arrays.h): X(device element type, name, what it holds). The names are
 * FlatScene's fields (host/render/scene_buffers.h). Expanded by kernels/core/scene_view.cl
 * (SceneView's pointers, SCENE_KERNEL_ARGS, SCENE_VIEW) and by host/render/scene_buffers.*
 * (the buffers, their upload, SceneBuffers::bind, device_bytes). A new scene array is one
 * line here and one FlatScene field. */
#ifndef CLPT_SHARED_SCENE_ARRAYS_H
#define CLPT_SHARED_SCENE_ARRAYS_H

#define SCENE_ARRAYS(X)                                                          \
  X(BvhNode4, nodes, "BVH node")                 /* 4-wide */                    \
  X(Triangle, triangles, "triangle")             /* leaf order */                \
  X(Vertex, vertices, "vertex")                                                  \
  X(float, tri_lanes, "triangle lanes")          /* CPU devices: leaves' positions as float4 lanes */ \
  X(VertexExtra, vertex_extra, "vertex attribute") /* valid with SCENE_VERTEX_EXTRA */ \
  X(Material, materials, "material")                                             \
  X(Texture, textures, "texture")                                                \
  X(u32, texels, "texel")                        /* RGBA8 texels of all textures */ \
  X(Light, lights, "light")                                                      \
  X(int, triangle_light, "triangle light")       /* per triangle: light index or -1 */ \
  X(float4, env_texels, "environment map")       /* row-major, top row first */  \
  X(float, env_cdf, "environment distribution")                                  \
  X(SceneInfo, info, "scene info")               /* one element */

#endif
