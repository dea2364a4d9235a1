/* One light interface over emissive triangles, glTF punctual lights and the environment,
 * with the verbs of SmallVCM's lights:
 *   light_illuminate   sample a light as seen from a shading point (next-event estimation),
 *   light_emit         sample a ray leaving a light (light tracing, issue 5),
 *   light_radiance     the radiance a ray sees when it hits an emitting surface,
 *   env_radiance       ... or when it escapes (light/environment.cl),
 *   light_pdf_w        light_illuminate's solid-angle density for such a hit,
 *   light_env_pdf_w    ... or for such an escape.
 * A light is chosen in proportion to its power through an alias table built on the host
 * (host/render/scene_buffers.cpp, docs/concepts/lights.md); densities include the selection
 * probability. Delta lights (point, spot, directional) report pdf_w = their selection
 * probability and is_delta, and take no MIS weight. */
#ifndef CLPT_LIGHT_LIGHT_CL
#define CLPT_LIGHT_LIGHT_CL

#include "bvh/intersect.cl"
#include "core/ray.cl"
#include "light/area_light.cl"
#include "light/environment.cl"
#include "light/punctual.cl"

static inline bool light_is_delta(const __global Light* l) {
  return l->type == LIGHT_POINT || l->type == LIGHT_SPOT || l->type == LIGHT_DIRECTIONAL;
}

/* Light chosen by u in [0, 1): slot floor(u n), kept with its threshold, else its alias. */
static inline u32 light_select(const SceneView* s, float u) {
  const float scaled = u * (float)s->num_lights;
  const u32 slot = min((u32)scaled, s->num_lights - 1u);
  const __global Light* e = &s->lights[slot];
  return (scaled - (float)slot) < e->alias_threshold ? slot : e->alias;
}

static inline LightSample light_illuminate(const SceneView* s, float3 p, float u_select,
                                           float2 u_point) {
  LightSample ls = light_sample_none(p);
  if (s->num_lights == 0u) return ls;
  const u32 i = light_select(s, u_select);
  const __global Light* l = &s->lights[i];
  switch (l->type) {
    case LIGHT_TRIANGLE:
      ls = area_light_illuminate(s, l->triangle, p, u_point);
      break;
    case LIGHT_ENVIRONMENT: {
      float pdf;
      ls.wi = env_sample_w(s, u_point, &pdf);
      ls.dist = INFINITY;
      ls.p = p + ls.wi;
      ls.pdf_w = pdf;
      ls.Le = pdf > 0.0f ? env_radiance(s, ls.wi) : (float3)(0.0f);
      break;
    }
    default:
      ls = punctual_illuminate(l, p);
      break;
  }
  ls.pdf_w *= l->pdf_select;
  ls.light = i;
  return ls;
}

/* The shadow ray of light sample ls from org, a point already off the receiving surface
 * towards ls->wi: along wi to an infinitely far light, or the segment to the light point,
 * moved off an area light's own surface (bvh/intersect.cl, segment_ray). */
static inline ShadowRay light_sample_shadow_ray(float3 org, const LightSample* ls) {
  if (!isfinite(ls->dist)) {
    ShadowRay r;
    r.org = org;
    r.dir = ls->wi;
    r.tmax = INFINITY;
    return r;
  }
  const float3 target = dot(ls->n, ls->n) > 0.0f ? offset_ray_origin_towards(ls->p, ls->n, -ls->wi) : ls->p;
  return segment_ray(org, target);
}

/* Whether light sample ls is hidden from org (light_sample_shadow_ray). */
static inline bool light_sample_occluded(const SceneView* s, float3 org, const LightSample* ls) {
  const ShadowRay r = light_sample_shadow_ray(org, ls);
  return shadow_ray_occluded(s, &r);
}

/* light_illuminate's density for a ray that hit emitter triangle `tri` (leaf order) at
 * distance dist under cosine cos_light at the light. */
