/* Kernels for tests/ic_test.cpp: the irradiance cache's lookup (kernels/integrators/ic/
 * lookup.cl over the grid of kernels/spatial/sphere_grid.cl) at given points. */
#include "integrators/ic/records.cl"

/* For query i (point queries[2i].xyz, normal queries[2i+1].xyz, depth as_uint of
 * queries[2i].w): the estimate (e, weight) and the number of records it used. */
__kernel void ic_lookup_points(__constant const IcParams* ic, __global const IcRecord* records,
                               __global const u32* starts, __global const u32* entries,
                               __global const float4* queries, u32 count, __global float4* out,
                               __global u32* used) {
  const u32 i = get_global_id(0);
  if (i >= count) return;
  const IcCache c = ic_cache(ic, records, starts, entries);
  const float4 q = queries[2u * i];
  const IcEstimate est = ic_lookup(&c, q.xyz, queries[2u * i + 1u].xyz, as_uint(q.w));
  out[i] = (float4)(est.e, est.weight);
  used[i] = est.records;
}

/* A record whose hemisphere sees the radiance L(w) = 1 + w . g (stratum centres, every ray
 * hitting at distance 1e6, as good as infinitely far): ic_finish_record then makes E, R and
 * the gradients. */
__kernel void ic_finish_linear(__constant const IcParams* ic, __global IcRecord* rec,
                               __global float4* rays, float gx, float gy, float gz) {
  if (get_global_id(0) != 0) return;
  const float3 n = vload3(0, rec->n), g = (float3)(gx, gy, gz);
  for (u32 j = 0; j < ic->rays_theta; ++j)
    for (u32 k = 0; k < ic->rays_phi; ++k) {
      const float3 w = to_world(ic_stratum_dir(j, k, ic->rays_theta, ic->rays_phi, (float2)(0.5f)), n);
      rays[j * ic->rays_phi + k] = (float4)((float3)(1.0f + dot(w, g)), 1e6f);
    }
  ic_finish_record(ic, rec, rays);
}

/* A record under an infinite ceiling at height h along its normal whose radiance is linear
 * in position, L(p) = a + b . p (b tangent to the ceiling), the record at the origin: E(x) =
 * pi (a + b . x), so grad_trans E = pi b (Ward and Heckbert's translational gradient, whose
 * rays' distances r = h / cos(theta) now matter). Stratum centres. */
__kernel void ic_finish_ceiling(__constant const IcParams* ic, __global IcRecord* rec,
                                __global float4* rays, float a, float bx, float by, float bz,
                                float h) {
  if (get_global_id(0) != 0) return;
  const float3 n = vload3(0, rec->n), b = (float3)(bx, by, bz);
  for (u32 j = 0; j < ic->rays_theta; ++j)
    for (u32 k = 0; k < ic->rays_phi; ++k) {
      const float3 w = to_world(ic_stratum_dir(j, k, ic->rays_theta, ic->rays_phi, (float2)(0.5f)), n);
      const float r = h / dot(w, n);
      rays[j * ic->rays_phi + k] = (float4)((float3)(a + dot(b, r * w)), r);
    }
  ic_finish_record(ic, rec, rays);
}
