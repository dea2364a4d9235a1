/* Entry points of vertex connection and merging (--integrator vcm,
 * kernels/integrators/vcm/vcm_path.cl). Per sample index (one pass, one merge radius), over
 * a tile of pixel indices [path_offset, path_offset + path_count):
 *   vcm_light        light_per_pixel light subpaths per pixel index: camera connections
 *                    splatted, the vertices of each stored in its own light_vertex_capacity
 *                    slots, light path j of pixel index i at path_count j + i (so the first
 *                    path_count paths are the ones the camera subpaths connect to);
 *   vcm_grid_count   one work-item per light path (light_paths of them): its stored
 *                    vertices counted into their grid buckets when merging, and with light
 *                    vertex caching (--bdpt-lvc) their slots put on the tile's list of stored
 *                    vertices; the host then sums the counts into bucket starts;
 *   vcm_grid_fill    one work-item per light path: its stored vertices placed in their
 *                    buckets' runs of the cell-sorted grid (spatial/hash_grid.cl) when merging.
 *                    (A work-item per slot, most of them empty and each found by a division,
 *                    cost more than the counting and placing themselves.)
 *   vcm_camera       one camera subpath per pixel: connections to its own light subpath,
 *                    merges with the whole tile's, added to the film (and the merged part to
 *                    merge_sum, for the picture of what merging contributes).
 * With per-pixel radii (VcmParams.pixel_radius) pixel_radii holds each pixel's (r, N) for the
 * pass: vcm_light weights its camera connections with the eta of the pixel each lands in and
 * stores each vertex's EtaSlopes in `slopes`; vcm_camera merges with its pixel's radius,
 * weights with its eta and writes the pixel's (r, N) for the next pass to next_pixel_radii
 * (the host swaps the two after the pass, so every tile of a pass reads the same radii).
 * Ray counts, strategy shadow rays (connection_counts), stored light vertices and merges are
 * counted per pixel index for --stats. */
#include "film/film.cl"
#include "film/splat_filter.cl"
#include "integrators/vcm/vcm_path.cl"

__kernel void vcm_light(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                        __constant const VcmParams* vcm, u32 path_offset,
                        u32 path_count, __global PathVertex* vertices, __global float2* slopes,
                        __global u32* vertex_counts, __global const float2* pixel_radii,
                        __global float4* splat, __global u32* ray_counts,
                        __global u32* connection_counts, __global u32* stored_counts) {
  const u32 i = get_global_id(0);
  if (i >= path_count) return;
  const u32 path = path_offset + i;
  const SceneView scene = SCENE_VIEW();
  u32 rays = 0, connections = 0, stored = 0;
  /* The pixel's j-th light subpath of the pass draws from sample index light_sample + j:
   * numbers of its own (in the light subpaths' stream of dimensions, DIM_BDPT_LIGHT_STREAM,
   * apart from the camera subpaths'), consecutive over the passes (a sample sequence's
   * strides are not its own distribution: Sobol's first dimension at stride 4 stays in a
   * quarter of [0, 1)), and with one subpath per pixel the pass's own sample index. */
  for (u32 j = 0u; j < vcm->light_per_pixel; ++j) {
    const Sampler sampler = sampler_init(params, path, vcm->light_sample + j);
    const u32 l = j * path_count + i;
    const size_t first = (size_t)l * vcm->light_vertex_capacity;
    const u32 n = vcm_light_path(params, vcm, &scene, &sampler, vertices + first, slopes + first,
                                 pixel_radii, splat, &rays, &connections);
    vertex_counts[l] = n;
    stored += n;
  }
  ray_counts[path] += rays;
  connection_counts[path] += connections;
  stored_counts[path] += stored;
}

__kernel void vcm_grid_count(__constant const VcmParams* vcm, u32 path_count,
                             __global const PathVertex* vertices, __global const u32* vertex_counts,
                             volatile __global u32* counts, __global u32* cache,
                             volatile __global u32* cache_count) {
  const u32 i = get_global_id(0);
  if (i >= path_count) return;
  const bool merges = vcm_mode_merges(vcm->mode);
  const u32 first = i * vcm->light_vertex_capacity;
  for (u32 slot = first, end = first + vertex_counts[i]; slot < end; ++slot) {
    if (merges) grid_count_point(vload3(0, vertices[slot].p), vcm->inv_cell, vcm->mask, counts);
    if (vcm->lvc) cache[atomic_inc(cache_count)] = slot;
  }
}

__kernel void vcm_grid_fill(__constant const VcmParams* vcm, u32 path_count,
                            __global const PathVertex* vertices, __global const u32* vertex_counts,
                            volatile __global u32* cursor, __global GridPoint* points) {
  const u32 i = get_global_id(0);
  if (i >= path_count) return;
  const u32 first = i * vcm->light_vertex_capacity;
  for (u32 slot = first, end = first + vertex_counts[i]; slot < end; ++slot) {
    __global const PathVertex* y = vertices + slot;
    grid_fill_point(vload3(0, y->p), vload3(0, y->ng), y->depth, slot, vcm->inv_cell, vcm->mask,
                    cursor, points);
  }
}

__kernel void vcm_camera(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                         __constant const VcmParams* vcm, u32 sample_index, u32 path_offset,
                         u32 path_count, __global const PathVertex* vertices,
                         __global const float2* slopes,
                         __global const u32* vertex_counts, __global const u32* cache,
                         __global const u32* cache_count, __global const u32* starts,
                         __global const GridPoint* points, __global const float2* pixel_radii,
                         __global float2* next_pixel_radii, __global float4* film_sum,
                         __global float4* film_sum_sq, __global float4* splat, __global float4* merge_sum,
                         __global u32* ray_counts, __global u32* connection_counts,
                         __global u32* merge_counts) {
  const u32 i = get_global_id(0);
  if (i >= path_count) return;
  const u32 pixel = path_offset + i;
  const SceneView scene = SCENE_VIEW();
  const Sampler sampler = sampler_init(params, pixel, sample_index);
  u32 rays = 0, connections = 0, merges = 0, found = 0;
  FilmPixel film = film_load(film_sum, film_sum_sq, pixel);
  const size_t first = (size_t)i * vcm->light_vertex_capacity;
  const float2 rn = vcm->pixel_radius ? pixel_radii[pixel] : (float2)(vcm->radius, 0.0f);
  const MergeSetting g = vcm_merge_setting(params, vcm, rn.x);
  float3 merged;
  const float3 L = vcm_camera_path(
      params, vcm, &g, &scene, &sampler, pixel % params->width, pixel / params->width,
      vertices + first, slopes + first, vcm_mode_connects(vcm->mode) ? vertex_counts[i] : 0u,
      vertices, slopes, cache, vcm->lvc ? cache_count[0] : 0u, starts, points, &merged, &found,
      &rays, &connections, &merges);
  if (vcm->pixel_radius) next_pixel_radii[pixel] = vcm_radius_update(vcm, rn, found);
  if (!film_camera_splat(params, splat, &sampler, pixel, L)) film_add(&film, L);
  film_store(film_sum, film_sum_sq, pixel, &film);
  if (is_finite3(merged)) merge_sum[pixel].xyz += merged;
  ray_counts[pixel] += rays;
  connection_counts[pixel] += connections;
  merge_counts[pixel] += merges;
}
