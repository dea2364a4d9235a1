/* Per-pass render parameters, uploaded to a small __constant buffer. */
#ifndef CLPT_SHARED_RENDER_TYPES_H
#define CLPT_SHARED_RENDER_TYPES_H

#include "shared/compat.h"

CLPT_BEGIN_SHARED

enum CameraType { CAMERA_PERSPECTIVE = 0, CAMERA_ORTHOGRAPHIC = 1 };

/* A pinhole or orthographic camera as world-space vectors. For a film point (sx, sy) in
 * [-1, 1]^2 (+y up), a perspective ray has direction forward + sx*right + sy*up from
 * origin; an orthographic ray starts at origin + sx*right + sy*up along forward. */
typedef struct CameraData {
  float origin[4];
  float right[4];   /* perspective: tan(fov_x / 2) * camera x; orthographic: half width * x */
  float up[4];      /* perspective: tan(fov_y / 2) * camera y; orthographic: half height * y */
  float forward[4]; /* unit view direction (camera -z) */
  u32 type;         /* CameraType */
  u32 pad[3];
} CameraData;

typedef struct RenderParams {
  CameraData camera;
  u32 width;
  u32 height;
  u32 max_depth;        /* bounces; 0 shows emitters only */
  u32 rr_depth;         /* Russian roulette may end paths from this bounce on */
  u32 seed;
  u32 sample_offset;    /* index of this pass's first sample in every pixel */
  u32 samples_per_pass; /* samples each pixel takes this pass */
  u32 pad;
} RenderParams;

CLPT_END_SHARED

#endif
