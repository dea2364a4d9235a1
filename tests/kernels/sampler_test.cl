/* Evaluates the sampler on a grid of (pixel, sample index, dimension) for the Sampler* tests.
 * out[(p * num_samples + i) * num_dims + j] = sample_2d(dims[j]) when two_d, else
 * (sample_1d(dims[j]), 0), for pixel pixels[p] and sample index first_sample + i. */
#include "sampler/sampler.cl"

__kernel void sampler_values(__constant const RenderParams* params, __global const u32* pixels,
                             u32 num_pixels, u32 first_sample, u32 num_samples,
                             __global const u32* dims, u32 num_dims, u32 two_d,
                             __global float2* out) {
  const u32 id = get_global_id(0);
  if (id >= num_pixels * num_samples * num_dims) return;
  const u32 j = id % num_dims;
  const u32 i = (id / num_dims) % num_samples;
  const u32 p = id / (num_dims * num_samples);
  const Sampler s = sampler_init(params, pixels[p], first_sample + i);
  out[id] = two_d ? sample_2d(&s, dims[j]) : (float2)(sample_1d(&s, dims[j]), 0.0f);
}

/* stratum_to_unit(strata[k], counts[k], bits[k]) for the fixed-point border tests. */
__kernel void stratum_values(__global const u32* strata, __global const u32* counts,
                             __global const u32* bits, u32 num, __global float* out) {
  const u32 k = get_global_id(0);
  if (k >= num) return;
  out[k] = stratum_to_unit(strata[k], counts[k], bits[k]);
}

/* The bits-to-float conversions of the samplers at given bit patterns: out[2k] from the
 * independent sampler's u32_to_unit_float, out[2k+1] from Sobol's sobol_to_unit. */
__kernel void unit_float_values(__global const u32* bits, u32 num, __global float* out) {
  const u32 k = get_global_id(0);
  if (k >= num) return;
  out[2 * k] = u32_to_unit_float(bits[k]);
  out[2 * k + 1] = sobol_to_unit(bits[k]);
}
