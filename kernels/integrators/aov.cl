/* First-hit AOVs (--aov): for each pixel, the camera rays of its first AOV_MAX_SAMPLES samples
 * (the same sampler keys, film positions and lens points as the image's samples) to their first
 * hit, summed into AovSums (kernels/shared/aov_types.h):
 *   albedo    the surface's reflectance colour as Intel Open Image Denoise takes it: the base
 *             colour of diffuse and metallic surfaces, 1 for the transmitted share of a
 *             dielectric (glass shows what is behind it, which the albedo cannot); textures,
 *             vertex colours and KHR_materials_diffuse_transmission's colour included,
 *   normal    the shading normal (normal maps included) turned to face the camera, world space,
 *   position  the world-space hit point, depth its distance from the ray's origin,
 *   material  the material index of the pixel's first sample.
 * Misses add nothing but the sample count (albedo and normal average to 0 there; position and
 * depth average over the hits). */
#include "bsdf/bsdf.cl"
#include "bvh/intersect.cl"
#include "integrators/stages/pixel_samples.cl"
#include "material/material.cl"
#include "shared/aov_types.h"

static inline float3 aov_albedo(const BsdfParams* b) {
  const float3 dielectric = mix(b->base_color, (float3)(1.0f), b->transmission);
  return mix(dielectric, b->base_color, b->metallic);
}

__kernel void aov_render(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                         __global AovSums* aov) {
  const u32 pixel = get_global_id(0);
  if (pixel >= params->width * params->height) return;
  const u32 first = params->sample_offset;
  if (first >= AOV_MAX_SAMPLES) return;
  const u32 count = min(params->samples_per_pass, AOV_MAX_SAMPLES - first);
  const SceneView scene = SCENE_VIEW();
  PixelSamples ps;
  ps.pixel = pixel;
  ps.x = pixel % params->width;
  ps.y = pixel / params->width;

  AovSums sums = aov[pixel];
  float3 albedo = vload3(0, sums.albedo), normal = vload3(0, sums.normal), position = vload3(0, sums.position);
  for (u32 i = 0; i < count; ++i) {
    float3 org, dir;
    pixel_sample(params, &ps, i, &org, &dir);
    ++sums.samples;
    Hit hit;
    const bool hit_any = intersect_closest(&scene, org, dir, INFINITY, &hit);
    if (first + i == 0u) sums.material = AOV_NO_MATERIAL;
    if (!hit_any) continue;
    float cone_width, cone_spread;
    camera_pixel_cone(params, &cone_width, &cone_spread);
    SurfaceHit sh = surface_shade_cone(&scene, &hit, org, dir, cone_width + cone_spread * hit.t);
    bsdf_orient(&sh, -dir);
    ++sums.hits;
    albedo += aov_albedo(&sh.bsdf);
    normal += sh.ns;
    position += sh.p;
    sums.depth += distance(org, sh.p);
    if (first + i == 0u) sums.material = sh.material;
  }
  vstore3(albedo, 0, sums.albedo);
  vstore3(normal, 0, sums.normal);
  vstore3(position, 0, sums.position);
  aov[pixel] = sums;
}
