/* Thin wrappers around kernels/light/light.cl for tests/light_test.cpp. Every kernel takes
 * the scene arguments first (SceneBuffers::bind), then its own. Random numbers: SplitMix64 as
 * in warp_test.cl, in the open interval (0, 1). */
#include "bvh/intersect.cl"
#include "light/light.cl"

inline float test_random(uint seed, uint i, uint k) {
  ulong z = ((ulong)seed << 32) + ((ulong)i * 4ul + (ulong)k + 1ul) * 0x9e3779b97f4a7c15ul;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ul;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebul;
  z ^= z >> 31;
  return ((float)(uint)(z >> 41) + 0.5f) * 0x1.0p-23f;
}

/* light_illuminate's density for direction w from p, found the way the path tracer finds it:
 * the closest hit along w (an emitter: light_pdf_w), or the environment when w escapes. */
inline float pdf_by_tracing(const SceneView* s, float3 p, float3 w) {
  Hit hit;
  if (intersect_closest(s, p, w, INFINITY, &hit)) {
    float3 p0, p1, p2;
    triangle_vertices(s, hit.triangle, &p0, &p1, &p2);
    const float3 ng = safe_normal(cross(p1 - p0, p2 - p0));
    return light_pdf_w(s, hit.triangle, hit.t, fabs(dot(ng, w)));
  }
  return light_env_pdf_w(s, w);
}

/* NEE samples from p: out_dir = (wi, pdf_w), out_le = (Le, selected light index),
 * out_check.x = the same light's density for wi found independently (light_pdf_w after a
 * traced hit of that light's triangle, light_env_pdf_w for the environment; -1 for delta
 * lights and for a triangle sample whose ray hits another triangle first). */
__kernel void light_illuminate_samples(SCENE_KERNEL_ARGS float4 p4, uint seed,
                                       __global float4* out_dir, __global float4* out_le,
                                       __global float* out_check, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const SceneView s = SCENE_VIEW();
  const float3 p = p4.xyz;
  const float u_sel = test_random(seed, i, 0);
  const float2 u = (float2)(test_random(seed, i, 1), test_random(seed, i, 2));
  const LightSample ls = light_illuminate(&s, p, u_sel, u);
  const u32 li = light_select(&s, u_sel);
  out_dir[i] = (float4)(ls.wi, ls.pdf_w);
  out_le[i] = (float4)(ls.Le, (float)li);
  float check = -1.0f;
  const __global Light* l = &s.lights[li];
  if (l->type == LIGHT_ENVIRONMENT) {
    check = light_env_pdf_w(&s, ls.wi);
  } else if (l->type == LIGHT_TRIANGLE) {
    Hit hit;
    if (intersect_closest(&s, p, ls.wi, INFINITY, &hit) && hit.triangle == l->triangle) {
      float3 p0, p1, p2;
      triangle_vertices(&s, hit.triangle, &p0, &p1, &p2);
      const float3 ng = safe_normal(cross(p1 - p0, p2 - p0));
      check = light_pdf_w(&s, hit.triangle, hit.t, fabs(dot(ng, ls.wi)));
    }
  }
  out_check[i] = check;
}

/* The density of light_illuminate from p at each direction (for the chi-square grid). */
__kernel void light_pdf_at(SCENE_KERNEL_ARGS float4 p4, __global const float4* dirs,
                           __global float* out, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const SceneView s = SCENE_VIEW();
  out[i] = pdf_by_tracing(&s, p4.xyz, normalize(dirs[i].xyz));
}

/* Emitted rays: out = (Le * cos_light / (pdf_a * pdf_w * pdf_select) as RGB, light index),
 * whose mean over the samples of light i is light i's radiant power. out_ray = (dir, 0). */
__kernel void light_emit_samples(SCENE_KERNEL_ARGS uint seed, __global float4* out,
                                 __global float4* out_dir, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const SceneView s = SCENE_VIEW();
  const float u_sel = test_random(seed, i, 0);
  const float2 u_pos = (float2)(test_random(seed, i, 1), test_random(seed, i, 2));
  const float2 u_dir = (float2)(test_random(seed, i, 3), test_random(seed ^ 0x5bd1e995u, i, 0));
  const LightEmission e = light_emit(&s, u_sel, u_pos, u_dir);
  const float denom = e.pdf_a * e.pdf_w * e.pdf_select;
  const float3 v = denom > 0.0f ? e.Le * e.cos_light / denom : (float3)(0.0f);
  out[i] = (float4)(v, (float)light_select(&s, u_sel));
  out_dir[i] = (float4)(e.dir, 0.0f);
}

/* env_radiance for a batch of directions (tests of the mapping). */
__kernel void env_radiance_at(SCENE_KERNEL_ARGS __global const float4* dirs,
                              __global float4* out, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const SceneView s = SCENE_VIEW();
  out[i] = (float4)(env_radiance(&s, dirs[i].xyz), 0.0f);
}
