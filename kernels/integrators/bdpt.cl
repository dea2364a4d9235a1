/* Entry points of bidirectional path tracing (--integrator bdpt). Per sample index, over a
 * range of pixels [path_offset, path_offset + path_count) (the host tiles the image so the
 * light vertex buffer stays within its memory budget):
 *   bdpt_light   one light subpath per pixel index: t = 1 strategies splatted, connectable
 *                vertices stored (kernels/integrators/estimators/bdpt/light_path.cl);
 *   bdpt_camera  one camera subpath per pixel, joined with the light subpath of the same
 *                index (kernels/integrators/estimators/bdpt/camera_path.cl), added to the film.
 * Both use the sampler key (pixel, sample index), in disjoint dimension streams. Per pixel
 * index they add the rays they trace to ray_counts and the shadow rays of strategies
 * (connections: s = 1, t = 1 and inner ones) to connection_counts. */
#include "integrators/estimators/bdpt/camera_path.cl"
#include "integrators/estimators/bdpt/light_path.cl"
#include "film/film.cl"
#include "film/splat_filter.cl"

__kernel void bdpt_light(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                         __constant const BdptParams* bdpt, u32 sample_index,
                         u32 path_offset, u32 path_count, __global PathVertex* vertices,
                         __global u32* vertex_counts, volatile __global u32* pool_count,
                         __global float4* splat,
                         __global u32* ray_counts, __global u32* connection_counts) {
  const u32 i = get_global_id(0);
  if (i >= path_count) return;
  const u32 path = path_offset + i;
  const SceneView scene = SCENE_VIEW();
  const Sampler sampler = sampler_init(params, path, sample_index);
  u32 rays = 0, connections = 0;
  vertex_counts[i] = bdpt_light_path(params, bdpt, &scene, &sampler,
                                     vertices + (size_t)i * bdpt->light_vertex_capacity, vertices,
                                     pool_count, splat, &rays, &connections);
  ray_counts[path] += rays;
  connection_counts[path] += connections;
}

__kernel void bdpt_camera(SCENE_KERNEL_ARGS __constant const RenderParams* params,
                          __constant const BdptParams* bdpt, u32 sample_index,
                          u32 path_offset, u32 path_count, __global const PathVertex* vertices,
                          __global const u32* vertex_counts, __global const u32* pool_count,
                          __global float4* film_sum,
                          __global float4* film_sum_sq, __global float4* splat, __global u32* ray_counts,
                          __global u32* connection_counts) {
  const u32 i = get_global_id(0);
  if (i >= path_count) return;
  const u32 pixel = path_offset + i;
  const SceneView scene = SCENE_VIEW();
  const Sampler sampler = sampler_init(params, pixel, sample_index);
  u32 rays = 0, connections = 0;
  FilmPixel film = film_load(film_sum, film_sum_sq, pixel);
  /* With light vertex caching the whole tile's cache, else this pixel's own light subpath. */
  const bool lvc = bdpt->lvc != 0u;
  const float3 L = bdpt_camera_path(params, bdpt, &scene, &sampler, pixel % params->width,
                                   pixel / params->width,
                                   lvc ? vertices : vertices + (size_t)i * bdpt->light_vertex_capacity,
                                   lvc ? pool_count[0] : vertex_counts[i], path_count, &rays,
                                   &connections);
  if (!film_camera_splat(params, splat, &sampler, pixel, L)) film_add(&film, L);
  film_store(film_sum, film_sum_sq, pixel, &film);
  ray_counts[pixel] += rays;
  connection_counts[pixel] += connections;
}
