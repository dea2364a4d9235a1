/* Spawning rays from surfaces without hitting the surface they leave. */
#ifndef CLPT_CORE_RAY_CL
#define CLPT_CORE_RAY_CL

/* Moves a surface point p off its surface along the geometric normal ng, which the caller
 * orients to the side the new ray leaves from (ng for reflection off the front, -ng for
 * transmission or rays leaving the back). ng should be unit length.
 *
 * After C. Wächter and N. Binder, "A Fast and Robust Method for Avoiding Self-Intersection",
 * Ray Tracing Gems (2019), chapter 6: the offset is a fixed number of units in the last
 * place of each coordinate (int_scale * ng, applied to the float's integer representation),
 * so it scales with the magnitude of p and with the rounding error of the hit point
 * computed from barycentrics. Near the origin, where ulps become tiny and the error of the
 * hit point is dominated by the triangle's vertices rather than by p, a small absolute
 * offset (float_scale * ng) is used instead. The new ray then starts at t = 0 with no
 * epsilon of its own.
 *
 * float_scale is 2^-28, not the paper's 2^-16: the paper's constant assumes scenes of about
 * unit size, and its 1.5e-5 absolute step darkened small scenes (the Cornell box scaled to
 * 11 cm rendered 8 % too dark, at 1 mm 22 %: tests/robustness_test.cpp ScaleInvariance).
 * A smaller step is safe here because intersect_triangle also rejects any t within its
 * rounding-error bound (kernels/bvh/intersect.cl), which is what keeps large triangles from
 * re-hitting themselves (Reintersect.*). */
static inline float3 offset_ray_origin(float3 p, float3 ng) {
  const float origin = 1.0f / 32.0f;
  const float float_scale = 1.0f / 268435456.0f; /* 2^-28: see above */
  const float int_scale = 256.0f;

  const int3 of_i = convert_int3(int_scale * ng); /* truncates toward zero, as in the paper */
  /* Adding to the integer representation moves away from zero; a negative coordinate moves
   * along the normal by subtracting. */
  const int3 signed_of = select(of_i, -of_i, isless(p, (float3)(0.0f)));
  const float3 p_i = as_float3(as_int3(p) + signed_of);
  return select(p_i, p + float_scale * ng, isless(fabs(p), (float3)(origin)));
}

/* The origin of a ray leaving surface point p in direction w: p offset along the geometric
 * normal ng turned to w's side (a reflected ray leaves on the side it arrived from, a
 * transmitted one on the other). */
static inline float3 offset_ray_origin_towards(float3 p, float3 ng, float3 w) {
  return offset_ray_origin(p, dot(w, ng) >= 0.0f ? ng : -ng);
}

#endif
