/* Warps from [0,1)^2 to directions and points, as sample / pdf / invert triples:
 *   warp_X(u, ...)         maps u in [0,1)^2 to a direction or point,
 *   warp_X_pdf(...)        its density: per steradian for directions, per unit area of the
 *                          warp's own plane for points; 0 off the support,
 *   warp_X_invert(p, ...)  the u that maps to p, for p on the support (u in [0,1]^2).
 * Directions are unit vectors in a local frame with +z the pole (the normal); the
 * azimuth phi = 2 pi u.y runs counter-clockwise from +x.
 * tests/warp_test.cpp checks each triple: chi-square of the samples against the pdf, the
 * pdf integrates to 1, and sample -> invert -> sample round trips. */
#ifndef CLPT_CORE_WARP_CL
#define CLPT_CORE_WARP_CL

#include "core/math.cl"
#include "shared/compat.h"

/* The azimuth of (x, y) as u.y in [0, 1). */
static inline float warp_azimuth_invert(float y, float x) {
  float t = atan2(y, x) * (0.5f * INV_PI_F);
  if (t < 0.0f) t += 1.0f;
  return fmin(t, 0x1.fffffep-1f); /* -tiny + 1 rounds to 1 */
}

/* ---- Disks: points of the unit disk, pdf_a = 1 / pi ------------------------------------ */

/* Concentric disk mapping (Shirley & Chiu 1997): squares to rings, low distortion. */
static inline float2 warp_concentric_disk(float2 u) {
  const float2 o = 2.0f * u - (float2)(1.0f, 1.0f);
  if (o.x == 0.0f && o.y == 0.0f) return (float2)(0.0f, 0.0f);
  float r, turns; /* the angle theta in turns */
  if (fabs(o.x) > fabs(o.y)) {
    r = o.x;
    turns = 0.125f * (o.y / o.x);
  } else {
    r = o.y;
    turns = 0.25f - 0.125f * (o.x / o.y);
  }
  return r * cos_sin_turns(turns);
}

static inline float warp_concentric_disk_pdf(float2 p) {
  return dot(p, p) <= 1.0f ? INV_PI_F : 0.0f;
}

/* The forward map sends the square's four wedges (right, top, left, bottom of
 * o = 2u - 1, split by its diagonals) to the quarter-disks centred on phi = 0, pi/2, pi and
 * 3 pi/2; undo that from phi in [-pi/4, 7 pi/4). */
static inline float2 warp_concentric_disk_invert(float2 p) {
  const float r = length(p);
  float phi = atan2(p.y, p.x);
  if (phi < -PI_F / 4.0f) phi += 2.0f * PI_F;
  const float k = 4.0f / PI_F;
  float2 o;
  if (phi < PI_F / 4.0f) {
    o = (float2)(r, r * phi * k);
  } else if (phi < 3.0f * PI_F / 4.0f) {
    o = (float2)(r * (2.0f - phi * k), r);
  } else if (phi < 5.0f * PI_F / 4.0f) {
    o = (float2)(-r, -r * (phi - PI_F) * k);
  } else {
    o = (float2)(-r * (2.0f - (phi - PI_F) * k), -r);
  }
  return clamp(0.5f * (o + (float2)(1.0f, 1.0f)), 0.0f, 1.0f);
}

/* Polar map r = sqrt(u.x), phi = 2 pi u.y: simple, but stretches the square near the centre. */
static inline float2 warp_uniform_disk(float2 u) {
  return sqrt(u.x) * cos_sin_turns(u.y);
}

static inline float warp_uniform_disk_pdf(float2 p) { return dot(p, p) <= 1.0f ? INV_PI_F : 0.0f; }

static inline float2 warp_uniform_disk_invert(float2 p) {
  return (float2)(fmin(dot(p, p), 1.0f), warp_azimuth_invert(p.y, p.x));
}

/* ---- Directions ---------------------------------------------------------------------- */

/* Uniform hemisphere around +z: cos(theta) = u.x; pdf_w = 1 / (2 pi). */
static inline float3 warp_uniform_hemisphere(float2 u) {
  const float z = u.x;
  const float r = sqrt(fmax(0.0f, (1.0f - z) * (1.0f + z)));
  return (float3)(r * cos_sin_turns(u.y), z);
}

static inline float warp_uniform_hemisphere_pdf(float cos_theta) {
  return cos_theta >= 0.0f ? 0.5f * INV_PI_F : 0.0f;
}

static inline float2 warp_uniform_hemisphere_invert(float3 w) {
  return (float2)(clamp(w.z, 0.0f, 1.0f), warp_azimuth_invert(w.y, w.x));
}

