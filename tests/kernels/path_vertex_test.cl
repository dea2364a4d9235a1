/* tests/path_vertex_test.cpp: a SurfaceHit stored into a PathVertex and read back
 * (kernels/integrators/stages/path_vertex.cl), for every field the BSDF and the connection
 * code read. in[i]: 36 floats per item (base colour[3], specular colour[3], metallic,
 * roughness, specular, transmission, ior, clearcoat, clearcoat roughness, material as a float,
 * front, unused, iridescence, its ior and thickness, diffuse transmission, its colour[3],
 * sheen colour[3], sheen roughness, anisotropy direction[3] and strength, unused, the
 * clearcoat's normal[3], unused), each BSDF input rounded by bsdf_unorm16 or
 * bsdf_unorm8 where material_resolve rounds it; out[i]: the same 36 read back from the stored
 * vertex (15: flipped; the rounded ones as the difference from what was stored). */
#include "integrators/stages/path_vertex.cl"

__kernel void path_vertex_round_trip(__global const float* in, __global PathVertex* vertices,
                                     __global float* out, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  __global const float* c = in + 36 * i;
  SurfaceHit sh;
  sh.p = (float3)(1.0f, 2.0f, 3.0f);
  sh.ng = sh.ns = (float3)(0.0f, 0.0f, 1.0f);
  sh.bsdf.base_color = (float3)(c[0], c[1], c[2]);
  sh.bsdf.specular_color = (float3)(c[3], c[4], c[5]);
  sh.bsdf.metallic = c[6];
  sh.bsdf.roughness = c[7];
  sh.bsdf.specular = c[8];
  sh.bsdf.transmission = c[9];
  sh.bsdf.ior = c[10];
  sh.bsdf.clearcoat = bsdf_unorm16(c[11]);
  sh.bsdf.clearcoat_roughness = bsdf_unorm16(c[12]);
  sh.bsdf.iridescence = c[16];
  sh.bsdf.iridescence_ior = c[17];
  sh.bsdf.iridescence_thickness = c[18];
  sh.bsdf.diffuse_transmission = c[19];
  sh.bsdf.diffuse_transmission_color = (float3)(c[20], c[21], c[22]);
  sh.bsdf.sheen_color = (float3)(bsdf_unorm8(c[23]), bsdf_unorm8(c[24]), bsdf_unorm8(c[25]));
  sh.bsdf.sheen_roughness = bsdf_unorm8(c[26]);
  sh.bsdf.anisotropy_t = (float3)(c[27], c[28], c[29]);
  sh.bsdf.anisotropy = c[30];
  sh.bsdf.clearcoat_n = (float3)(c[32], c[33], c[34]);
  sh.material = (u32)c[13];
  sh.front = (u32)c[14];
  SubpathState st;
  st.beta = (float3)(1.0f);
  st.dvcm = st.dvc = st.dvm = 0.0f;
  path_vertex_store(&vertices[i], &sh, (float3)(0.0f, 0.0f, 1.0f), &st, 1u);
  const SurfaceHit r = path_vertex_surface(&vertices[i]);
  __global float* o = out + 36 * i;
  o[0] = r.bsdf.base_color.x, o[1] = r.bsdf.base_color.y, o[2] = r.bsdf.base_color.z;
  o[3] = r.bsdf.specular_color.x, o[4] = r.bsdf.specular_color.y, o[5] = r.bsdf.specular_color.z;
  o[6] = r.bsdf.metallic, o[7] = r.bsdf.roughness, o[8] = r.bsdf.specular;
  o[9] = r.bsdf.transmission, o[10] = r.bsdf.ior;
  o[11] = r.bsdf.clearcoat - sh.bsdf.clearcoat;  /* 0: stored exactly */
  o[12] = r.bsdf.clearcoat_roughness - sh.bsdf.clearcoat_roughness;
  o[13] = (float)r.material, o[14] = (float)r.front, o[15] = (float)r.flipped;
  o[16] = r.bsdf.iridescence, o[17] = r.bsdf.iridescence_ior, o[18] = r.bsdf.iridescence_thickness;
  o[19] = r.bsdf.diffuse_transmission;
  o[20] = r.bsdf.diffuse_transmission_color.x, o[21] = r.bsdf.diffuse_transmission_color.y;
  o[22] = r.bsdf.diffuse_transmission_color.z;
  o[23] = r.bsdf.sheen_color.x - sh.bsdf.sheen_color.x; /* 0: stored exactly */
  o[24] = r.bsdf.sheen_color.y - sh.bsdf.sheen_color.y;
  o[25] = r.bsdf.sheen_color.z - sh.bsdf.sheen_color.z;
  o[26] = r.bsdf.sheen_roughness - sh.bsdf.sheen_roughness;
  o[27] = r.bsdf.anisotropy_t.x, o[28] = r.bsdf.anisotropy_t.y, o[29] = r.bsdf.anisotropy_t.z;
  o[30] = r.bsdf.anisotropy, o[31] = 0.0f;
  o[32] = r.bsdf.clearcoat_n.x, o[33] = r.bsdf.clearcoat_n.y, o[34] = r.bsdf.clearcoat_n.z;
  o[35] = 0.0f;
}
