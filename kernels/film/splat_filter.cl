/* Splatting through the pixel filter (--filter with an integrator that splats: lt, bdpt, vcm,
 * mlt; RenderParams.filter_splat). A contribution at film position `raster` (pixels, x right,
 * y down) adds to every pixel k whose filter reaches it, weighted by that filter's density
 * there over the share of the filter that lies on the film:
 *     w_k = h(raster.x - cx_k) h(raster.y - cy_k) / (Z_x(k) Z_y(k)),
 * so with camera samples uniform over their pixels (spp per pixel) pixel k's sum estimates
 * the image under k's filter cut at the film's edges and renormalised, the same quantity
 * filter importance sampling gives the integrators that do not splat
 * (camera/pixel_filter.cl: pixel_filter_jitter_on_film). The default box of half a pixel is
 * the plain splat into the pixel the position falls in. */
#ifndef CLPT_FILM_SPLAT_FILTER_CL
#define CLPT_FILM_SPLAT_FILTER_CL

#include "core/prefetch.cl"

#include "camera/pixel_filter.cl"
#include "film/splat.cl"
#include "sampler/sampler.cl"

/* The pixel a film position falls in, clamped to the film. */
static inline u32 film_pixel_of(__constant const RenderParams* p, float2 raster) {
  const u32 x = min((u32)max(raster.x, 0.0f), p->width - 1u), y = min((u32)max(raster.y, 0.0f), p->height - 1u);
  return y * p->width + x;
}

/* True when contributions are spread through the filter: an integrator that splats, with a
 * filter other than the default box. */
static inline bool film_splats_through_filter(__constant const RenderParams* p) {
  return p->filter_splat && !filter_is_pixel_box(p->filter, p->filter_radius);
}

/* Fetches the splat film's pixel at raster ahead of film_splat_at's atomic adds there: the
 * camera connections of lt, bdpt and vcm know it before they trace their shadow ray, and the
 * adds otherwise wait on the line (lt on the Cornell box: 0.90x the render time,
 * docs/BENCHMARKS.md session 41). With a wider filter, the centre pixel. */
static inline void film_splat_prefetch(__constant const RenderParams* p, __global float4* splat,
                                       float2 raster) {
  CLPT_PREFETCH_WRITE(splat + film_pixel_of(p, raster));
}

static inline void film_splat_at(__constant const RenderParams* p, __global float4* splat, float2 raster,
                                 float3 L) {
  const u32 filter = p->filter;
  const float r = p->filter_radius;
  if (filter_is_pixel_box(filter, r) || !is_finite3(L)) {
    film_splat(splat, film_pixel_of(p, raster), L);
    return;
  }
  const int x0 = max(0, (int)ceil(raster.x - r - 0.5f)), x1 = min((int)p->width - 1, (int)floor(raster.x + r - 0.5f));
  const int y0 = max(0, (int)ceil(raster.y - r - 0.5f)), y1 = min((int)p->height - 1, (int)floor(raster.y + r - 0.5f));
  for (int y = y0; y <= y1; ++y) {
    const float cy = (float)y + 0.5f;
    const float wy = filter_density_1d(filter, r, raster.y - cy) /
                     filter_mass_on_film(filter, r, cy, (float)p->height);
    if (!(wy > 0.0f)) continue;
    for (int x = x0; x <= x1; ++x) {
      const float cx = (float)x + 0.5f;
      const float w = wy * filter_density_1d(filter, r, raster.x - cx) /
                      filter_mass_on_film(filter, r, cx, (float)p->width);
      if (w > 0.0f) film_splat(splat, (u32)y * p->width + (u32)x, L * w);
    }
  }
}

/* A camera sample's contribution L for integrators whose film splats (bdpt, vcm): with a
 * pixel filter other than the default box, spread from the sample's film position (its pixel
 * plus its DIM_PIXEL jitter, as pixel_ray took it) and true is returned; else false, and the
 * caller adds L to its own pixel as always. */
static inline bool film_camera_splat(__constant const RenderParams* p, __global float4* splat,
                                     const Sampler* sampler, u32 pixel, float3 L) {
  if (!film_splats_through_filter(p)) return false;
  const float2 u = sample_2d(sampler, DIM_PIXEL);
  film_splat_at(p, splat, (float2)((float)(pixel % p->width) + u.x, (float)(pixel / p->width) + u.y), L);
  return true;
}

#endif
