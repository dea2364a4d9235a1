/* Film accumulation. Each pixel keeps the running sum of its samples (xyz) and the number
 * of samples dropped for being NaN/Inf (w), and the running sum of squares (xyz) for the
 * per-pixel variance. A pass adds its samples in sample order, so any split of the samples
 * into passes gives bit-identical sums. */
#ifndef CLPT_FILM_FILM_CL
#define CLPT_FILM_FILM_CL

#include "core/math.cl"
#include "shared/compat.h"

typedef struct FilmPixel {
  float4 sum;    /* xyz: sum of radiance; w: dropped (non-finite) samples */
  float4 sum_sq; /* xyz: sum of squared radiance */
} FilmPixel;

static inline FilmPixel film_load(__global const float4* sum, __global const float4* sum_sq,
                                  u32 pixel) {
  FilmPixel f;
  f.sum = sum[pixel];
  f.sum_sq = sum_sq[pixel];
  return f;
}

static inline void film_add(FilmPixel* f, float3 L) {
  if (is_finite3(L)) {
    f->sum.xyz += L;
    f->sum_sq.xyz += L * L;
  } else {
    f->sum.w += 1.0f;
  }
}

static inline void film_store(__global float4* sum, __global float4* sum_sq, u32 pixel,
                              const FilmPixel* f) {
  sum[pixel] = f->sum;
  sum_sq[pixel] = f->sum_sq;
}

#endif
