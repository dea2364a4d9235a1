/* The camera ray of one pixel sample: the film position and the lens position each take
 * their own sampler dimensions (DIM_PIXEL, DIM_CAMERA_LENS). */
#ifndef CLPT_CAMERA_PIXEL_RAY_CL
#define CLPT_CAMERA_PIXEL_RAY_CL

#include "camera/camera.cl"
#include "sampler/sampler.cl"

inline void pixel_ray(__constant const RenderParams* p, const Sampler* sampler, u32 x, u32 y,
                      float3* org, float3* dir) {
  const float2 film = film_point(x, y, p->width, p->height, sample_2d(sampler, DIM_PIXEL));
  const float2 lens =
      p->camera.lens_radius > 0.0f ? sample_2d(sampler, DIM_CAMERA_LENS) : (float2)(0.5f);
  camera_ray(&p->camera, film, lens, org, dir);
}

#endif
