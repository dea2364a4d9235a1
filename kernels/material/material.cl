/* Material evaluation at a surface point: the glTF material's factors, its textures (by
 * slot, each with its UV set and KHR_texture_transform) and the vertex colour, resolved into
 * the BSDF inputs, the shading normal (normal map) and the emission. */
#ifndef CLPT_MATERIAL_MATERIAL_CL
#define CLPT_MATERIAL_MATERIAL_CL

#include "geometry/surface.cl"
#include "geometry/vertex_attributes.cl"
#include "texture/texture.cl"

/* Emitted radiance of material m at the given UVs (front side): emissiveFactor x
 * emissive_strength x the emissive texture (sRGB). */
static inline float3 material_emission_uv(const SceneView* s, __global const Material* m,
                                          float2 uv0,
                                          float2 uv1) {
  if (!(m->flags & MATERIAL_EMISSIVE)) return (float3)(0.0f);
  const float3 e = vload3(0, m->emission);
  /* Emission is read at full resolution: light sampling sees it so, and must agree. */
  const TexPoint q = {uv0, uv1, (float2)(-INFINITY)};
  return e * texture_slot_sample(s, &m->tex[TEX_EMISSIVE], &q, true, (float4)(1.0f)).xyz;
}

/* Emitted radiance at a point of leaf-order triangle `triangle` (front side), for lights
 * that sample a point on an emissive triangle. */
static inline float3 material_emission_at(const SceneView* s, u32 triangle, float b1, float b2) {
  const Triangle t = s->triangles[triangle];
  __global const Material* m = &s->materials[t.material];
  if (!(m->flags & MATERIAL_EMISSIVE)) return (float3)(0.0f);
  if (m->tex[TEX_EMISSIVE].texture < 0) return vload3(0, m->emission);
  float2 uv1;
  float4 color;
  hit_extra(s, &t, b1, b2, &uv1, &color);
  return material_emission_uv(s, m, hit_uv0(s, &t, b1, b2), uv1);
}

/* The tangent frame of the hit's shading normal n: the interpolated tangent made orthogonal
 * to n (t) and bitangent = sign * cross(n, t) (b). False without a usable tangent. */
static inline bool material_tangent_frame(const SurfaceHit* sh, float3* t, float3* b) {
  const float3 n = sh->ns;
  *t = sh->tangent.xyz - n * dot(n, sh->tangent.xyz);
  const float tl = length(*t);
  if (!(tl > 1e-8f)) return false;
  *t /= tl;
  *b = sh->tangent.w * cross(n, *t);
  return true;
}

/* A normal map (the base's TEX_NORMAL or the clearcoat's TEX_CLEARCOAT_NORMAL): tangent-space
 * normal (x, y scaled by `scale`) in the frame of the interpolated tangent, bitangent = sign *
 * cross(n, t) and the interpolated normal. Without a usable tangent the interpolated normal
 * is returned. The result stays on the geometric normal's side. */
static inline float3 material_normal_map(const SceneView* s, __global const TextureSlot* slot, float scale,
                                         const SurfaceHit* sh, const TexPoint* q) {
  const float3 n = sh->ns;
  float3 t, b;
  if (!material_tangent_frame(sh, &t, &b)) return n;
  float3 c = texture_slot_sample(s, slot, q, false, (float4)(0.5f, 0.5f, 1.0f, 1.0f)).xyz;
  c = c * 2.0f - 1.0f;
  c.xy *= scale;
  float3 p = c.x * t + c.y * b + c.z * n;
  const float pl = length(p);
  if (!(pl > 1e-8f) || !isfinite(pl)) return n;
  p /= pl;
  /* Keep it in the geometric normal's hemisphere (a strong map at a grazing mesh normal can
   * tip it over): lift it just above the tangent plane of ng. */
  const float cos_g = dot(p, sh->ng);
  if (cos_g < 1e-3f) p = normalize(p + (1e-3f - cos_g) * sh->ng);
  return p;
}

/* KHR_materials_anisotropy: the strength, and the direction in world space: (1, 0) or the
 * texture's RG x 2 - 1 in the tangent frame (interpolated tangent, bitangent sign x cross(n,
 * t), n the interpolated normal), turned counter-clockwise by anisotropyRotation. Without a
 * usable tangent (the loader generates one from the UVs; a mesh without UVs has none) or
 * with a zero texture direction the BSDF stays isotropic. */
