/* The path a primary sample vector stands for (PSSMLT over the path tracer, Kelemen et al.
 * 2002): the film position from DIM_PIXEL, then pt's estimator (integrators/estimators/path_trace.cl,
 * the same function pt's pixels run) reading the vector through the PSS sampler, its depths
 * first_depth on (2 where the direct light is rendered apart, MltParams.first_depth). The
 * chain's target function is the luminance of that contribution. */
#ifndef CLPT_INTEGRATORS_MLT_PSS_PATH_CL
#define CLPT_INTEGRATORS_MLT_PSS_PATH_CL

#include "camera/pixel_ray.cl"
#include "integrators/estimators/path_trace.cl"

typedef struct PssPath {
  float3 L;        /* the path's contribution C (radiance, pt's estimate for one sample) */
  float target;    /* I = luminance(C); 0 for a black or non-finite C */
  u32 pixel;       /* where its film position falls */
  float2 raster;   /* its film position (pixels), for a splat through the pixel filter */
} PssPath;

static inline PssPath pss_path(const SceneView* s, __constant const RenderParams* p,
                               const Sampler* sampler, u32 first_depth, u32* rays) {
  PssPath path;
  float3 org, dir;
  path.pixel = film_sample_ray(p, sampler, &org, &dir, &path.raster);
  path.L = pt_radiance(s, p, sampler, org, dir, first_depth, rays);
  const float y = luminance(path.L);
  path.target = is_finite3(path.L) && y > 0.0f ? y : 0.0f;
  return path;
}

#endif
