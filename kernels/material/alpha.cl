/* glTF alpha modes at a candidate ray hit, for the traversal (bvh/intersect.cl):
 *   MASK:  alpha = baseColorFactor.a x base colour texture alpha x COLOR_0 alpha; a hole
 *          where alpha < alphaCutoff.
 *   BLEND: stochastic transparency, a hole with probability 1 - alpha, decided by a hash of
 *          the ray and the triangle: the same ray always sees the same answer (closest hit
 *          and shadow rays agree), different rays are independent.
 * Opaque materials cost one material flag load per accepted candidate hit. */
#ifndef CLPT_MATERIAL_ALPHA_CL
#define CLPT_MATERIAL_ALPHA_CL

#include "geometry/vertex_attributes.cl"
#include "texture/texture.cl"

/* The material alpha at a point of a triangle. */
static inline float material_alpha(const SceneView* s, __global const Material* m,
                                   const Triangle* t,
                                   float b1, float b2) {
  float2 uv1;
  float4 color;
  hit_extra(s, t, b1, b2, &uv1, &color);
  float alpha = m->base_color[3] * color.w;
  __global const TextureSlot* slot = &m->tex[TEX_BASE_COLOR];
  if (slot->texture >= 0) {
    const float2 uv0 = hit_uv0(s, t, b1, b2);
    alpha *= texture_sample(s, slot->texture, texture_slot_uv(slot, uv0, uv1), false).w;
  }
  return alpha;
}

static inline u32 alpha_mix(u32 h, u32 k) {
  k *= 0xcc9e2d51u;
  k = rotate(k, 15u);
  k *= 0x1b873593u;
  h ^= k;
  h = rotate(h, 13u);
  return h * 5u + 0xe6546b64u;
}

/* A number in [0, 1) from the ray and the triangle (MurmurHash3 steps and finaliser). */
static inline float alpha_hash(float3 org, float3 dir, u32 tri) {
  u32 h = 0x9747b28cu;
  h = alpha_mix(h, as_uint(org.x));
  h = alpha_mix(h, as_uint(org.y));
  h = alpha_mix(h, as_uint(org.z));
  h = alpha_mix(h, as_uint(dir.x));
  h = alpha_mix(h, as_uint(dir.y));
  h = alpha_mix(h, as_uint(dir.z));
  h = alpha_mix(h, tri);
  h ^= 28u;
  h ^= h >> 16;
  h *= 0x85ebca6bu;
  h ^= h >> 13;
  h *= 0xc2b2ae35u;
  h ^= h >> 16;
  return (float)(h >> 8) * 0x1.0p-24f;
}

/* The material of leaf-order triangle `tri` (and the triangle in *t) when it has one of the
 * alpha modes in `modes`; 0 otherwise. Opaque scenes skip the material look-up, and kernels
 * without a material buffer (tests) see every surface as opaque. */
static inline __global const Material* alpha_material(const SceneView* s, u32 tri, u32 modes,
                                                      Triangle* t) {
  if (!(s->flags & SCENE_ALPHA) || s->materials == 0) return 0;
  *t = s->triangles[tri];
  __global const Material* m = &s->materials[t->material];
  return (m->flags & modes) ? m : 0;
}

/* Whether the hit of ray (org, dir) on leaf-order triangle `tri` at (b1, b2) falls in a hole
 * of its material. */
static inline bool alpha_hole(const SceneView* s, u32 tri, float b1, float b2, float3 org,
                              float3 dir) {
  Triangle t;
  __global const Material* m = alpha_material(s, tri, MATERIAL_ALPHA_MASK | MATERIAL_ALPHA_BLEND, &t);
  if (!m) return false;
  const float alpha = material_alpha(s, m, &t, b1, b2);
  if (m->flags & MATERIAL_ALPHA_MASK) return !(alpha >= m->alpha_cutoff);
  return alpha_hash(org, dir, tri) >= alpha;
}

/* The probability that a ray reaching hit `hit` of surface `tri` meets the surface rather
 * than a hole: a BLEND material's alpha, 1 elsewhere (a MASK hit is always on the solid
 * part). A density estimate from photons stored at hits divides by it: the photons stored
 * there are that fraction of those that arrived, while the light the surface reflects is
 * the whole incident light's (the camera meets the surface with that probability too). */
static inline float alpha_coverage(const SceneView* s, u32 tri, float b1, float b2) {
  Triangle t;
  __global const Material* m = alpha_material(s, tri, MATERIAL_ALPHA_BLEND, &t);
  return m ? clamp(material_alpha(s, m, &t, b1, b2), 0.0f, 1.0f) : 1.0f;
}

#endif
