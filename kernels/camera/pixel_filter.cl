/* Pixel reconstruction filters by filter importance sampling (--filter; Ernst, Stamminger and
 * Greiner, "Filter Importance Sampling", IEEE Symposium on Interactive Ray Tracing 2006):
 * each camera sample's film position is drawn from the filter around its pixel's centre and
 * counts with weight 1 for that pixel alone, so a pixel's mean is the image convolved with the
 * filter, no sample is shared between pixels (samples stay independent, the per-pixel variance
 * stays a sample variance) and images stay deterministic.
 *
 * Every filter here is separable and non-negative: each axis is drawn on its own by inverting
 * its 1-D CDF on [-r, r], which keeps the sampler's stratification (the map is monotone per
 * axis). The formulas are in docs/filters.md; tests/pixel_filter_test.cpp checks each
 * sampler with a chi-square test against the CDF computed on the host. */
#ifndef CLPT_CAMERA_PIXEL_FILTER_CL
#define CLPT_CAMERA_PIXEL_FILTER_CL

#include "shared/render_types.h"

/* erfinv(x) for x in (-1, 1): Giles, "Approximating the erfinv function" (GPU Computing Gems,
 * 2011), the single-precision polynomials. */
static inline float filter_erfinv(float x) {
  float w = -log((1.0f - x) * (1.0f + x));
  float p;
  if (w < 5.0f) {
    w = w - 2.5f;
    p = 2.81022636e-08f;
    p = 3.43273939e-07f + p * w;
    p = -3.5233877e-06f + p * w;
    p = -4.39150654e-06f + p * w;
    p = 0.00021858087f + p * w;
    p = -0.00125372503f + p * w;
    p = -0.00417768164f + p * w;
    p = 0.246640727f + p * w;
    p = 1.50140941f + p * w;
  } else {
    w = sqrt(w) - 3.0f;
    p = -0.000200214257f;
    p = 0.000100950558f + p * w;
    p = 0.00134934322f + p * w;
    p = -0.00367342844f + p * w;
    p = 0.00573950773f + p * w;
    p = -0.0076224613f + p * w;
    p = 0.00943887047f + p * w;
    p = 1.00167406f + p * w;
    p = 2.83297682f + p * w;
  }
  return p * x;
}

/* Blackman-Harris window on t in [0, 1] (four terms, Harris 1978), normalised to a density:
 * its integral over [0, 1] is a0. */
#define BH_A0 0.35875f
#define BH_A1 0.48829f
#define BH_A2 0.14128f
#define BH_A3 0.01168f

static inline float filter_bh_cdf(float t) {
  const float tau = 6.28318530718f;
  return (BH_A0 * t - BH_A1 * sin(tau * t) / tau + BH_A2 * sin(2.0f * tau * t) / (2.0f * tau) -
          BH_A3 * sin(3.0f * tau * t) / (3.0f * tau)) /
         BH_A0;
}

static inline float filter_bh_pdf(float t) {
  const float tau = 6.28318530718f;
  return (BH_A0 - BH_A1 * cos(tau * t) + BH_A2 * cos(2.0f * tau * t) - BH_A3 * cos(3.0f * tau * t)) / BH_A0;
}

/* t in [0, 1] with filter_bh_cdf(t) = u: Newton's steps kept inside a shrinking bracket
 * (bisection where a step would leave it; the density is near 0 at the ends). The window is
 * symmetric, so the lower half is solved for min(u, 1 - u) and mirrored: near t = 1 the CDF
 * is within float rounding of 1 over a wide range of t, near t = 0 it is small and exact
 * enough. */
static inline float filter_bh_invert(float u) {
  const bool upper = u > 0.5f;
  const float v = upper ? 1.0f - u : u;
  float lo = 0.0f, hi = 0.5f, t = v;
  for (int i = 0; i < 32; ++i) {
    const float f = filter_bh_cdf(t) - v;
    if (f > 0.0f) hi = t; else lo = t;
    const float pdf = filter_bh_pdf(t);
    float next = pdf > 1e-6f ? t - f / pdf : 0.5f * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5f * (lo + hi);
    const bool done = fabs(next - t) < 1e-7f;
    t = next;
    if (done) break;
  }
  return upper ? 1.0f - t : t;
}

/* The default: a box of half a pixel, the plain jitter inside the pixel (and a splat into the
 * pixel a position falls in). Every use of a filter keeps this case as it always was. */
static inline bool filter_is_pixel_box(u32 filter, float r) { return filter == FILTER_BOX && r == 0.5f; }

