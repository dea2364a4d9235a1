/* Small math helpers shared by all device code. */
#ifndef CLPT_CORE_MATH_CL
#define CLPT_CORE_MATH_CL

#include "shared/luminance.h"

/* A large function called from many places stays out of line. NVIDIA's OpenCL compiler
 * inlines every call it may, so each call site of such a function is a copy of it in the
 * kernel, and the driver's build time grows with the copies: thin_film_reflectance alone
 * doubled pt's PTX (kernel_compile_check.py --targets nvinline; docs/BENCHMARKS.md). A call
 * costs its arguments' trip through the stack, so what is cheap and common stays inline in
 * front of it (the glTF BSDF's Lambertian shortcuts before its layered lobes), and each use
 * is measured on PoCL. -DCLPT_NO_NOINLINE inlines everything again. */
#ifndef CLPT_NO_NOINLINE
#define CLPT_NOINLINE static __attribute__((noinline))
#else
#define CLPT_NOINLINE static
#endif

#define PI_F 3.14159265358979323846f
#define INV_PI_F 0.31830988618379067154f

/* (cos, sin) of 2 pi t, t in turns, for |t| < 2^20: what the samplers' azimuths need
 * (phi = 2 pi u) at a fraction of the built-in sin and cos's cost, which reduce any argument
 * (PoCL's general reduction was 4 % of a Cornell box render and 6.5 % of photon tracing,
 * `perf`; docs/BENCHMARKS.md). In turns the reduction is exact: q = rint(4t) picks the
 * quadrant and r = t - q / 4 in [-1/8, 1/8] has no rounding error (4t is exact, and 4t - q
 * by Sterbenz's lemma), so the only error is the polynomials': the Taylor series of sin and
 * cos of 2 pi r to r^9 and r^10, whose first dropped terms are below 2e-9 there. Measured
 * against double precision over [-1/8, 1/8]: within 1.7 ulp (sin) and 7.4e-8 (cos);
 * tests/warp_test.cpp (WarpTrig) checks four periods. */
static inline float2 cos_sin_turns(float t) {
  const float q = rint(4.0f * t);
  const float r = (4.0f * t - q) * 0.25f;
  const float r2 = r * r;
  const float s =
      r * (6.2831854820f +
           r2 * (-41.341701507f + r2 * (81.605247497f + r2 * (-76.705856323f + r2 * 42.058692932f))));
  const float c =
      1.0f + r2 * (-19.739208221f +
                   r2 * (64.939392090f + r2 * (-85.456817627f + r2 * (60.244640350f + r2 * -26.426256180f))));
  switch ((int)q & 3) {
    case 0: return (float2)(c, s);
    case 1: return (float2)(-s, c);
    case 2: return (float2)(-c, -s);
    default: return (float2)(s, -c);
  }
}

/* ln x for a positive normal float x, at a fraction of the built-in log's cost (PoCL calls
 * SLEEF's logf out of line: 9 % of an mmlt render, whose small steps draw a Gaussian per
 * coordinate; docs/BENCHMARKS.md). x = 2^e (1 + f) with 1 + f in [sqrt(1/2), sqrt(2)), and
 * ln(1 + f) = 2 atanh(s), s = f / (2 + f), |s| <= 0.1716, whose series' terms past s^9 are below
 * 7e-10; the series is summed as f - (f^2 / 2 - s (f^2 / 2 + R)), R its terms from s^3 on
 * (fdlibm's arrangement), so that near x = 1 the error stays a fraction of f's last bit.
 * tests/warp_test.cpp (WarpLog) measures it against double precision. Subnormals, zero,
 * infinities and NaN are outside its domain. */
static inline float ln_positive(float x) {
  const uint bits = as_uint(x);
  int e = (int)(bits >> 23) - 127;
  float m = as_float((bits & 0x007fffffu) | 0x3f800000u);
  if (m > 1.41421356f) {
    m *= 0.5f;
    e += 1;
  }
  const float f = m - 1.0f, s = f / (2.0f + f), z = s * s;
  const float R = z * (0.666666667f + z * (0.4f + z * (0.285714286f + z * 0.222222222f)));
  const float hfsq = 0.5f * f * f;
  return (float)e * 0.693147181f + (f - (hfsq - s * (hfsq + R)));
}

static inline float max_component(float3 v) { return fmax(v.x, fmax(v.y, v.z)); }

static inline float luminance(float3 c) {
  return dot(c, (float3)(CLPT_LUMINANCE_R, CLPT_LUMINANCE_G, CLPT_LUMINANCE_B));
}

static inline bool is_black(float3 c) { return c.x <= 0.0f && c.y <= 0.0f && c.z <= 0.0f; }

static inline bool is_finite3(float3 c) { return isfinite(c.x) && isfinite(c.y) && isfinite(c.z); }

/* An orthonormal basis around unit n (Duff et al. 2017, "Building an Orthonormal Basis,
 * Revisited"). */
static inline void make_basis(float3 n, float3* t, float3* b) {
  const float sign = copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  *t = (float3)(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
  *b = (float3)(c, sign + n.y * n.y * a, -n.y);
}

static inline float3 to_world(float3 v, float3 n) {
  float3 t, b;
  make_basis(n, &t, &b);
  return v.x * t + v.y * b + v.z * n;
}

#endif