static inline void material_anisotropy(const SceneView* s, __global const Material* m,
                                       SurfaceHit* sh, const TexPoint* q) {
  sh->bsdf.anisotropy = 0.0f;
  sh->bsdf.anisotropy_t = (float3)(0.0f);
  if (!(m->flags & MATERIAL_ANISOTROPIC)) return;
  float2 d = (float2)(1.0f, 0.0f);
  float strength = m->anisotropy[0];
  if (m->tex[TEX_ANISOTROPY].texture >= 0) {
    const float3 a = texture_slot_sample(s, &m->tex[TEX_ANISOTROPY], q, false,
                                         (float4)(1.0f)).xyz;
    d = a.xy * 2.0f - 1.0f;
    strength *= a.z;
  }
  const float c = m->anisotropy[1], sn = m->anisotropy[2];
  d = (float2)(c * d.x - sn * d.y, sn * d.x + c * d.y);
  float3 t, b;
  if (!(strength > 0.0f) || !material_tangent_frame(sh, &t, &b)) return;
  const float3 dir = d.x * t + d.y * b;
  const float dl = length(dir);
  if (!(dl > 1e-6f) || !isfinite(dl)) return;
  sh->bsdf.anisotropy = fmin(strength, 1.0f);
  sh->bsdf.anisotropy_t = dir / dl;
}

/* The BSDF inputs of material m at sh from its factors, textures, vertex colour and layers:
 * the general case (material_resolve below takes the plain one's shortcut). */
CLPT_NOINLINE void material_resolve_full(const SceneView* s, __global const Material* m,
                                         SurfaceHit* sh) {
  const float2 uv0 = sh->uv, uv1 = sh->uv1;
  const TexPoint q = {uv0, uv1, sh->tex_lod};
  const float4 white = (float4)(1.0f);
  const float4 base = vload4(0, m->base_color) * sh->color *
                      texture_slot_sample(s, &m->tex[TEX_BASE_COLOR], &q, true, white);
  sh->bsdf.base_color = base.xyz;
  const float4 mr = texture_slot_sample(s, &m->tex[TEX_METALLIC_ROUGHNESS], &q, false, white);
  sh->bsdf.metallic = m->metallic * mr.z;
  sh->bsdf.roughness = m->roughness * mr.y;
  sh->bsdf.transmission =
      m->transmission * texture_slot_sample(s, &m->tex[TEX_TRANSMISSION], &q, false, white).x;
  sh->bsdf.specular =
      m->specular * texture_slot_sample(s, &m->tex[TEX_SPECULAR], &q, false, white).w;
  sh->bsdf.specular_color =
      vload3(0, m->specular_color) *
      texture_slot_sample(s, &m->tex[TEX_SPECULAR_COLOR], &q, true, white).xyz;
  sh->bsdf.ior = m->ior;
  sh->bsdf.dispersion = sh->bsdf.transmission > 0.0f ? m->dispersion : 0.0f;
  /* The layers' textures are read only where their factor makes them matter (most
   * materials have neither layer: their four slot look-ups would be spent for nothing). */
  sh->bsdf.clearcoat = sh->bsdf.clearcoat_roughness = 0.0f;
  sh->bsdf.clearcoat_n = sh->ns; /* the interpolated normal: the base's map is applied below */
  if (m->clearcoat > 0.0f) {
    sh->bsdf.clearcoat = bsdf_unorm16(
        m->clearcoat * texture_slot_sample(s, &m->tex[TEX_CLEARCOAT], &q, false, white).x);
    sh->bsdf.clearcoat_roughness = bsdf_unorm16(
        m->clearcoat_roughness *
        texture_slot_sample(s, &m->tex[TEX_CLEARCOAT_ROUGHNESS], &q, false, white).y);
    if (m->tex[TEX_CLEARCOAT_NORMAL].texture >= 0)
      sh->bsdf.clearcoat_n = material_normal_map(s, &m->tex[TEX_CLEARCOAT_NORMAL],
                                                 m->clearcoat_normal_scale, sh, &q);
  }
  sh->bsdf.iridescence = 0.0f;
  sh->bsdf.iridescence_ior = m->iridescence_ior;
  sh->bsdf.iridescence_thickness = m->iridescence_thickness_max;
  if (m->iridescence > 0.0f) {
    sh->bsdf.iridescence =
        m->iridescence * texture_slot_sample(s, &m->tex[TEX_IRIDESCENCE], &q, false, white).x;
    /* Without a thickness texture G reads 1: the maximum, as the extension says. */
    sh->bsdf.iridescence_thickness =
        mix(m->iridescence_thickness_min, m->iridescence_thickness_max,
            texture_slot_sample(s, &m->tex[TEX_IRIDESCENCE_THICKNESS], &q, false, white).y);
  }
  sh->bsdf.diffuse_transmission = 0.0f;
  sh->bsdf.diffuse_transmission_color = vload3(0, m->diffuse_transmission_color);
  if (m->diffuse_transmission > 0.0f) {
    sh->bsdf.diffuse_transmission =
        m->diffuse_transmission *
        texture_slot_sample(s, &m->tex[TEX_DIFFUSE_TRANSMISSION], &q, false, white).w;
    sh->bsdf.diffuse_transmission_color *=
        texture_slot_sample(s, &m->tex[TEX_DIFFUSE_TRANSMISSION_COLOR], &q, true, white).xyz;
  }
  /* The sheen is rounded to 8-bit steps (bsdf_unorm8: what a PathVertex stores). */
  sh->bsdf.sheen_color = (float3)(0.0f);
  sh->bsdf.sheen_roughness = 0.0f;
  if (max_component(vload3(0, m->sheen_color)) > 0.0f) {
    const float3 c = vload3(0, m->sheen_color) *
                     texture_slot_sample(s, &m->tex[TEX_SHEEN_COLOR], &q, true, white).xyz;
    sh->bsdf.sheen_color = (float3)(bsdf_unorm8(c.x), bsdf_unorm8(c.y), bsdf_unorm8(c.z));
    sh->bsdf.sheen_roughness = bsdf_unorm8(
        m->sheen_roughness * texture_slot_sample(s, &m->tex[TEX_SHEEN_ROUGHNESS], &q, false, white).w);
  }
  material_anisotropy(s, m, sh, &q);
  sh->emission = material_emission_uv(s, m, uv0, uv1);
  if (m->tex[TEX_NORMAL].texture >= 0)
    sh->ns = material_normal_map(s, &m->tex[TEX_NORMAL], m->normal_scale, sh, &q);
}