/* One axis: the offset from the pixel's centre, in pixels, for u in [0, 1). */
static inline float filter_sample_1d(u32 filter, float r, float u) {
  float x;
  switch (filter) {
    case FILTER_TENT:
      x = u < 0.5f ? r * (sqrt(2.0f * u) - 1.0f) : r * (1.0f - sqrt(2.0f - 2.0f * u));
      break;
    case FILTER_GAUSSIAN: {
      /* sigma = r / 3, truncated at r: x = sigma sqrt(2) erfinv((2u - 1) erf(3 / sqrt(2))). */
      const float sigma = r / 3.0f;
      x = sigma * 1.41421356f * filter_erfinv((2.0f * u - 1.0f) * 0.99730020f);
      break;
    }
    case FILTER_BLACKMAN_HARRIS:
      x = r * (2.0f * filter_bh_invert(u) - 1.0f);
      break;
    default: /* FILTER_BOX */
      x = r * (2.0f * u - 1.0f);
  }
  return clamp(x, -r, r);
}

/* P(offset < x) for the filter of radius r; x is clamped to [-r, r]. */
static inline float filter_cdf_1d(u32 filter, float r, float x) {
  x = clamp(x, -r, r);
  switch (filter) {
    case FILTER_TENT: {
      const float a = (x + r) / r; /* in [0, 2] */
      return x < 0.0f ? 0.5f * a * a : 1.0f - 0.5f * (2.0f - a) * (2.0f - a);
    }
    case FILTER_GAUSSIAN:
      return 0.5f * (1.0f + erf(x * 3.0f / (r * 1.41421356f)) / 0.99730020f);
    case FILTER_BLACKMAN_HARRIS:
      return filter_bh_cdf((x + r) / (2.0f * r));
    default: /* FILTER_BOX */
      return (x + r) / (2.0f * r);
  }
}

/* The filter's density at offset x (per pixel), normalised over [-r, r]; 0 outside. */
static inline float filter_density_1d(u32 filter, float r, float x) {
  if (!(fabs(x) < r)) return 0.0f;
  switch (filter) {
    case FILTER_TENT:
      return (1.0f - fabs(x) / r) / r;
    case FILTER_GAUSSIAN: {
      const float sigma = r / 3.0f;
      return exp(-0.5f * x * x / (sigma * sigma)) / (sigma * 2.50662827f * 0.99730020f);
    }
    case FILTER_BLACKMAN_HARRIS:
      return filter_bh_pdf((x + r) / (2.0f * r)) / (2.0f * r);
    default: /* FILTER_BOX */
      return 0.5f / r;
  }
}

/* An offset drawn from the filter restricted to [lo, hi] (a pixel near the film's edge: its
 * filter is cut at the edge and renormalised), by inverting the CDF over that interval. */
static inline float filter_sample_1d_in(u32 filter, float r, float lo, float hi, float u) {
  if (lo <= -r && hi >= r) return filter_sample_1d(filter, r, u);
  const float c0 = filter_cdf_1d(filter, r, lo), c1 = filter_cdf_1d(filter, r, hi);
  return clamp(filter_sample_1d(filter, r, c0 + u * (c1 - c0)), lo, hi);
}

/* The share of the filter of the pixel whose centre is c (in [0, n) pixels along an axis)
 * that lies on the film [0, n]: what its cut filter is renormalised by. */
static inline float filter_mass_on_film(u32 filter, float r, float c, float n) {
  return filter_cdf_1d(filter, r, n - c) - filter_cdf_1d(filter, r, -c);
}

/* The film offset of a sample inside the pixel's [0, 1)^2 frame (0.5 is the centre; a wide
 * filter reaches past 0 and 1), from the sample's pixel dimensions u. The box of radius 0.5,
 * the default, is u itself: images without --filter are as they always were. */
static inline float2 pixel_filter_jitter(u32 filter, float radius, float2 u) {
  if (filter_is_pixel_box(filter, radius)) return u;
  return (float2)(0.5f + filter_sample_1d(filter, radius, u.x), 0.5f + filter_sample_1d(filter, radius, u.y));
}

/* As pixel_filter_jitter for pixel (x, y) of a width x height film, with the filter cut at the
 * film's edges: every sample lands on the film, and a pixel's mean is the image under its
 * filter renormalised over the film (what a splatted filter gives too, film/splat_filter.cl). */
static inline float2 pixel_filter_jitter_on_film(u32 filter, float radius, u32 x, u32 y, u32 width,
                                                 u32 height, float2 u) {
  if (filter_is_pixel_box(filter, radius)) return u;
  const float cx = (float)x + 0.5f, cy = (float)y + 0.5f;
  return (float2)(0.5f + filter_sample_1d_in(filter, radius, -cx, (float)width - cx, u.x),
                  0.5f + filter_sample_1d_in(filter, radius, -cy, (float)height - cy, u.y));
}

#endif
