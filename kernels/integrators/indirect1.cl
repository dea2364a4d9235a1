/* Entry points of the one-bounce indirect integrator (--integrator indirect1; the generators
 * in kernels/integrators/indirect/generators.cl):
 *   indirect1_areas   each leaf-order triangle's area, from which the host builds the
 *                     surface-area distribution of --indirect surface;
 *   indirect1_render  one work-item per pixel, samples_per_pass samples each: the light that
 *                     reaches the camera's first hit x after exactly one reflection. */
#include "integrators/stages/pixel_samples.cl"
#include "integrators/indirect/generators.cl"

__kernel void indirect1_areas(SCENE_KERNEL_ARGS u32 count, __global float* areas) {
  const u32 i = get_global_id(0);
  if (i >= count) return;
  const SceneView scene = SCENE_VIEW();
  areas[i] = triangle_area(&scene, i);
}

static inline float3 indirect1_radiance(const SceneView* s, __constant const RenderParams* p,
                                        __constant const IndirectParams* ip,
                                        __global const float* cdf,
                                        const Sampler* sampler, float3 org, float3 dir, u32* rays) {
  if (p->max_depth < 2u) return (float3)(0.0f); /* no path of one bounce after x */
  Hit hit;
  ++*rays;
  if (!intersect_closest(s, org, dir, INFINITY, &hit)) return (float3)(0.0f);
  SurfaceHit x = surface_shade(s, &hit, org, dir);
  bsdf_orient(&x, -dir);
  if (!bsdf_has_smooth_lobe(&x)) return (float3)(0.0f);
  if (ip->generator == INDIRECT_SOURCE) return indirect_source(s, sampler, &x, -dir, rays);
  if (ip->generator == INDIRECT_SURFACE) return indirect_surface(s, ip, cdf, sampler, &x, -dir, rays);
  return indirect_receiver(s, sampler, &x, -dir, rays);
}

__kernel void indirect1_render(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                               __constant const IndirectParams* indirect,
                               __global const float* area_cdf, __global float4* film_sum,
                               __global float4* film_sum_sq, __global u32* ray_counts) {
  const u32 pixel = get_global_id(0);
  if (pixel >= params->width * params->height) return;
  const SceneView scene = SCENE_VIEW();
  PixelSamples ps = pixel_samples_begin(params, pixel, film_sum, film_sum_sq);
  for (u32 i = 0; i < params->samples_per_pass; ++i) {
    float3 org, dir;
    const Sampler sampler = pixel_sample(params, &ps, i, &org, &dir);
    film_add(&ps.film,
             indirect1_radiance(&scene, params, indirect, area_cdf, &sampler, org, dir, &ps.rays));
  }
  pixel_samples_end(&ps, film_sum, film_sum_sq, ray_counts);
}