/* A plain material (MATERIAL_PLAIN, decided by the host: no texture in any slot, emissive
 * included, and no layer: clearcoat, iridescence, diffuse transmission, sheen and anisotropy
 * all off): its factors times the vertex colour. Bit for bit what material_resolve_full
 * gives it, since every slot then reads its fallback 1 and x * 1 = x exactly
 * (Material.ResolvePlainIsResolveFull), without the seventeen slot look-ups and the layers'
 * tests: on PoCL those were 9 % of a Cornell box render (docs/BENCHMARKS.md, session 31). */
static inline void material_resolve_plain(__global const Material* m, SurfaceHit* sh) {
  sh->bsdf.base_color = (vload4(0, m->base_color) * sh->color).xyz;
  sh->bsdf.metallic = m->metallic;
  sh->bsdf.roughness = m->roughness;
  sh->bsdf.transmission = m->transmission;
  sh->bsdf.specular = m->specular;
  sh->bsdf.specular_color = vload3(0, m->specular_color);
  sh->bsdf.ior = m->ior;
  sh->bsdf.dispersion = m->transmission > 0.0f ? m->dispersion : 0.0f;
  sh->bsdf.clearcoat = sh->bsdf.clearcoat_roughness = 0.0f;
  sh->bsdf.clearcoat_n = sh->ns;
  sh->bsdf.iridescence = 0.0f;
  sh->bsdf.iridescence_ior = m->iridescence_ior;
  sh->bsdf.iridescence_thickness = m->iridescence_thickness_max;
  sh->bsdf.diffuse_transmission = 0.0f;
  sh->bsdf.diffuse_transmission_color = vload3(0, m->diffuse_transmission_color);
  sh->bsdf.sheen_color = (float3)(0.0f);
  sh->bsdf.sheen_roughness = 0.0f;
  sh->bsdf.anisotropy = 0.0f;
  sh->bsdf.anisotropy_t = (float3)(0.0f);
  sh->emission = (m->flags & MATERIAL_EMISSIVE) ? vload3(0, m->emission) : (float3)(0.0f);
}

/* The BSDF inputs, shading normal and emission of the hit's material. */
static inline void material_resolve(const SceneView* s, SurfaceHit* sh) {
  __global const Material* m = &s->materials[sh->material];
  if (m->flags & MATERIAL_PLAIN)
    material_resolve_plain(m, sh);
  else
    material_resolve_full(s, m, sh);
}

/* The hit's surface with its material resolved: what integrators shade with. */
static inline SurfaceHit surface_shade(const SceneView* s, const Hit* hit, float3 org, float3 dir) {
  SurfaceHit sh = surface_at(s, hit, org, dir);
  material_resolve(s, &sh);
  return sh;
}

/* The same, its textures read over the footprint of a ray cone `cone_width` wide at the hit
 * (0: none, full resolution; surface_texture_lod), written to *sh (surface_at_to). */
static inline void surface_shade_cone_to(const SceneView* s, const Hit* hit, float3 org, float3 dir,
                                         float cone_width, SurfaceHit* sh) {
  surface_at_to(s, hit, org, dir, sh);
  if (cone_width > 0.0f && (s->materials[sh->material].flags & MATERIAL_TEXTURED))
    sh->tex_lod = surface_texture_lod(s, sh, dir, cone_width);
  material_resolve(s, sh);
}

static inline SurfaceHit surface_shade_cone(const SceneView* s, const Hit* hit, float3 org, float3 dir,
                                            float cone_width) {
  SurfaceHit sh;
  surface_shade_cone_to(s, hit, org, dir, cone_width, &sh);
  return sh;
}

#endif