static inline float light_pdf_w(const SceneView* s, u32 tri, float dist, float cos_light) {
  const int e = s->triangle_light[tri];
  if (e < 0) return 0.0f;
  return s->lights[e].pdf_select * area_light_pdf_w(s, tri, dist, cos_light);
}

/* light_illuminate's density for a ray that escaped in direction w. */
static inline float light_env_pdf_w(const SceneView* s, float3 w) {
  if (!env_present(s)) return 0.0f;
  return s->lights[s->info->env_light].pdf_select * env_pdf_w(s, w);
}

/* Radiance seen by a ray that hit surface sh (before bsdf_orient), leaving towards wo. */
static inline float3 light_radiance(const SceneView* s, const SurfaceHit* sh, float3 wo) {
  return area_light_radiance(s, sh, wo);
}

/* A ray leaving a light chosen in proportion to power. Environment: the direction from the
 * environment's distribution, the origin a uniform point of the disk of the scene's bounding
 * radius perpendicular to it, one radius out from the bounding sphere's centre. */
static inline LightEmission light_emit(const SceneView* s, float u_select, float2 u_pos,
                                       float2 u_dir) {
  LightEmission e;
  e.pdf_a = 0.0f;
  e.pdf_w = 0.0f;
  e.pdf_select = 0.0f;
  e.Le = (float3)(0.0f);
  e.p = (float3)(0.0f);
  e.dir = (float3)(0.0f, 0.0f, 1.0f);
  e.cos_light = 0.0f;
  e.is_delta_pos = 0;
  e.is_delta_dir = 0;
  e.light = 0u;
  if (s->num_lights == 0u) return e;
  const u32 i = light_select(s, u_select);
  const __global Light* l = &s->lights[i];
  if (l->type == LIGHT_TRIANGLE) {
    e = area_light_emit(s, l->triangle, u_pos, u_dir);
  } else if (l->type == LIGHT_ENVIRONMENT) {
    float pdf;
    const float3 w = env_sample_w(s, u_dir, &pdf); /* towards the environment */
    const float r = s->info->bounds_radius;
    const float2 q = warp_concentric_disk(u_pos) * r;
    float3 t, b;
    make_basis(w, &t, &b);
    e.p = vload3(0, s->info->bounds_center) + r * w + q.x * t + q.y * b;
    e.dir = -w;
    e.pdf_w = pdf;
    e.pdf_a = r > 0.0f ? INV_PI_F / (r * r) : 0.0f;
    e.Le = pdf > 0.0f ? env_radiance(s, w) : (float3)(0.0f);
    e.cos_light = 1.0f;
  } else {
    e = punctual_emit(s, l, u_pos, u_dir);
  }
  e.pdf_select = l->pdf_select;
  e.light = i;
  return e;
}

/* Where the ray of emission e starts: on an area light, e.p offset off its triangle on the
 * side the ray leaves by (so it cannot hit its own triangle); elsewhere e.p. */
static inline float3 light_emission_origin(const SceneView* s, const LightEmission* e) {
  const __global Light* l = &s->lights[e->light];
  if (l->type != LIGHT_TRIANGLE) return e->p;
  float3 p0, p1, p2;
  triangle_vertices(s, l->triangle, &p0, &p1, &p2);
  const float3 ng = safe_normal(cross(p1 - p0, p2 - p0));
  return offset_ray_origin_towards(e->p, ng, e->dir);
}

/* Densities of a light's two sampling techniques for one light point, in the form the
 * bidirectional MIS weights use them (kernels/integrators/stages/vertex_mis.cl; Georgiev 2012,
 * SmallVCM's Illuminate/Emit/GetRadiance outputs):
 *   direct     light_illuminate's density of the point: per unit area for area lights, per
 *              steradian for the environment, the selection probability alone for delta
 *              lights (their position or direction is certain);
 *   emit_w     light_emit's density of the ray leaving that point in that direction: the
 *              selection probability times the position's and the direction's densities;
 *              the environment's and a directional light's position is a point of the disk
 *              of the scene's bounding radius (1 / (pi r^2));
 *   cos_light  the cosine at the light (area lights; 1 otherwise);
 *   finite     whether the light is at a finite distance (not environment or directional). */
