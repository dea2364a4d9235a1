/* Entry points of the irradiance cache (--integrator ic, host/integrators/irradiance_cache.h):
 *   ic_place          one work-item per point of a coarse-to-fine pixel grid: the camera ray
 *                     through the pixel's centre to its first non-delta vertex; a vertex no
 *                     record covers becomes a candidate record (appended);
 *   ic_record_rays    one work-item per hemisphere ray of the batch's records (path traced,
 *                     or reading the global photon map: IcParams.gather);
 *   ic_record_finish  one work-item per record of the batch: E, R and gradients;
 *   ic_render         one work-item per pixel, samples_per_pass samples: the image
 *                     (ic/ic_path.cl).
 * The placement and record kernels take a RenderParams of their own (the independent
 * sampler under a seed of the cache's), the image the render's. */
#include "integrators/stages/pixel_samples.cl"
#include "integrators/ic/records.cl"


#define IC_PLACE_MARGIN 0.7f

__kernel void ic_place(SCENE_KERNEL_ARGS __constant const RenderParams* params, IC_CACHE_ARGS,
                       __global IcRecord* candidates, volatile __global u32* count) {
  const u32 g = ic->grid_first + get_global_id(0);
  if (get_global_id(0) >= ic->capacity || g >= ic->grid_w * ic->grid_h) return;
  const SceneView scene = SCENE_VIEW();
  const IcCache cache = ic_cache(ic, records, starts, entries);
  const u32 x = min((g % ic->grid_w) * ic->step + ic->step / 2u, params->width - 1u);
  const u32 y = min((g / ic->grid_w) * ic->step + ic->step / 2u, params->height - 1u);
  const u32 pixel = y * params->width + x;
  /* Pixel centres; the last pass (jitter 1) a random point in each pixel, sample index 1,
   * where the image's jittered samples would find no record. */
  const Sampler sampler = sampler_init(params, pixel, ic->jitter);
  float3 org, dir;
  jittered_pixel_ray(params, &sampler, x, y,
                     ic->jitter ? sample_2d(&sampler, DIM_PIXEL) : (float2)(0.5f), &org, &dir);
  PathWalk w = walk_from_camera(params, org, dir, 0u, 0u);
  float3 L = (float3)(0.0f);
  float travelled = 0.0f;
  u32 rays = 0;
  if (!ic_first_vertex(params, &scene, &sampler, &w, &L, &travelled, &rays)) return;
  if (w.depth + 1u >= params->max_depth || is_black(bsdf_diffuse_factor(&w.sh, w.wo))) return;
  /* Covered with a margin: a centre just inside a record's bound leaves the rest of the
   * pixel outside it (the image's samples are jittered), and such points would be path
   * traced (10 % of the lookups at 32 x 32 without the margin). */
  if (ic_lookup_within(&cache, IC_PLACE_MARGIN * ic->error, w.sh.p, w.sh.ns, w.depth).weight > 0.0f)
    return;
  const u32 slot = atomic_inc(count);
  if (slot >= ic->capacity) return;
  __global IcRecord* c = &candidates[slot];
  vstore3(w.sh.p, 0, c->p);
  vstore3(w.sh.ns, 0, c->n);
  c->r = ic_footprint(ic, travelled);
  c->depth = w.depth;
  c->pixel = pixel;
  for (int k = 0; k < 9; ++k) c->rot[k] = c->trans[k] = 0.0f;
  vstore3((float3)(0.0f), 0, c->e);
  c->footprint = c->r;
  c->inv_r_sum = 0.0f;
  c->rays = 0u;
  c->pad = 0u;
}

__kernel void ic_record_rays(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                             __constant const IcParams* ic, __global const IcRecord* records,
                             __global float4* results, __global const KdNode* map_nodes,
                             __global const Photon* map_photons, u32 map_count) {
  const u32 g = get_global_id(0);
  const u32 per = ic->rays_theta * ic->rays_phi;
  if (g >= ic->batch * per) return;
  const SceneView scene = SCENE_VIEW();
  const u32 r = ic->first + g / per, q = g % per;
  /* A record's later batches draw the sample indices after its earlier rays'. */
  const Sampler sampler = sampler_init(params, r, records[r].rays + q);
  const PhotonMap map = photon_map(map_nodes, map_photons, map_count, &ic->photons);
  u32 rays = 0;
  results[g] = ic_record_ray(params, &scene, ic, &map, &records[r], q, &sampler, &rays);
}

__kernel void ic_record_finish(__constant const IcParams* ic, __global IcRecord* records,
                               __global const float4* results) {
  const u32 g = get_global_id(0);
  if (g >= ic->batch) return;
  ic_finish_record(ic, &records[ic->first + g], results + (size_t)g * ic->rays_theta * ic->rays_phi);
}

__kernel void ic_render(SCENE_KERNEL_ARGS __constant const RenderParams* params, IC_IMAGE_ARGS,
                        __global float4* film_sum, __global float4* film_sum_sq,
                        __global u32* ray_counts) {
  const u32 pixel = get_global_id(0);
  if (pixel >= params->width * params->height) return;
  const SceneView scene = SCENE_VIEW();
  const IcCache cache = ic_cache(ic, records, starts, entries);
  const int marked = ic->show_records && marks[pixel];

  PixelSamples ps = pixel_samples_begin(params, pixel, film_sum, film_sum_sq);
  IcCounts counts = {0u, 0u, 0u};
  for (u32 i = 0; i < params->samples_per_pass; ++i) {
    float3 org, dir;
    const Sampler sampler = pixel_sample(params, &ps, i, &org, &dir);
    const float3 L = ic_radiance(params, &scene, &cache, &sampler, org, dir, &ps.rays, &counts);
    film_add(&ps.film, marked ? (float3)(1.0f, 0.0f, 0.0f) : L);
  }
  pixel_samples_end(&ps, film_sum, film_sum_sq, ray_counts);
  ic_store_counts(lookup_counts, pixel, &counts);
}
