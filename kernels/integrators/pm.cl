/* Entry point of classic photon mapping (kernels/integrators/photon/pm_radiance.cl): one
 * work-item per pixel, samples_per_pass samples each, over the global and caustic maps the
 * host built (host/integrators/photon_mapper.cpp) and, with --final-gather-cache, the
 * irradiance cache built from the global map (a cache with no records otherwise). Same film
 * layout as pt. */
#include "integrators/stages/pixel_samples.cl"
#include "integrators/photon/pm_radiance.cl"

__kernel void pm_render(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                        __constant const PmParams* pm,
                        __global const KdNode* global_nodes, __global const Photon* global_photons,
                        u32 global_count, __global const KdNode* caustic_nodes,
                        __global const Photon* caustic_photons, u32 caustic_count,
                        IC_IMAGE_ARGS, __global float4* film_sum, __global float4* film_sum_sq,
                        __global u32* ray_counts) {
  const u32 pixel = get_global_id(0);
  if (pixel >= params->width * params->height) return;
  const SceneView scene = SCENE_VIEW();
  const PhotonMap global_map = photon_map(global_nodes, global_photons, global_count, &pm->lookup);
  const PhotonMap caustic_map = photon_map(caustic_nodes, caustic_photons, caustic_count, &pm->lookup);

  const IcCache cache = ic_cache(ic, records, starts, entries);
  const int marked = ic->show_records && marks[pixel];

  PixelSamples ps = pixel_samples_begin(params, pixel, film_sum, film_sum_sq);
  IcCounts counts = {0u, 0u, 0u};
  for (u32 i = 0; i < params->samples_per_pass; ++i) {
    float3 org, dir;
    const Sampler sampler = pixel_sample(params, &ps, i, &org, &dir);
    const float3 L = pm_radiance(params, pm, &scene, &sampler, &global_map, &caustic_map, &cache, org,
                                 dir, &ps.rays, &counts);
    film_add(&ps.film, marked ? (float3)(1.0f, 0.0f, 0.0f) : L);
  }
  pixel_samples_end(&ps, film_sum, film_sum_sq, ray_counts);
  ic_store_counts(lookup_counts, pixel, &counts);
}
