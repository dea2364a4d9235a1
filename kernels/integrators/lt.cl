/* Entry point of the light tracer: one work-item per "virtual pixel" (an index in
 * [0, width * height) that keys the sampler, not a place on the film), samples_per_pass
 * light paths each, so a pass traces samples_per_pass * width * height light paths and
 * --spp keeps meaning paths per pixel on average. Contributions land anywhere on the film
 * (film/splat.cl); ray counts stay with the work-item's virtual pixel. */
#include "integrators/lt/light_trace.cl"

__kernel void lt_render(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                        __global float4* splat, __global u32* ray_counts) {
  const u32 path = get_global_id(0);
  if (path >= params->width * params->height) return;
  const SceneView scene = SCENE_VIEW();
  u32 rays = 0;
  for (u32 i = 0; i < params->samples_per_pass; ++i) {
    const Sampler sampler = sampler_init(params, path, params->sample_offset + i);
    lt_trace(params, &scene, &sampler, splat, &rays);
  }
  ray_counts[path] += rays;
}
