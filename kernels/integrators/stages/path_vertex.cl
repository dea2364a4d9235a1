/* Light vertices between BDPT's two kernels: a SurfaceHit's BSDF-relevant part and the
 * subpath state at it, packed into a PathVertex (kernels/shared/bdpt_types.h). */
#ifndef CLPT_INTEGRATORS_BDPT_PATH_VERTEX_CL
#define CLPT_INTEGRATORS_BDPT_PATH_VERTEX_CL

#include "geometry/surface.cl"
#include "shared/bdpt_types.h"

/* The state of a subpath being traced (Georgiev 2012, SmallVCM's SubPathState). */
typedef struct SubpathState {
  float3 beta;    /* throughput */
  float dvcm;     /* dVCM: the reverse pdf ratios of the strategies that end here */
  float dvc;      /* dVC: the partial sum for vertex connection */
  float dvm;      /* dVM: the partial sum for vertex merging (vcm) */
} SubpathState;

static inline void path_vertex_store(__global PathVertex* v, const SurfaceHit* sh, float3 wo,
                                     const SubpathState* st, u32 depth) {
  vstore3(sh->p, 0, v->p);
  vstore3(sh->ng, 0, v->ng);
  vstore3(sh->ns, 0, v->ns);
  vstore3(wo, 0, v->wo);
  vstore3(st->beta, 0, v->beta);
  vstore3(sh->bsdf.base_color, 0, v->base_color);
  vstore3(sh->bsdf.specular_color, 0, v->specular_color);
  v->metallic = sh->bsdf.metallic;
  v->roughness = sh->bsdf.roughness;
  v->specular = sh->bsdf.specular;
  v->transmission = sh->bsdf.transmission;
  v->ior = sh->bsdf.ior;
  v->clearcoat = bsdf_unorm16_bits(sh->bsdf.clearcoat) | bsdf_unorm16_bits(sh->bsdf.clearcoat_roughness) << 16;
  v->dvcm = st->dvcm;
  v->dvc = st->dvc;
  v->dvm = st->dvm;
  v->depth = depth;
  v->material = (sh->material & 0x7fffffffu) | (sh->front ? 0x80000000u : 0u);
  v->iridescence = sh->bsdf.iridescence;
  v->iridescence_ior = sh->bsdf.iridescence_ior;
  v->iridescence_thickness = sh->bsdf.iridescence_thickness;
  v->diffuse_transmission = sh->bsdf.diffuse_transmission;
  vstore3(sh->bsdf.diffuse_transmission_color, 0, v->diffuse_transmission_color);
  v->sheen = bsdf_unorm8_bits(sh->bsdf.sheen_color.x) | bsdf_unorm8_bits(sh->bsdf.sheen_color.y) << 8 |
             bsdf_unorm8_bits(sh->bsdf.sheen_color.z) << 16 | bsdf_unorm8_bits(sh->bsdf.sheen_roughness) << 24;
  vstore3(sh->bsdf.anisotropy_t, 0, v->anisotropy_t);
  v->anisotropy = sh->bsdf.anisotropy;
  vstore3(sh->bsdf.clearcoat_n, 0, v->clearcoat_n);
  v->pad = 0u;
}

/* The subpath state stored with a vertex. */
static inline SubpathState path_vertex_state(__global const PathVertex* v) {
  SubpathState st;
  st.beta = vload3(0, v->beta);
  st.dvcm = v->dvcm;
  st.dvc = v->dvc;
  st.dvm = v->dvm;
  return st;
}

/* The SurfaceHit a stored vertex stands for: enough for bsdf_eval_cos, bsdf_pdf_w and
 * volume_transmittance (no uv, colour or tangent: the BSDF was resolved when stored). */
static inline SurfaceHit path_vertex_surface(__global const PathVertex* v) {
  SurfaceHit sh;
  sh.p = vload3(0, v->p);
  sh.ng = vload3(0, v->ng);
  sh.ns = vload3(0, v->ns);
  sh.uv = (float2)(0.0f);
  sh.uv1 = (float2)(0.0f);
  sh.color = (float4)(1.0f);
  sh.tangent = (float4)(0.0f);
  sh.tex_lod = (float2)(-INFINITY);
  sh.triangle = 0u;
  sh.material = v->material & 0x7fffffffu;
  sh.front = v->material >> 31;
  sh.flipped = sh.front ? 0u : 1u; /* stored oriented to the side the ray arrived from */
  sh.bsdf.base_color = vload3(0, v->base_color);
  sh.bsdf.specular_color = vload3(0, v->specular_color);
  sh.bsdf.metallic = v->metallic;
  sh.bsdf.roughness = v->roughness;
  sh.bsdf.specular = v->specular;
  sh.bsdf.transmission = v->transmission;
  sh.bsdf.ior = v->ior; /* a dispersive glass's index at its path's wavelength */
  sh.bsdf.dispersion = 0.0f;
  sh.bsdf.clearcoat = (float)(v->clearcoat & 0xffffu) * (1.0f / 65535.0f);
  sh.bsdf.clearcoat_roughness = (float)(v->clearcoat >> 16) * (1.0f / 65535.0f);
  sh.bsdf.iridescence = v->iridescence;
  sh.bsdf.iridescence_ior = v->iridescence_ior;
  sh.bsdf.iridescence_thickness = v->iridescence_thickness;
  sh.bsdf.diffuse_transmission = v->diffuse_transmission;
  sh.bsdf.diffuse_transmission_color = vload3(0, v->diffuse_transmission_color);
  sh.bsdf.sheen_color = (float3)((float)(v->sheen & 0xffu), (float)((v->sheen >> 8) & 0xffu),
                                 (float)((v->sheen >> 16) & 0xffu)) * (1.0f / 255.0f);
  sh.bsdf.sheen_roughness = (float)(v->sheen >> 24) * (1.0f / 255.0f);
  sh.bsdf.anisotropy_t = vload3(0, v->anisotropy_t);
  sh.bsdf.anisotropy = v->anisotropy;
  sh.bsdf.clearcoat_n = vload3(0, v->clearcoat_n);
  sh.emission = (float3)(0.0f);
  return sh;
}

#endif
