/* glTF's KHR_lights_punctual lights: point, spot and directional. All three are delta
 * lights: a BSDF-sampled ray never finds them, so next-event estimation is their only
 * technique and takes no MIS weight.
 *
 * Units (README "Lights"): clpt renders in the file's numbers. A point or spot light of
 * intensity I (candela in glTF) times its colour is taken as radiant intensity in W/sr; a
 * directional light's intensity (lux) times colour as irradiance in W/m^2; an emissive
 * surface's emissiveFactor x strength is radiance in W/(m^2 sr). So a diffuse plane of albedo
 * rho at distance d straight under a point light of intensity I shows rho / pi * I / d^2.
 *
 * Spot falloff, from the KHR_lights_punctual specification:
 *     scale  = 1 / max(0.001, cos(inner) - cos(outer)),
 *     offset = -cos(outer) * scale,
 *     t = saturate(cd * scale + offset),   attenuation = t^2,
 * cd the cosine between the spot's direction and the direction from the light to the point. */
#ifndef CLPT_LIGHT_PUNCTUAL_CL
#define CLPT_LIGHT_PUNCTUAL_CL

#include "core/math.cl"
#include "core/scene_view.cl"
#include "core/warp.cl"
#include "light/light_types.cl"

static inline float spot_falloff(const __global Light* l, float cd) {
  const float scale = 1.0f / fmax(0.001f, l->cos_inner - l->cos_outer);
  const float t = clamp(cd * scale - l->cos_outer * scale, 0.0f, 1.0f);
  return t * t;
}

/* Radiant intensity of a point or spot light towards unit direction w (leaving the light). */
static inline float3 punctual_intensity(const __global Light* l, float3 w) {
  const float3 I = vload3(0, l->intensity);
  if (l->type == LIGHT_SPOT) return I * spot_falloff(l, dot(vload3(0, l->direction), w));
  return I;
}

/* The light as seen from p; ls->pdf_w is 1 (selection not included). */
static inline LightSample punctual_illuminate(const __global Light* l, float3 p) {
  LightSample ls = light_sample_none(p);
  ls.is_delta = 1;
  if (l->type == LIGHT_DIRECTIONAL) {
    ls.wi = -vload3(0, l->direction);
    ls.dist = INFINITY;
    ls.p = p + ls.wi;
    ls.Le = vload3(0, l->intensity);
    ls.pdf_w = 1.0f;
    return ls;
  }
  ls.p = vload3(0, l->position);
  const float3 d = ls.p - p;
  const float dist2 = dot(d, d);
  if (!(dist2 > 0.0f) || !isfinite(dist2)) return ls;
  ls.dist = sqrt(dist2);
  ls.wi = d / ls.dist;
  ls.Le = punctual_intensity(l, -ls.wi) / dist2;
  ls.pdf_w = 1.0f;
  return ls;
}

/* A ray leaving a punctual light. Point: uniform sphere; spot: uniform in the outer cone;
 * directional: a uniform point of the disk of the scene's bounding radius, perpendicular to
 * the light's direction, one radius behind the bounding sphere's centre. */
static inline LightEmission punctual_emit(const SceneView* s, const __global Light* l, float2 u_pos,
                                          float2 u_dir) {
  LightEmission e;
  e.cos_light = 1.0f;
  if (l->type == LIGHT_DIRECTIONAL) {
    const float3 d = vload3(0, l->direction);
    const float r = s->info->bounds_radius;
    const float2 q = warp_concentric_disk(u_pos) * r;
    float3 t, b;
    make_basis(d, &t, &b);
    e.p = vload3(0, s->info->bounds_center) - r * d + q.x * t + q.y * b;
    e.dir = d;
    e.Le = vload3(0, l->intensity);
    e.pdf_a = r > 0.0f ? INV_PI_F / (r * r) : 0.0f;
    e.pdf_w = 1.0f;
    e.is_delta_pos = 0;
    e.is_delta_dir = 1;
    return e;
  }
  e.p = vload3(0, l->position);
  e.pdf_a = 1.0f;
  e.is_delta_pos = 1;
  e.is_delta_dir = 0;
  if (l->type == LIGHT_SPOT) {
    e.dir = to_world(warp_uniform_cone(u_dir, l->cos_outer), vload3(0, l->direction));
    e.pdf_w = warp_uniform_cone_pdf(1.0f, l->cos_outer);
  } else {
    e.dir = warp_uniform_sphere(u_dir);
    e.pdf_w = warp_uniform_sphere_pdf();
  }
  e.Le = punctual_intensity(l, e.dir);
  return e;
}

#endif