/* Cosine-weighted hemisphere around +z (Malley's method: the concentric disk lifted onto
 * the hemisphere); pdf_w = cos(theta) / pi. */
static inline float3 warp_cosine_hemisphere(float2 u) {
  const float2 d = warp_concentric_disk(u);
  const float z = sqrt(fmax(0.0f, 1.0f - d.x * d.x - d.y * d.y));
  return (float3)(d.x, d.y, z);
}

static inline float warp_cosine_hemisphere_pdf(float cos_theta) {
  return cos_theta > 0.0f ? cos_theta * INV_PI_F : 0.0f;
}

static inline float2 warp_cosine_hemisphere_invert(float3 w) {
  return warp_concentric_disk_invert(w.xy);
}

/* Uniform sphere: cos(theta) = 1 - 2 u.x; pdf_w = 1 / (4 pi). sin(theta) is taken as
 * 2 sqrt(u.x (1 - u.x)), exact near the poles where 1 - z^2 cancels. */
static inline float3 warp_uniform_sphere(float2 u) {
  const float z = 1.0f - 2.0f * u.x;
  const float r = 2.0f * sqrt(fmax(0.0f, u.x * (1.0f - u.x)));
  return (float3)(r * cos_sin_turns(u.y), z);
}

static inline float warp_uniform_sphere_pdf(void) { return 0.25f * INV_PI_F; }

static inline float2 warp_uniform_sphere_invert(float3 w) {
  return (float2)(clamp(0.5f * (1.0f - w.z), 0.0f, 1.0f), warp_azimuth_invert(w.y, w.x));
}

/* Uniform cone of directions around +z with cos(theta) >= cos_theta_max (< 1): cos(theta)
 * falls linearly from 1 to cos_theta_max as u.x goes from 0 to 1; pdf_w = 1 / (2 pi (1 -
 * cos_theta_max)). 1 - cos(theta) is carried without cancellation for narrow cones. */
static inline float3 warp_uniform_cone(float2 u, float cos_theta_max) {
  const float one_minus_cos = u.x * (1.0f - cos_theta_max);
  const float cos_theta = fmax(1.0f - one_minus_cos, cos_theta_max);
  const float sin_theta = sqrt(fmax(0.0f, one_minus_cos * (2.0f - one_minus_cos)));
  return (float3)(sin_theta * cos_sin_turns(u.y), cos_theta);
}

static inline float warp_uniform_cone_pdf(float cos_theta, float cos_theta_max) {
  return cos_theta >= cos_theta_max ? 0.5f * INV_PI_F / (1.0f - cos_theta_max) : 0.0f;
}

static inline float2 warp_uniform_cone_invert(float3 w, float cos_theta_max) {
  /* 1 - cos = sin^2 / (1 + cos) near the pole, where 1 - w.z loses the digits. */
  const float one_minus_cos =
      w.z > 0.0f ? (w.x * w.x + w.y * w.y) / (1.0f + w.z) : 1.0f - w.z;
  return (float2)(clamp(one_minus_cos / (1.0f - cos_theta_max), 0.0f, 1.0f),
                  warp_azimuth_invert(w.y, w.x));
}

/* ---- Triangle ------------------------------------------------------------------------ */

/* Uniform point on a triangle as barycentrics (b1, b2) of vertices 1 and 2:
 * s = b1 + b2 = sqrt(u.x), b2 / s = u.y. pdf = 2 over the (b1, b2) plane, which is
 * pdf_a = 1 / area on a triangle of that area. */
static inline float2 warp_uniform_triangle(float2 u) {
  const float su = sqrt(u.x);
  return (float2)(su * (1.0f - u.y), su * u.y);
}

static inline float warp_uniform_triangle_pdf(float2 b) {
  return (b.x >= 0.0f && b.y >= 0.0f && b.x + b.y <= 1.0f) ? 2.0f : 0.0f;
}

static inline float2 warp_uniform_triangle_invert(float2 b) {
  const float s = b.x + b.y;
  return (float2)(fmin(s * s, 1.0f), s > 0.0f ? clamp(b.y / s, 0.0f, 1.0f) : 0.0f);
}

/* ---- Discrete distributions ------------------------------------------------------------ */

/* The interval i of a CDF of n intervals (n + 1 values, cdf[0] = 0, cdf[n] = 1) with
 * cdf[i] <= u < cdf[i + 1]: never an interval of zero probability. */
static inline u32 cdf_find_interval(__global const float* cdf, u32 n, float u) {
  u32 lo = 0u, hi = n;
  while (lo + 1u < hi) {
    const u32 mid = (lo + hi) >> 1;
    if (cdf[mid] <= u) lo = mid;
    else hi = mid;
  }
  return lo;
}

#endif
