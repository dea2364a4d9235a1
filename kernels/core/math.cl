/* Small math helpers shared by all device code. */
#ifndef CLPT_CORE_MATH_CL
#define CLPT_CORE_MATH_CL

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

static inline float max_component(float3 v) { return fmax(v.x, fmax(v.y, v.z)); }

static inline float luminance(float3 c) { return dot(c, (float3)(0.2126f, 0.7152f, 0.0722f)); }

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
