/* Thin wrappers around kernels/bsdf/ for tests/bsdf_test.cpp.
 * A BSDF configuration arrives as 28 floats (tests/bsdf_test.cpp `pack`): base colour[3],
 * specular colour[3], metallic, roughness, specular, transmission, ior, clearcoat,
 * clearcoat roughness, iridescence, its film's ior and thickness (nm), diffuse transmission
 * and its colour[3], sheen colour[3] and roughness, anisotropy strength (along local x), the
 * clearcoat's normal[3] (local, normalised here; (0, 0, 1): the shading normal). Directions
 * are local (+z the front-face normal) unless the kernel says world. Sample outputs:
 *   dir_pdf[i]  = (wi, pdf_w): pdf_w 0 for an absorbed sample, the discrete probability for
 *                 a delta one;
 *   weight[i]   = (f |cos| / pdf, is_delta). */
#include "bsdf/bsdf.cl"

inline BsdfParams test_params(__global const float* c) {
  BsdfParams p;
  p.base_color = (float3)(c[0], c[1], c[2]);
  p.specular_color = (float3)(c[3], c[4], c[5]);
  p.metallic = c[6];
  p.roughness = c[7];
  p.specular = c[8];
  p.transmission = c[9];
  p.ior = c[10];
  p.clearcoat = c[11];
  p.clearcoat_roughness = c[12];
  p.iridescence = c[13];
  p.iridescence_ior = c[14];
  p.iridescence_thickness = c[15];
  p.diffuse_transmission = c[16];
  p.diffuse_transmission_color = (float3)(c[17], c[18], c[19]);
  p.sheen_color = (float3)(c[20], c[21], c[22]);
  p.sheen_roughness = c[23];
  p.anisotropy_t = (float3)(1.0f, 0.0f, 0.0f); /* local frames: x is the direction */
  p.anisotropy = c[24];
  p.clearcoat_n = (float3)(0.0f, 0.0f, 1.0f); /* world-space kernels set their own */
  return p;
}

/* The clearcoat's normal of the configuration, local: exactly (0, 0, 1) when untilted. */
inline float3 test_coat_normal(__global const float* c) {
  const float3 n = (float3)(c[25], c[26], c[27]);
  return n.x == 0.0f && n.y == 0.0f ? (float3)(0.0f, 0.0f, 1.0f) : normalize(n);
}

/* The test's own random numbers (as warp_test.cl): SplitMix64 at position i of stream
 * `seed`, 23 bits per coordinate as (k + 1/2) / 2^23, in the open interval (0, 1). */
inline ulong test_splitmix(ulong z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ul;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebul;
  return z ^ (z >> 31);
}

inline float4 test_random_4d(uint seed, uint i) {
  const ulong base = ((ulong)seed << 32) + ((ulong)i + 1ul) * 0x9e3779b97f4a7c15ul;
  const ulong a = test_splitmix(base), b = test_splitmix(base ^ 0x632be59bd9b4e019ul);
  const float scale = 0x1.0p-23f;
  return (float4)(((float)(uint)(a >> 41) + 0.5f) * scale, ((float)((uint)a >> 9) + 0.5f) * scale,
                  ((float)(uint)(b >> 41) + 0.5f) * scale, ((float)((uint)b >> 9) + 0.5f) * scale);
}

/* wo[i * wo_stride]: one direction for all (stride 0) or one per item (stride 1). */
__kernel void bsdf_sample_random(__global const float* cfg, int mode, __global const float4* wo,
                                 uint wo_stride, uint seed, __global float4* dir_pdf,
                                 __global float4* weight, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const BsdfParams p = test_params(cfg);
  const float4 u = test_random_4d(seed, i);
  const BsdfSample bs = gltf_bsdf_sample(&p, test_coat_normal(cfg), wo[i * wo_stride].xyz, u.xy, u.z, mode);
  dir_pdf[i] = (float4)(bs.wi, bs.pdf_w);
  weight[i] = (float4)(bs.weight, (float)bs.is_delta);
}

/* pdf and f |cos| at pairs (wo[i * wo_stride], wi[i]). */
__kernel void bsdf_eval_pairs(__global const float* cfg, int mode, __global const float4* wo,
                              uint wo_stride, __global const float4* wi, __global float4* out,
                              uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const BsdfParams p = test_params(cfg);
  const float3 o = wo[i * wo_stride].xyz, d = wi[i].xyz;
  const float3 nc = test_coat_normal(cfg);
  out[i] = (float4)(gltf_bsdf_eval(&p, nc, o, d, mode), gltf_bsdf_pdf(&p, nc, o, d));
}

/* A surface point of configuration cfg with a random geometric normal, a shading normal
 * tilted from it, the coat's normal in ns's frame, and a random wo (r0, r1.xy). */
static SurfaceHit test_world_hit(__global const float* cfg, float4 r0, float4 r1, float3* wo_out) {
  SurfaceHit sh;
  sh.p = (float3)(0.0f);
  sh.ng = warp_uniform_sphere(r0.xy);
  const float3 tilt = 0.7f * warp_uniform_sphere(r0.zw);
  sh.ns = normalize(sh.ng + tilt);
  if (dot(sh.ns, sh.ng) < 0.0f) sh.ns = -sh.ns;
  sh.uv = (float2)(0.0f);
  sh.triangle = 0u;
  sh.material = 0u;
  sh.bsdf = test_params(cfg);
  /* The coat's normal: the configuration's, in the frame of ns (front face). */
  {
    float3 t, b;
    make_basis(sh.ns, &t, &b);
    const float3 nc = test_coat_normal(cfg);
    sh.bsdf.clearcoat_n = nc.x == 0.0f && nc.y == 0.0f ? sh.ns : normalize(nc.x * t + nc.y * b + nc.z * sh.ns);
  }
  sh.emission = (float3)(0.0f);
  float3 wo = warp_uniform_sphere(r1.xy);
  if (fabs(dot(wo, sh.ng)) < 1e-3f) wo = sh.ng;
  sh.front = dot(wo, sh.ng) > 0.0f ? 1u : 0u;
  sh.flipped = 0u;
  *wo_out = wo;
  return sh;
}

