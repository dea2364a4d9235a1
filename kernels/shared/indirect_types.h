/* The one-bounce indirect integrator's own parameters (--integrator indirect1,
 * kernels/integrators/indirect1.cl, docs/concepts/indirect-generators.md), written by the
 * host (host/integrators/indirect1.cpp) beside the common RenderParams. */
#ifndef CLPT_SHARED_INDIRECT_TYPES_H
#define CLPT_SHARED_INDIRECT_TYPES_H

#include "shared/compat.h"

CLPT_BEGIN_SHARED

/* --indirect: how the light that reaches x from a surface point y lit by a light is found
 * (the lecture's three generators of indirect paths x <- y <- light). */
enum IndirectGenerator {
  INDIRECT_RECEIVER = 0, /* shoot from x by its BSDF, find y, next-event estimation at y */
  INDIRECT_SOURCE = 1,   /* shoot from a light, find y, connect y to x */
  INDIRECT_SURFACE = 2   /* pick y on the scene's surfaces by area, connect x - y and y - light */
};

typedef struct IndirectParams {
  u32 generator; /* IndirectGenerator */
  u32 triangles; /* intervals of the surface-area distribution (INDIRECT_SURFACE) */
  float total_area; /* the scene's surface area: the distribution's normalisation */
  u32 pad;
} IndirectParams;

CLPT_END_SHARED

#endif
