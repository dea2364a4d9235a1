/* Kernels for tests/light_tracer_test.cpp: the splat film's float atomics and the camera's
 * importance (kernels/film/splat.cl, kernels/camera/camera_importance.cl). */
#include "camera/camera_importance.cl"
#include "film/splat.cl"

/* Work-item i adds values[i] to channel i % 3 of pixel cells[i]. */
__kernel void splat_add(__global float4* splat, __global const u32* cells,
                        __global const float* values, u32 n) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  float3 L = (float3)(0.0f);
  if (i % 3u == 0u) L.x = values[i];
  else if (i % 3u == 1u) L.y = values[i];
  else L.z = values[i];
  film_splat(splat, cells[i], L);
}

/* For each world point and lens sample: the connection's raster position, validity and
 * distance, and We, pdf_w, weight and the cosine at the camera. */
__kernel void camera_connections(__constant const CameraData* cam, u32 width, u32 height,
                                 __global const float4* points, __global const float2* lens,
                                 u32 n, __global float4* raster_valid, __global float4* values) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  const CameraConnection c = camera_connect(cam, width, height, points[i].xyz, lens[i]);
  raster_valid[i] = (float4)(c.raster, (float)c.valid, c.dist);
  values[i] = (float4)(c.We, c.pdf_w, c.weight, dot(c.wi, -vload3(0, cam->forward)));
}

/* The camera ray through film point film[i].xy with lens sample film[i].zw. */
__kernel void camera_rays_lt(__constant const CameraData* cam, __global const float4* film,
                             u32 n, __global float4* org_out, __global float4* dir_out) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  float3 org, dir;
  camera_ray(cam, film[i].xy, film[i].zw, &org, &dir);
  org_out[i] = (float4)(org, 0.0f);
  dir_out[i] = (float4)(dir, 0.0f);
}
