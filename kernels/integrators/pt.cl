/* Entry point of the path tracer: one work-item per pixel, samples_per_pass samples each. */
#include "integrators/stages/pixel_samples.cl"
#include "integrators/estimators/path_trace.cl"

__kernel void pt_render(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                        __global float4* film_sum, __global float4* film_sum_sq,
                        __global u32* ray_counts) {
  const u32 pixel = get_global_id(0);
  if (pixel >= params->width * params->height) return;
  const SceneView scene = SCENE_VIEW();

  PixelSamples ps = pixel_samples_begin(params, pixel, film_sum, film_sum_sq);
  for (u32 i = 0; i < params->samples_per_pass; ++i) {
    float3 org, dir;
    const Sampler sampler = pixel_sample(params, &ps, i, &org, &dir);
    film_add(&ps.film, pt_radiance(&scene, params, &sampler, org, dir, 0u, &ps.rays));
  }
  pixel_samples_end(&ps, film_sum, film_sum_sq, ray_counts);
}
