/* What bidirectional path tracing keeps of a light subpath between its two kernels
 * (kernels/integrators/bdpt.cl): one PathVertex per stored light vertex, a fixed number of
 * slots per light path (BdptParams.light_vertex_capacity). Plain floats, so the host
 * knows its size (192 bytes) for the buffer it allocates. */
#ifndef CLPT_SHARED_BDPT_TYPES_H
#define CLPT_SHARED_BDPT_TYPES_H

#include "shared/compat.h"

CLPT_BEGIN_SHARED

#define BDPT_ALL_STRATEGIES 0xffffffffu

/* bdpt's own parameters (--integrator bdpt, kernels/integrators/bdpt.cl), written by the host
 * (host/integrators/bdpt.cpp) beside the common RenderParams. */
typedef struct BdptParams {
  u32 strategy_s;            /* --bdpt-strategy: light vertices of the one strategy that contributes; */
  u32 strategy_t;            /*   camera vertices; BDPT_ALL_STRATEGIES in strategy_s: every strategy */
  u32 unweighted;            /* 1: that strategy without its MIS weight (--bdpt-unweighted) */
  u32 light_vertex_capacity; /* light vertices stored per light subpath */
  u32 lvc;                   /* connections per camera vertex to random cached light vertices
                              * (--bdpt-lvc, light vertex caching); 0: to every vertex of its own
                              * light subpath */
  u32 pad[3];
} BdptParams;

typedef struct PathVertex {
  float p[3];
  float ng[3];             /* geometric normal, turned to wo's side */
  float ns[3];             /* shading normal, on ng's side */
  float wo[3];             /* unit direction towards the previous vertex of the subpath */
  float beta[3];           /* subpath throughput up to this vertex (its BSDF not included) */
  float base_color[3];     /* the resolved BSDF (BsdfParams) */
  float specular_color[3];
  float metallic, roughness, specular, transmission, ior;
  u32 clearcoat;           /* clearcoat (bits 0-15) and its roughness (16-31), unorm16: the
                            * values material_resolve rounds them to (PATH_VERTEX_UNORM16) */
  float dvcm, dvc, dvm;    /* recursive MIS quantities (Georgiev 2012); dvm for merging */
  u32 depth;               /* index k of the vertex y_k: 1 for the first surface hit */
  u32 material;            /* bits 0-30: the material; bit 31: SurfaceHit.front */
  float iridescence, iridescence_ior, iridescence_thickness; /* KHR_materials_iridescence */
  float diffuse_transmission;              /* KHR_materials_diffuse_transmission */
  float diffuse_transmission_color[3];
  u32 sheen;               /* KHR_materials_sheen, unorm8: colour R, G, B (bits 0-23) and
                            * roughness (24-31), as material_resolve rounds them */
  float anisotropy_t[3];   /* KHR_materials_anisotropy: direction (world) and strength */
  float anisotropy;
  float clearcoat_n[3];    /* the clearcoat's normal (world, front face; BsdfParams) */
  u32 pad;
} PathVertex;

CLPT_END_SHARED

#endif
