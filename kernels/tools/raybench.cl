/* Entry points of clpt-raybench (host/tools/raybench.cpp): each work-item traces one ray of a
 * fixed set through the scene's BVH (kernels/bvh/intersect.cl) and writes 1 where it hits:
 * the closest hit (as every camera and scattered ray of the integrators) or any hit (as their
 * shadow rays), with no shading, so the figure is traversal and triangle tests alone. */
#include "bvh/intersect.cl"

__kernel void raybench_closest(SCENE_KERNEL_ARGS __global const float4* origins,
                               __global const float4* directions, u32 count, __global u32* hits) {
  const u32 i = get_global_id(0);
  if (i >= count) return;
  const SceneView scene = SCENE_VIEW();
  Hit hit;
  hits[i] = intersect_closest(&scene, origins[i].xyz, directions[i].xyz, INFINITY, &hit) ? 1u : 0u;
}

__kernel void raybench_any(SCENE_KERNEL_ARGS __global const float4* origins,
                           __global const float4* directions, u32 count, __global u32* hits) {
  const u32 i = get_global_id(0);
  if (i >= count) return;
  const SceneView scene = SCENE_VIEW();
  hits[i] = intersect_any(&scene, origins[i].xyz, directions[i].xyz, INFINITY) ? 1u : 0u;
}
