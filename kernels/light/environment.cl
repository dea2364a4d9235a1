/* The environment: radiance arriving from infinitely far away along a direction, either an
 * equirectangular map (--env, scaled by --env-scale, turned by --env-rotate about +y) or a
 * constant background (--background). It is a light like any other (LIGHT_ENVIRONMENT).
 *
 * The mapping, in one place (the host builds its sampling distribution by the same rule):
 * +y is up. A world direction w is first turned by -env_rotation about +y into map space m;
 * then
 *     u = 1/2 + atan2(m.x, -m.z) / (2 pi),     v = acos(m.y) / pi,
 * with texel (x, y) = (floor(u W), floor(v H)), row 0 at the top (+y). The image centre
 * (u, v) = (1/2, 1/2) is the direction -z, the way glTF's default camera looks; u grows
 * towards +x, so the image is seen unmirrored from inside. Lookups are nearest-texel: the
 * radiance is exactly the piecewise-constant function the sampling distribution follows.
 *
 * Sampling: a piecewise-constant 2D distribution proportional to luminance x sin(theta) of
 * the texel centre row: the marginal CDF over rows, then one conditional CDF per row, found
 * by binary search. env_cdf holds [H + 1 marginal | H x (W + 1) conditional] values, each
 * CDF starting at 0 and ending at exactly 1. Each texel's .w is its density in (u, v),
 * pdf_uv; in solid angle pdf_w = pdf_uv / (2 pi^2 sin(theta)). The constant background is
 * sampled uniformly over the sphere, pdf_w = 1 / (4 pi). */
#ifndef CLPT_LIGHT_ENVIRONMENT_CL
#define CLPT_LIGHT_ENVIRONMENT_CL

#include "core/math.cl"
#include "core/scene_view.cl"
#include "core/warp.cl"

/* Rotation of w by `angle` radians about +y (right-handed: +z turns towards +x). */
static inline float3 env_rotate_y(float3 w, float angle) {
  const float c = cos(angle), s = sin(angle);
  return (float3)(c * w.x + s * w.z, w.y, -s * w.x + c * w.z);
}

static inline float2 env_dir_to_uv(float3 m) {
  float u = 0.5f + atan2(m.x, -m.z) * (0.5f * INV_PI_F);
  u = u - floor(u);
  const float v = acos(clamp(m.y, -1.0f, 1.0f)) * INV_PI_F;
  return (float2)(fmin(u, 0x1.fffffep-1f), fmin(v, 0x1.fffffep-1f));
}

static inline float3 env_uv_to_dir(float2 uv) {
  const float2 theta = cos_sin_turns(0.5f * uv.y), alpha = cos_sin_turns(uv.x - 0.5f);
  return (float3)(theta.y * alpha.y, theta.x, -theta.y * alpha.x);
}

static inline u32 env_texel(const SceneView* s, float2 uv) {
  const u32 w = s->info->env_width, h = s->info->env_height;
  const u32 x = min((u32)(uv.x * (float)w), w - 1u), y = min((u32)(uv.y * (float)h), h - 1u);
  return y * w + x;
}

/* Whether the scene has a non-black environment (then it is light s->info->env_light). */
static inline bool env_present(const SceneView* s) { return s->info && s->info->env_light != ~0u; }

/* Radiance arriving along -w, i.e. seen looking in direction w (black without environment). */
static inline float3 env_radiance(const SceneView* s, float3 w) {
  if (!s->info) return (float3)(0.0f);
  if (s->info->env_width == 0u) return vload3(0, s->info->background);
  const float3 m = env_rotate_y(w, -s->info->env_rotation);
  return s->env_texels[env_texel(s, env_dir_to_uv(m))].xyz * s->info->env_scale;
}

/* Solid-angle density of env_sample_w for direction w (selection not included). */
static inline float env_pdf_w(const SceneView* s, float3 w) {
  if (s->info->env_width == 0u) return warp_uniform_sphere_pdf();
  const float3 m = env_rotate_y(w, -s->info->env_rotation);
  /* From the horizontal component: sqrt(1 - y^2) rounds to 0 near the poles. */
  const float sin_theta = sqrt(m.x * m.x + m.z * m.z);
  if (!(sin_theta > 0.0f)) return 0.0f;
  const float pdf_uv = s->env_texels[env_texel(s, env_dir_to_uv(m))].w;
  return pdf_uv / (2.0f * PI_F * PI_F * sin_theta);
}

/* A direction towards the environment with density *pdf_w (selection not included). */
static inline float3 env_sample_w(const SceneView* s, float2 u, float* pdf_w) {
  if (s->info->env_width == 0u) {
    *pdf_w = warp_uniform_sphere_pdf();
    return warp_uniform_sphere(u);
  }
  const u32 w = s->info->env_width, h = s->info->env_height;
  __global const float* marginal = s->env_cdf;
  const u32 y = cdf_find_interval(marginal, h, u.y);
  const float dy = (u.y - marginal[y]) / (marginal[y + 1u] - marginal[y]);
  __global const float* row = s->env_cdf + (h + 1u) + y * (w + 1u);
  const u32 x = cdf_find_interval(row, w, u.x);
  const float dx = (u.x - row[x]) / (row[x + 1u] - row[x]);
  const float2 uv = (float2)(((float)x + clamp(dx, 0.0f, 0x1.fffffep-1f)) / (float)w,
                             ((float)y + clamp(dy, 0.0f, 0x1.fffffep-1f)) / (float)h);
  const float3 wi = env_rotate_y(env_uv_to_dir(uv), s->info->env_rotation);
  /* The density looked up from the direction, as env_pdf_w does, so that the two agree
   * exactly even where rounding moves a sample across a texel edge. */
  *pdf_w = env_pdf_w(s, wi);
  return wi;
}

#endif
