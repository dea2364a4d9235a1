/* camera/pixel_filter.cl for tests/pixel_filter_test.cpp: the film jitter of each u. */
#include "camera/pixel_filter.cl"

__kernel void filter_jitter(u32 filter, float radius, __global const float2* u, __global float2* out, u32 n) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  out[i] = pixel_filter_jitter(filter, radius, u[i]);
}
