/* Warps from [0,1)^2 to directions and points, each with its density. */
#ifndef CLPT_CORE_WARP_CL
#define CLPT_CORE_WARP_CL

#include "core/math.cl"

/* Concentric disk mapping (Shirley & Chiu 1997). */
inline float2 warp_concentric_disk(float2 u) {
  const float2 o = 2.0f * u - (float2)(1.0f, 1.0f);
  if (o.x == 0.0f && o.y == 0.0f) return (float2)(0.0f, 0.0f);
  float r, theta;
  if (fabs(o.x) > fabs(o.y)) {
    r = o.x;
    theta = (PI_F / 4.0f) * (o.y / o.x);
  } else {
    r = o.y;
    theta = (PI_F / 2.0f) - (PI_F / 4.0f) * (o.x / o.y);
  }
  return r * (float2)(cos(theta), sin(theta));
}

/* Cosine-weighted hemisphere around +z (Malley's method); pdf_w = cos(theta) / pi. */
inline float3 warp_cosine_hemisphere(float2 u) {
  const float2 d = warp_concentric_disk(u);
  const float z = sqrt(fmax(0.0f, 1.0f - d.x * d.x - d.y * d.y));
  return (float3)(d.x, d.y, z);
}

inline float warp_cosine_hemisphere_pdf(float cos_theta) {
  return cos_theta > 0.0f ? cos_theta * INV_PI_F : 0.0f;
}

/* Uniform point on a triangle as barycentrics (b1, b2) of vertices 1 and 2; pdf_a = 1/area. */
inline float2 warp_uniform_triangle(float2 u) {
  const float su = sqrt(u.x);
  return (float2)(su * (1.0f - u.y), su * u.y);
}

#endif
