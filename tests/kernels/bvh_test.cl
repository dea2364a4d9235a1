/* Thin wrappers around bvh/intersect.cl and core/ray.cl for tests/bvh_test.cpp.
 * Rays come as float4 pairs: origin, and direction with w = tmax.
 * Hits go out as float4 (t, b1, b2, as_float(triangle)); a miss is (-1, 0, 0, as_float(~0)). */
#include "bvh/intersect.cl"
#include "core/ray.cl"

inline float4 hit_record(bool found, const Hit* h) {
  return found ? (float4)(h->t, h->b1, h->b2, as_float(h->triangle))
               : (float4)(-1.0f, 0.0f, 0.0f, as_float(0xffffffffu));
}

__kernel void bvh_closest(__global const BvhNode4* nodes, __global const Triangle* triangles,
                          __global const Vertex* vertices, __global const float* lanes,
                          __global const float4* ray_org,
                          __global const float4* ray_dir, __global float4* out, u32 n) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  const SceneView s = scene_view(nodes, triangles, vertices, lanes, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0);
  const float4 d = ray_dir[i];
  Hit h;
  const bool found = intersect_closest(&s, ray_org[i].xyz, d.xyz, d.w, &h);
  out[i] = hit_record(found, &h);
}

__kernel void bvh_any(__global const BvhNode4* nodes, __global const Triangle* triangles,
                      __global const Vertex* vertices, __global const float* lanes,
                      __global const float4* ray_org,
                      __global const float4* ray_dir, __global int* out, u32 n) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  const SceneView s = scene_view(nodes, triangles, vertices, lanes, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0);
  const float4 d = ray_dir[i];
  out[i] = intersect_any(&s, ray_org[i].xyz, d.xyz, d.w) ? 1 : 0;
}

/* Every triangle in order, the first of equal distances kept: the reference for the BVH. */
__kernel void brute_closest(__global const BvhNode4* nodes, __global const Triangle* triangles,
                            __global const Vertex* vertices, __global const float* lanes,
                            __global const float4* ray_org,
                            __global const float4* ray_dir, __global float4* out, u32 n,
                            u32 num_triangles) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  const SceneView s = scene_view(nodes, triangles, vertices, lanes, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0);
  const float4 d = ray_dir[i];
  const TriangleRay r = triangle_ray(ray_org[i].xyz, d.xyz);
  Hit h;
  h.t = d.w;
  bool found = false;
  for (u32 k = 0; k < num_triangles; ++k) {
    float t, b1, b2;
    if (intersect_triangle(&s, &r, k, h.t, &t, &b1, &b2)) {
      h.t = t;
      h.b1 = b1;
      h.b2 = b2;
      h.triangle = k;
      found = true;
    }
  }
  out[i] = hit_record(found, &h);
}

/* Spawns a ray from a point on a triangle and traces it.
 * sample: (b1, b2, cos_theta, phi): the point's barycentrics and the direction in the
 * hemisphere of the geometric normal, cos_theta < 0 meaning the back hemisphere.
 * out: (t, as_float(triangle) or ~0, cosine of the direction with the side's normal, 0). */
__kernel void spawn_and_trace(__global const BvhNode4* nodes, __global const Triangle* triangles,
                              __global const Vertex* vertices, __global const float* lanes,
                              __global const u32* tri,
                              __global const float4* sample, __global float4* out, u32 n) {
  const u32 i = get_global_id(0);
  if (i >= n) return;
  const SceneView s = scene_view(nodes, triangles, vertices, lanes, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0);
  const Triangle T = triangles[tri[i]];
  const float3 p0 = vertex_position(&s, T.v[0]), p1 = vertex_position(&s, T.v[1]),
               p2 = vertex_position(&s, T.v[2]);
  const float4 u = sample[i];
  /* The hit point as an integrator computes it, from barycentrics. */
  const float3 p = (1.0f - u.x - u.y) * p0 + u.x * p1 + u.y * p2;
  float3 ng = normalize(cross(p1 - p0, p2 - p0));
  if (u.z < 0.0f) ng = -ng;
  /* Orthonormal basis around ng (Duff et al. 2017). */
  const float sign = copysign(1.0f, ng.z);
  const float a = -1.0f / (sign + ng.z);
  const float c = ng.x * ng.y * a;
  const float3 tx = (float3)(1.0f + sign * ng.x * ng.x * a, sign * c, -sign * ng.x);
  const float3 ty = (float3)(c, sign + ng.y * ng.y * a, -ng.y);
  const float cos_t = fabs(u.z), sin_t = sqrt(fmax(0.0f, 1.0f - cos_t * cos_t));
  const float3 dir = sin_t * cos(u.w) * tx + sin_t * sin(u.w) * ty + cos_t * ng;

  const float3 org = offset_ray_origin(p, ng);
  Hit h;
  const bool found = intersect_closest(&s, org, dir, INFINITY, &h);
  out[i] = (float4)(found ? h.t : -1.0f, as_float(found ? h.triangle : 0xffffffffu),
                    dot(dir, ng), 0.0f);
}
