/* The camera ray of one sample: the film position and the lens position each take their own
 * sampler dimensions (DIM_PIXEL, DIM_CAMERA_LENS). pixel_ray draws the film position from the
 * pixel filter around the work-item's pixel (camera/pixel_filter.cl); film_sample_ray takes the film position itself from the sample, for integrators
 * whose work-items are not pixels (mlt's chains). */
#ifndef CLPT_CAMERA_PIXEL_RAY_CL
#define CLPT_CAMERA_PIXEL_RAY_CL

#include "camera/camera.cl"
#include "camera/pixel_filter.cl"
#include "sampler/sampler.cl"

/* The ray through pixel (x, y) at offset `jitter` in [0,1)^2, with the lens point from the
 * sample. */
static inline void jittered_pixel_ray(__constant const RenderParams* p, const Sampler* sampler,
                                      u32 x,
                                      u32 y, float2 jitter, float3* org, float3* dir) {
  const float2 film = film_point(x, y, p->width, p->height, jitter);
  const float2 lens =
      p->camera.lens_radius > 0.0f ? sample_2d(sampler, DIM_CAMERA_LENS) : (float2)(0.5f);
  camera_ray(&p->camera, film, lens, org, dir);
}

static inline void pixel_ray(__constant const RenderParams* p, const Sampler* sampler, u32 x, u32 y,
                             float3* org, float3* dir) {
  const float2 u = sample_2d(sampler, DIM_PIXEL);
  jittered_pixel_ray(p, sampler, x, y,
                     p->filter_splat ? u
                                     : pixel_filter_jitter_on_film(p->filter, p->filter_radius, x, y, p->width,
                                                                   p->height, u),
                     org, dir);
}

/* DIM_PIXEL spans the whole image: u in [0,1)^2 is the raster position (u.x * width,
 * u.y * height), so a uniform u is the same film density as pixel_ray over uniform pixels.
 * Returns the pixel it falls in, and the raster position in *raster. */
static inline u32 film_sample_ray(__constant const RenderParams* p, const Sampler* sampler,
                                  float3* org,
                                  float3* dir, float2* raster) {
  const float2 u = sample_2d(sampler, DIM_PIXEL);
  const float fx = u.x * (float)p->width, fy = u.y * (float)p->height;
  *raster = (float2)(fx, fy);
  const u32 x = min((u32)fx, p->width - 1u), y = min((u32)fy, p->height - 1u);
  jittered_pixel_ray(p, sampler, x, y, (float2)(fx - (float)x, fy - (float)y), org, dir);
  return y * p->width + x;
}

#endif
