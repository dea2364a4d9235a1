/* Thin wrappers around texture/texture.cl, material/material.cl and the alpha test of
 * bvh/intersect.cl for tests/texture_test.cpp and tests/material_test.cpp. Every kernel takes
 * the scene arguments first (SceneBuffers::bind). */
#include "bvh/intersect.cl"
#include "material/material.cl"

/* out[i] = texture_sample(texture, uv[i]) (srgb: decoded). */
__kernel void texture_lookup(SCENE_KERNEL_ARGS int texture, u32 srgb, __global const float2* uv,
                             __global float4* out, u32 n) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  const SceneView s = SCENE_VIEW();
  out[i] = texture_sample(&s, texture, uv[i], srgb != 0u);
}

/* out[i] = texture_sample_lod(texture, uv[i].xy, level uv[i].z) (srgb: decoded). */
__kernel void texture_lookup_lod(SCENE_KERNEL_ARGS int texture, u32 srgb, __global const float4* uv,
                                 __global float4* out, u32 n) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  const SceneView s = SCENE_VIEW();
  out[i] = texture_sample_lod(&s, texture, uv[i].xy, srgb != 0u, uv[i].z);
}

/* out[i] = srgb_to_linear(in[i]) (the formula; the table is read through texture_lookup). */
__kernel void srgb_formula(__global const float* in, __global float* out, u32 n) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  out[i] = srgb_to_linear(in[i]);
}

/* out[i] = the UV that slot `slot` of material `material` reads for (uv0[i], uv1[i]). */
__kernel void slot_uv(SCENE_KERNEL_ARGS u32 material, u32 slot, __global const float4* uvs,
                      __global float2* out, u32 n) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  const SceneView s = SCENE_VIEW();
  out[i] = texture_slot_uv(&s.materials[material].tex[slot], uvs[i].xy, uvs[i].zw);
}

/* Traces ray i (origin, direction) and resolves its material. Per ray, 5 float4s out:
 * (hit, t, uv1), base colour + alpha-free, shading normal, emission, material_emission_at. */
__kernel void resolve_rays(SCENE_KERNEL_ARGS __global const float4* org, __global const float4* dir,
                           __global float4* out, u32 n) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  const SceneView s = SCENE_VIEW();
  Hit hit;
  __global float4* o = out + 5 * i;
  if (!intersect_closest(&s, org[i].xyz, dir[i].xyz, INFINITY, &hit)) {
    o[0] = (float4)(0.0f);
    return;
  }
  const SurfaceHit sh = surface_shade(&s, &hit, org[i].xyz, dir[i].xyz);
  o[0] = (float4)(1.0f, hit.t, sh.uv1.x, sh.uv1.y);
  o[1] = (float4)(sh.bsdf.base_color, sh.bsdf.metallic);
  o[2] = (float4)(sh.ns, sh.bsdf.roughness);
  o[3] = (float4)(sh.emission, sh.bsdf.specular);
  o[4] = (float4)(material_emission_at(&s, hit.triangle, hit.b1, hit.b2), sh.color.w);
}

/* Closest-hit and any-hit answers for ray i: out[2i] = closest hit?, out[2i+1] = any hit?. */
__kernel void alpha_rays(SCENE_KERNEL_ARGS __global const float4* org, __global const float4* dir,
                         __global int* out, u32 n) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  const SceneView s = SCENE_VIEW();
  Hit hit;
  out[2 * i] = intersect_closest(&s, org[i].xyz, dir[i].xyz, INFINITY, &hit) ? 1 : 0;
  out[2 * i + 1] = intersect_any(&s, org[i].xyz, dir[i].xyz, INFINITY) ? 1 : 0;
}

/* Ray i's hit resolved by material_resolve_full and by material_resolve_plain: out[2i] has
 * bit k set where field k of the two differs in any bit (the BSDF inputs, shading normal and
 * emission, in the order below), out[2i + 1] is the material's MATERIAL_PLAIN flag; both -1
 * for a miss. */
#define SAME1(a, b) (as_uint(a) == as_uint(b))
#define SAME3(a, b) (SAME1((a).x, (b).x) && SAME1((a).y, (b).y) && SAME1((a).z, (b).z))
__kernel void resolve_plain_both(SCENE_KERNEL_ARGS __global const float4* org,
                                 __global const float4* dir, __global int* out, u32 n) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  const SceneView s = SCENE_VIEW();
  Hit hit;
  if (!intersect_closest(&s, org[i].xyz, dir[i].xyz, INFINITY, &hit)) {
    out[2 * i] = out[2 * i + 1] = -1;
    return;
  }
  SurfaceHit a = surface_at(&s, &hit, org[i].xyz, dir[i].xyz), b = a;
  __global const Material* m = &s.materials[a.material];
  material_resolve_full(&s, m, &a);
  material_resolve_plain(m, &b);
  const BsdfParams* p = &a.bsdf;
  const BsdfParams* q = &b.bsdf;
  const bool same[] = {
      SAME3(p->base_color, q->base_color), SAME3(p->specular_color, q->specular_color),
      SAME3(p->diffuse_transmission_color, q->diffuse_transmission_color),
      SAME1(p->metallic, q->metallic), SAME1(p->roughness, q->roughness),
      SAME1(p->specular, q->specular), SAME1(p->transmission, q->transmission),
      SAME1(p->ior, q->ior), SAME1(p->dispersion, q->dispersion),
      SAME1(p->clearcoat, q->clearcoat), SAME1(p->clearcoat_roughness, q->clearcoat_roughness),
      SAME3(p->clearcoat_n, q->clearcoat_n), SAME1(p->iridescence, q->iridescence),
      SAME1(p->iridescence_ior, q->iridescence_ior),
      SAME1(p->iridescence_thickness, q->iridescence_thickness),
      SAME1(p->diffuse_transmission, q->diffuse_transmission),
      SAME3(p->sheen_color, q->sheen_color), SAME1(p->sheen_roughness, q->sheen_roughness),
      SAME3(p->anisotropy_t, q->anisotropy_t), SAME1(p->anisotropy, q->anisotropy),
      SAME3(a.ns, b.ns), SAME3(a.emission, b.emission)};
  int differ = 0;
  for (int k = 0; k < (int)(sizeof(same) / sizeof(same[0])); ++k)
    if (!same[k]) differ |= 1 << k;
  out[2 * i] = differ;
  out[2 * i + 1] = (m->flags & MATERIAL_PLAIN) ? 1 : 0;
}
#undef SAME1
#undef SAME3
