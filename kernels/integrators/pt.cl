/* Entry point of the path tracer: one work-item per pixel, samples_per_pass samples each. */
#include "camera/pixel_ray.cl"
#include "film/film.cl"
#include "integrators/path_trace.cl"

__kernel void pt_render(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                        __global float4* film_sum, __global float4* film_sum_sq,
                        __global u32* ray_counts) {
  const u32 pixel = get_global_id(0);
  if (pixel >= params->width * params->height) return;
  const SceneView scene = SCENE_VIEW();
  const u32 x = pixel % params->width, y = pixel / params->width;

  FilmPixel film = film_load(film_sum, film_sum_sq, pixel);
  u32 rays = 0;
  for (u32 i = 0; i < params->samples_per_pass; ++i) {
    const Sampler sampler = sampler_init(params, pixel, params->sample_offset + i);
    float3 org, dir;
    pixel_ray(params, &sampler, x, y, &org, &dir);
    film_add(&film, pt_radiance(&scene, params, &sampler, org, dir, &rays));
  }
  film_store(film_sum, film_sum_sq, pixel, &film);
  ray_counts[pixel] += rays;
}
