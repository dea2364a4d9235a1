/* tests/sheen_test.cpp: KHR_materials_sheen's lobe (kernels/bsdf/sheen.cl) and its tables
 * (kernels/bsdf/sheen_table.h), read through the kernels' own functions. */
#include "bsdf/gltf_bsdf.cl"

/* (E, E') at (cos, roughness) pairs: sheen_albedos after the kernel's roughness clamp. */
__kernel void sheen_tables_at(__global const float2* mu_r, __global float2* out, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  out[i] = sheen_albedos(mu_r[i].x, sheen_clamp_roughness(mu_r[i].y));
}

/* A sheen over a black base with specular 0 (so the sheen is the whole BSDF), sampled by
 * gltf_bsdf_sample from wo = (sqrt(1 - cos^2), 0, cos) on a k x k stratified grid of u (one
 * midpoint per cell; u_lobe 0.5): out[i] = (weight, pdf_w). The mean of the weights is the
 * BSDF's albedo at wo. */
__kernel void sheen_only_samples(float cos_o, float roughness, float4 colour, uint k,
                                 __global float4* out) {
  const uint i = get_global_id(0);
  if (i >= k * k) return;
  BsdfParams p;
  p.base_color = p.specular_color = p.diffuse_transmission_color = (float3)(0.0f);
  p.metallic = p.specular = p.transmission = p.clearcoat = p.clearcoat_roughness = 0.0f;
  p.roughness = 1.0f;
  p.ior = 1.5f;
  p.iridescence = 0.0f;
  p.iridescence_ior = 1.3f;
  p.iridescence_thickness = 400.0f;
  p.diffuse_transmission = 0.0f;
  p.sheen_color = colour.xyz;
  p.sheen_roughness = roughness;
  p.anisotropy_t = (float3)(0.0f);
  p.anisotropy = 0.0f;
  const float2 u = (float2)(((float)(i % k) + 0.5f) / (float)k, ((float)(i / k) + 0.5f) / (float)k);
  const float3 wo = (float3)(sqrt(fmax(0.0f, 1.0f - cos_o * cos_o)), 0.0f, cos_o);
  const BsdfSample bs = gltf_bsdf_sample(&p, (float3)(0.0f, 0.0f, 1.0f), wo, u, 0.5f, TRANSPORT_RADIANCE);
  out[i] = (float4)(bs.weight, bs.pdf_w);
}

/* How far the capped table's nodes were raised near the cap (sheen_table.h). */
__kernel void sheen_table_raise(__global float* out) { out[0] = SHEEN_E_CAPPED_RAISE; }
