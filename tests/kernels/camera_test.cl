/* Camera rays for tests/camera_test.cpp: for each (film, lens) pair, the ray's origin and
 * direction. */
#include "camera/camera.cl"

__kernel void camera_rays(__constant const CameraData* cam, __global const float4* uv, u32 n,
                          __global float4* org_out, __global float4* dir_out) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  float3 org, dir;
  const float4 q = uv[i];
  camera_ray(cam, (float2)(q.x, q.y), (float2)(q.z, q.w), &org, &dir);
  org_out[i] = (float4)(org, 0.0f);
  dir_out[i] = (float4)(dir, 0.0f);
}
