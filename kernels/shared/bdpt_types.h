/* What bidirectional path tracing keeps of a light subpath between its two kernels
 * (kernels/integrators/bdpt.cl): one PathVertex per stored light vertex, a fixed number of
 * slots per light path (RenderParams.light_vertex_capacity). Plain floats, so the host
 * knows its size (160 bytes) for the buffer it allocates. */
#ifndef CLPT_SHARED_BDPT_TYPES_H
#define CLPT_SHARED_BDPT_TYPES_H

#include "shared/compat.h"

CLPT_BEGIN_SHARED

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
  u32 unused;              /* free: keeps the size a multiple of 16 bytes */
} PathVertex;

CLPT_END_SHARED

#endif
