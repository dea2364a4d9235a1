/* Entry point of photon emission (kernels/integrators/photon/photon_trace.cl): one photon
 * path per work-item, paths [first_path, first_path + path_count) of a pass that emits
 * `inv_paths`^-1 paths in all. Photons go to photons[offset + slot] for the slots
 * [0, capacity) handed out by the counter count[0]; count[0] ends as the number the paths
 * made, kept or not. `store`: PHOTON_STORE_* mask. The sampler key is the path index, the
 * sample index params->sample_offset (one per photon pass). */
#include "integrators/photon/photon_trace.cl"

__kernel void photon_emit(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                          u32 first_path, u32 path_count, float inv_paths, u32 store,
                          __global Photon* photons, u32 offset, volatile __global u32* count,
                          u32 capacity, volatile __global u32* ray_count) {
  const u32 i = get_global_id(0);
  if (i >= path_count) return;
  const SceneView scene = SCENE_VIEW();
  const Sampler sampler = sampler_init(params, first_path + i, params->sample_offset);
  u32 rays = 0;
  photon_trace(params, &scene, &sampler, inv_paths, store, photons + offset, count, capacity,
               &rays);
  atomic_add(ray_count, rays);
}
