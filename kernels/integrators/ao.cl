/* Ambient occlusion, for quick looks: at the first hit, one cosine-distributed ray per
 * sample; the pixel value is the fraction of them that travel AoParams.radius (--ao-radius) unoccluded, an
 * estimate of (1/pi) * integral of V(x, w) cos(theta) dw over the hemisphere. Emitters are
 * shaded like any other surface. Camera rays that hit nothing give 0 (so objects stand out
 * against the background); occlusion rays that hit nothing count as unoccluded. */
#include "bsdf/bsdf.cl"
#include "bvh/intersect.cl"
#include "core/ray.cl"
#include "integrators/stages/pixel_samples.cl"
#include "shared/ao_types.h"
#include "sampler/sampler.cl"

static inline float ao_sample(const SceneView* s, __constant const AoParams* ao,
                              const Sampler* sampler,
                              float3 org, float3 dir, u32* rays) {
  Hit hit;
  ++*rays;
  if (!intersect_closest(s, org, dir, INFINITY, &hit)) return 0.0f;
  SurfaceHit sh = surface_at(s, &hit, org, dir);
  bsdf_orient(&sh, -dir);
  const float3 wi = to_world(warp_cosine_hemisphere(sample_2d(sampler, bounce_dim(0u, DIM_BSDF_DIR))), sh.ns);
  if (dot(wi, sh.ng) <= 0.0f) return 0.0f; /* below the surface: blocked by it */
  ++*rays;
  return intersect_any(s, offset_ray_origin(sh.p, sh.ng), wi, ao->radius) ? 0.0f : 1.0f;
}

__kernel void ao_render(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                        __constant const AoParams* ao,
                        __global float4* film_sum, __global float4* film_sum_sq,
                        __global u32* ray_counts) {
  const u32 pixel = get_global_id(0);
  if (pixel >= params->width * params->height) return;
  const SceneView scene = SCENE_VIEW();
  PixelSamples ps = pixel_samples_begin(params, pixel, film_sum, film_sum_sq);
  for (u32 i = 0; i < params->samples_per_pass; ++i) {
    float3 org, dir;
    const Sampler sampler = pixel_sample(params, &ps, i, &org, &dir);
    film_add(&ps.film, (float3)(ao_sample(&scene, ao, &sampler, org, dir, &ps.rays)));
  }
  pixel_samples_end(&ps, film_sum, film_sum_sq, ray_counts);
}