typedef struct LightPdfs {
  float direct;
  float emit_w;
  float cos_light;
  int finite;
} LightPdfs;

static inline float light_disk_pdf_a(const SceneView* s) {
  const float r = s->info->bounds_radius;
  return r > 0.0f ? INV_PI_F / (r * r) : 0.0f;
}

/* For emitter triangle `tri` of area `area` seen under cosine cos_light. */
static inline LightPdfs light_pdfs_triangle(const SceneView* s, u32 tri, float area,
                                            float cos_light) {
  LightPdfs q;
  q.direct = 0.0f;
  q.emit_w = 0.0f;
  q.cos_light = cos_light;
  q.finite = 1;
  const int e = s->triangle_light[tri];
  if (e < 0 || !(area > 0.0f) || !(cos_light > 0.0f)) return q;
  const float side = (s->materials[s->triangles[tri].material].flags & MATERIAL_DOUBLE_SIDED) ? 0.5f : 1.0f;
  q.direct = s->lights[e].pdf_select / area;
  q.emit_w = q.direct * side * cos_light * INV_PI_F;
  return q;
}

/* For an emitter triangle `tri` seen under cosine cos_light (a ray that hit it). */
static inline LightPdfs light_pdfs_area(const SceneView* s, u32 tri, float cos_light) {
  return light_pdfs_triangle(s, tri, triangle_area(s, tri), cos_light);
}

/* For the environment seen in direction w (towards the environment). */
static inline LightPdfs light_pdfs_env(const SceneView* s, float3 w) {
  LightPdfs q;
  q.direct = light_env_pdf_w(s, w);
  q.emit_w = q.direct * light_disk_pdf_a(s);
  q.cos_light = 1.0f;
  q.finite = 0;
  return q;
}

/* For a light_illuminate sample ls (valid: pdf_w > 0). */
static inline LightPdfs light_pdfs_sample(const SceneView* s, const LightSample* ls) {
  const __global Light* l = &s->lights[ls->light];
  if (l->type == LIGHT_TRIANGLE) {
    /* One look at the vertices for both the area and the normal. */
    float3 p0, p1, p2;
    triangle_vertices(s, l->triangle, &p0, &p1, &p2);
    const float3 c = cross(p1 - p0, p2 - p0);
    const float len = length(c);
    return light_pdfs_triangle(s, l->triangle, 0.5f * len, len > 0.0f ? fabs(dot(c, ls->wi)) / len : 0.0f);
  }
  if (l->type == LIGHT_ENVIRONMENT) return light_pdfs_env(s, ls->wi);
  LightPdfs q;
  q.direct = l->pdf_select;
  q.cos_light = 1.0f;
  if (l->type == LIGHT_DIRECTIONAL) {
    q.emit_w = l->pdf_select * light_disk_pdf_a(s);
    q.finite = 0;
  } else {
    q.emit_w = l->pdf_select * (l->type == LIGHT_SPOT ? warp_uniform_cone_pdf(1.0f, l->cos_outer)
                                                       : warp_uniform_sphere_pdf());
    q.finite = 1;
  }
  return q;
}

/* For the ray light_emit returned (e valid). */
static inline LightPdfs light_pdfs_emission(const SceneView* s, const LightEmission* e) {
  const __global Light* l = &s->lights[e->light];
  LightPdfs q;
  q.emit_w = e->pdf_select * e->pdf_a * e->pdf_w;
  q.cos_light = e->cos_light;
  q.finite = l->type != LIGHT_ENVIRONMENT && l->type != LIGHT_DIRECTIONAL;
  if (l->type == LIGHT_TRIANGLE) q.direct = e->pdf_select * e->pdf_a;
  else if (l->type == LIGHT_ENVIRONMENT) q.direct = e->pdf_select * e->pdf_w;
  else q.direct = e->pdf_select;
  return q;
}

#endif
