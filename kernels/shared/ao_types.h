/* Ambient occlusion's own parameters (--integrator ao, kernels/integrators/ao.cl), written by
 * the host (host/integrators/integrator.cpp, make_ao) beside the common RenderParams. */
#ifndef CLPT_SHARED_AO_TYPES_H
#define CLPT_SHARED_AO_TYPES_H

#include "shared/compat.h"

CLPT_BEGIN_SHARED

typedef struct AoParams {
  float radius; /* occluders farther than this do not count (--ao-radius; world units) */
  u32 pad[3];
} AoParams;

CLPT_END_SHARED

#endif
