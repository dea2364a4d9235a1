/* The sample loop of the integrators that give each pixel a work-item and sum independent
 * camera samples into it (pt and direct, ao, pm, ic, indirect1): which pixel, which sampler
 * key (pixel, sample_offset + i) and which camera ray sample i of a pass takes, and the
 * film's running sums. One place for what those kernels share:
 *
 *   PixelSamples ps = pixel_samples_begin(params, get_global_id(0), film_sum, film_sum_sq);
 *   for (u32 i = 0; i < params->samples_per_pass; ++i) {
 *     float3 org, dir;
 *     const Sampler sampler = pixel_sample(params, &ps, i, &org, &dir);
 *     film_add(&ps.film, radiance(..., &sampler, org, dir, &ps.rays));
 *   }
 *   pixel_samples_end(&ps, film_sum, film_sum_sq, ray_counts);
 *
 * (after the kernel's `pixel >= width * height` return). */
#ifndef CLPT_INTEGRATORS_STAGES_PIXEL_SAMPLES_CL
#define CLPT_INTEGRATORS_STAGES_PIXEL_SAMPLES_CL

#include "camera/pixel_ray.cl"
#include "film/film.cl"

typedef struct PixelSamples {
  u32 pixel, x, y;
  FilmPixel film; /* the pixel's sums, loaded at the start and stored at the end */
  u32 rays;       /* rays the pass's samples traced */
} PixelSamples;

static inline PixelSamples pixel_samples_begin(__constant const RenderParams* p, u32 pixel,
                                               __global const float4* film_sum,
                                               __global const float4* film_sum_sq) {
  PixelSamples ps;
  ps.pixel = pixel;
  ps.x = pixel % p->width;
  ps.y = pixel / p->width;
  ps.film = film_load(film_sum, film_sum_sq, pixel);
  ps.rays = 0u;
  return ps;
}

/* Sample i of the pass: its sampler and its camera ray (org, dir). */
static inline Sampler pixel_sample(__constant const RenderParams* p, const PixelSamples* ps, u32 i,
                                   float3* org, float3* dir) {
  const Sampler sampler = sampler_init(p, ps->pixel, p->sample_offset + i);
  pixel_ray(p, &sampler, ps->x, ps->y, org, dir);
  return sampler;
}

static inline void pixel_samples_end(const PixelSamples* ps, __global float4* film_sum,
                                     __global float4* film_sum_sq, __global u32* ray_counts) {
  film_store(film_sum, film_sum_sq, ps->pixel, &ps->film);
  ray_counts[ps->pixel] += ps->rays;
}

#endif
