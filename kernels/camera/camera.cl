/* Camera rays for a film point. */
#ifndef CLPT_CAMERA_CAMERA_CL
#define CLPT_CAMERA_CAMERA_CL

#include "shared/render_types.h"

/* Film coordinates of pixel (x, y) (y = 0 is the top row) offset by u in [0,1)^2,
 * mapped to [-1, 1]^2 with +y up. */
inline float2 film_point(u32 x, u32 y, u32 width, u32 height, float2 u) {
  return (float2)(2.0f * ((float)x + u.x) / (float)width - 1.0f,
                  1.0f - 2.0f * ((float)y + u.y) / (float)height);
}

inline void camera_ray(__constant const CameraData* cam, float2 film, float3* org, float3* dir) {
  const float3 o = vload3(0, cam->origin), r = vload3(0, cam->right), u = vload3(0, cam->up),
               f = vload3(0, cam->forward);
  if (cam->type == CAMERA_ORTHOGRAPHIC) {
    *org = o + film.x * r + film.y * u;
    *dir = f;
  } else {
    *org = o;
    *dir = normalize(f + film.x * r + film.y * u);
  }
}

#endif
