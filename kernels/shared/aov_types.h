/* Per-pixel sums of the first-hit AOVs (--aov; kernels/integrators/aov.cl, host/render/aov.cpp):
 * what the camera samples of a pixel see at their first hit, summed over up to
 * AOV_MAX_SAMPLES samples and divided by the host. */
#ifndef CLPT_SHARED_AOV_TYPES_H
#define CLPT_SHARED_AOV_TYPES_H

#include "shared/compat.h"

CLPT_BEGIN_SHARED

/* Samples per pixel the AOVs average: their first hits settle long before the image does. */
#define AOV_MAX_SAMPLES 64u
/* material of a pixel whose first sample hit nothing */
#define AOV_NO_MATERIAL 0xffffffffu

typedef struct AovSums {
  float albedo[3];   /* over every sample; a miss adds 0 */
  float normal[3];   /* shading normal facing the camera, world space; a miss adds 0 */
  float position[3]; /* world position, over the hits */
  float depth;       /* distance from the camera's ray origin, over the hits */
  u32 samples;       /* samples summed */
  u32 hits;          /* of them, those that hit a surface */
  u32 material;      /* the first sample's material index, or AOV_NO_MATERIAL */
  u32 pad[3];        /* to 64 bytes */
} AovSums;

CLPT_END_SHARED

#endif
