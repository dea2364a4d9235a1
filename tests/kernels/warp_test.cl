/* Thin wrappers around core/warp.cl for tests/warp_test.cpp.
 * Points go out as float4: directions as (x, y, z, pdf), planar points as (x, y, 0, pdf),
 * pdf being the warp's own pdf function at the point. `param` is cos_theta_max for the
 * cone and unused otherwise. */
#include "core/warp.cl"

#include "kernels/warp_ids.h"

inline float warp_pdf(int warp, float3 p, float param) {
  switch (warp) {
    case WARP_UNIFORM_HEMISPHERE: return warp_uniform_hemisphere_pdf(p.z);
    case WARP_COSINE_HEMISPHERE: return warp_cosine_hemisphere_pdf(p.z);
    case WARP_UNIFORM_SPHERE: return warp_uniform_sphere_pdf();
    case WARP_UNIFORM_CONE: return warp_uniform_cone_pdf(p.z, param);
    case WARP_CONCENTRIC_DISK: return warp_concentric_disk_pdf(p.xy);
    case WARP_UNIFORM_DISK: return warp_uniform_disk_pdf(p.xy);
    case WARP_UNIFORM_TRIANGLE: return warp_uniform_triangle_pdf(p.xy);
    default: return NAN;
  }
}

inline float3 warp_point(int warp, float2 u, float param) {
  switch (warp) {
    case WARP_UNIFORM_HEMISPHERE: return warp_uniform_hemisphere(u);
    case WARP_COSINE_HEMISPHERE: return warp_cosine_hemisphere(u);
    case WARP_UNIFORM_SPHERE: return warp_uniform_sphere(u);
    case WARP_UNIFORM_CONE: return warp_uniform_cone(u, param);
    case WARP_CONCENTRIC_DISK: return (float3)(warp_concentric_disk(u), 0.0f);
    case WARP_UNIFORM_DISK: return (float3)(warp_uniform_disk(u), 0.0f);
    case WARP_UNIFORM_TRIANGLE: return (float3)(warp_uniform_triangle(u), 0.0f);
    default: return (float3)(NAN);
  }
}

inline float2 warp_invert(int warp, float3 p, float param) {
  switch (warp) {
    case WARP_UNIFORM_HEMISPHERE: return warp_uniform_hemisphere_invert(p);
    case WARP_COSINE_HEMISPHERE: return warp_cosine_hemisphere_invert(p);
    case WARP_UNIFORM_SPHERE: return warp_uniform_sphere_invert(p);
    case WARP_UNIFORM_CONE: return warp_uniform_cone_invert(p, param);
    case WARP_CONCENTRIC_DISK: return warp_concentric_disk_invert(p.xy);
    case WARP_UNIFORM_DISK: return warp_uniform_disk_invert(p.xy);
    case WARP_UNIFORM_TRIANGLE: return warp_uniform_triangle_invert(p.xy);
    default: return (float2)(NAN);
  }
}

/* The test's own random numbers, independent of the renderer's sampler: SplitMix64
 * (Steele et al. 2014) at position i of the stream `seed`, 23 bits per coordinate, as
 * (k + 1/2) / 2^23: in the open square (0, 1)^2, so the measure-zero rim where a warp's pdf
 * is 0 (u.x = 0 of the cosine hemisphere is the horizon) is never hit. */
inline float2 test_random_2d(uint seed, uint i) {
  ulong z = ((ulong)seed << 32) + ((ulong)i + 1ul) * 0x9e3779b97f4a7c15ul;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ul;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebul;
  z ^= z >> 31;
  const float scale = 0x1.0p-23f;
  return (float2)(((float)(uint)(z >> 41) + 0.5f) * scale,
                  ((float)((uint)z >> 9) + 0.5f) * scale);
}

__kernel void warp_sample_random(int warp, float param, uint seed, __global float4* out,
                                 uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const float3 p = warp_point(warp, test_random_2d(seed, i), param);
  out[i] = (float4)(p, warp_pdf(warp, p, param));
}

__kernel void warp_sample_at(int warp, float param, __global const float2* u,
                             __global float4* out, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const float3 p = warp_point(warp, u[i], param);
  out[i] = (float4)(p, warp_pdf(warp, p, param));
}

__kernel void warp_pdf_at(int warp, float param, __global const float4* p, __global float* out,
                          uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  out[i] = warp_pdf(warp, p[i].xyz, param);
}

__kernel void warp_invert_at(int warp, float param, __global const float4* p,
                             __global float2* out, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  out[i] = warp_invert(warp, p[i].xyz, param);
}

/* core/math.cl's cos_sin_turns at t[i]: tests/warp_test.cpp's WarpTrig. */
__kernel void cos_sin_turns_at(__global const float* t, __global float2* out, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  out[i] = cos_sin_turns(t[i]);
}

/* core/math.cl's ln_positive at x[i]: tests/warp_test.cpp's WarpLog. */
__kernel void ln_positive_at(__global const float* x, __global float* out, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  out[i] = ln_positive(x[i]);
}
