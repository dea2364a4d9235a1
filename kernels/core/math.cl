/* Small math helpers shared by all device code. */
#ifndef CLPT_CORE_MATH_CL
#define CLPT_CORE_MATH_CL

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
