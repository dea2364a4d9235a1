/* Light-side vertices seen by the camera (t = 1 strategies: lt, bdpt): the pixel a camera
 * connection (camera/camera_importance.cl) lands in; contributions are splatted at the
 * connection's film position through the pixel filter (film/splat_filter.cl). */
#ifndef CLPT_INTEGRATORS_STAGES_CAMERA_SPLAT_CL
#define CLPT_INTEGRATORS_STAGES_CAMERA_SPLAT_CL

#include "camera/camera_importance.cl"
#include "film/splat.cl"
#include "film/splat_filter.cl"
#include "shared/render_types.h"

static inline u32 splat_pixel(__constant const RenderParams* p, const CameraConnection* c) {
  const u32 x = min((u32)c->raster.x, p->width - 1u), y = min((u32)c->raster.y, p->height - 1u);
  return y * p->width + x;
}

#endif
