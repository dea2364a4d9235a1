/* tests/thin_film_test.cpp: thin_film_reflectance (kernels/bsdf/thin_film.cl) at n points.
 * in[i] = (cos1, film ior, thickness nm, base f0 grey); out[i] = (R, G, B, 0). */
#include "bsdf/thin_film.cl"

__kernel void thin_film_eval(__global const float4* in, __global float4* out, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const float4 a = in[i];
  out[i] = (float4)(thin_film_reflectance(a.x, a.y, a.z, (float3)(a.w)), 0.0f);
}