/* The world-space wrapper (bsdf.cl) on random surface frames: ng uniform, ns tilted from it
 * by up to ~35 degrees, wo on either side (sh.front says which), normals oriented by
 * bsdf_orient or not. Per item, 4 float4:
 *   (weight, pdf_w) of a sample, (eval_cos, pdf) at the sampled wi,
 *   (dot(ng, wo) dot(ng, wi), the same with the normal that shades, is_delta, the reverse pdf
 *   of the point reached from wi's side), (wi, the reverse pdf of sh as it stands). */
__kernel void bsdf_world_check(__global const float* cfg, int mode, uint seed,
                               __global float4* out, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const float4 r0 = test_random_4d(seed, 4u * i), r1 = test_random_4d(seed, 4u * i + 1u);
  const float4 r2 = test_random_4d(seed, 4u * i + 2u);
  float3 wo;
  SurfaceHit sh = test_world_hit(cfg, r0, r1, &wo);
  const float3 ng0 = sh.ng, ns0 = sh.ns;
  SurfaceHit reverse = sh; /* the same point reached along -wi instead, normals as built */
  if (r1.z < 0.5f) bsdf_orient(&sh, wo);
  const BsdfSample bs = bsdf_sample(&sh, wo, r2.xy, r2.z, mode);
  const float3 e = bsdf_eval_cos(&sh, wo, bs.wi, mode);
  const float q = bsdf_pdf_w(&sh, wo, bs.wi);
  out[4u * i] = (float4)(bs.weight, bs.pdf_w);
  out[4u * i + 1u] = (float4)(e, q);
  /* The normal that shades: ns, or ng when wo is below the shading hemisphere (bsdf_frame). */
  const float3 n_eff = dot(ns0, wo) * dot(ng0, wo) > 0.0f ? ns0 : ng0;
  /* The reverse density (wo and wi swapped), as bidirectional MIS asks it of the oriented
   * vertex, and as the same point reached from wi's side would give it. */
  reverse.front = dot(bs.wi, ng0) > 0.0f ? 1u : 0u;
  out[4u * i + 2u] = (float4)(dot(ng0, wo) * dot(ng0, bs.wi), dot(n_eff, wo) * dot(n_eff, bs.wi),
                              (float)bs.is_delta, bsdf_pdf_w(&reverse, bs.wi, wo));
  out[4u * i + 3u] = (float4)(bs.wi, bsdf_pdf_w(&sh, bs.wi, wo));
}

/* bsdf_eval_cos_pdf (next-event estimation's one call) against bsdf_eval_cos and bsdf_pdf_w
 * at a random wi: out[2i] the one, out[2i + 1] the two. */
__kernel void bsdf_eval_pdf_check(__global const float* cfg, int mode, uint seed,
                                  __global float4* out, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const float4 r0 = test_random_4d(seed, 3u * i), r1 = test_random_4d(seed, 3u * i + 1u);
  const float4 r2 = test_random_4d(seed, 3u * i + 2u);
  float3 wo;
  SurfaceHit sh = test_world_hit(cfg, r0, r1, &wo);
  if (r1.z < 0.5f) bsdf_orient(&sh, wo);
  const float3 wi = warp_uniform_sphere(r2.xy);
  out[2u * i] = bsdf_eval_cos_pdf(&sh, wo, wi, mode);
  out[2u * i + 1u] = (float4)(bsdf_eval_cos(&sh, wo, wi, mode), bsdf_pdf_w(&sh, wo, wi));
}

/* The GGX visible-normal warp, alpha = (along x, along y) (equal: the isotropic path): h for
 * wo with its pdf; pdf at points; invert. */
__kernel void ggx_vndf_sample_random(float4 wo, float2 alpha, uint seed, __global float4* out,
                                     uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const float3 h = warp_ggx_vndf_2(test_random_4d(seed, i).xy, wo.xyz, alpha);
  out[i] = (float4)(h, warp_ggx_vndf_pdf_2(wo.xyz, h, alpha));
}

__kernel void ggx_vndf_sample_at(float4 wo, float2 alpha, __global const float2* u,
                                 __global float4* out, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const float3 h = warp_ggx_vndf_2(u[i], wo.xyz, alpha);
  out[i] = (float4)(h, warp_ggx_vndf_pdf_2(wo.xyz, h, alpha));
}

__kernel void ggx_vndf_pdf_at(float4 wo, float2 alpha, __global const float4* h,
                              __global float* out, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  out[i] = warp_ggx_vndf_pdf_2(wo.xyz, h[i].xyz, alpha);
}

__kernel void ggx_vndf_invert_at(float4 wo, float2 alpha, __global const float4* h,
                                 __global float2* out, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  out[i] = warp_ggx_vndf_invert_2(wo.xyz, h[i].xyz, alpha);
}
