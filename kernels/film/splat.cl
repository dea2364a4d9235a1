/* Splatting: adding a contribution to any pixel from any work-item (light tracing, and BDPT's
 * t = 1 strategies later). OpenCL 1.2 has no float atomics, so a float is added by a
 * compare-exchange loop on its 32-bit pattern; the order of concurrent adds is not fixed, so
 * splatted sums are not bit-reproducible (the float sum depends on the order), only
 * statistically so. The splat film holds, per pixel, xyz: the sum of contributions, w: the
 * number of non-finite contributions dropped. */
#ifndef CLPT_FILM_SPLAT_CL
#define CLPT_FILM_SPLAT_CL

#include "core/math.cl"
#include "shared/compat.h"

static inline void atomic_add_float(volatile __global float* addr, float v) {
  volatile __global uint* bits = (volatile __global uint*)addr;
  uint expected = *bits;
  for (;;) {
    const uint seen = atomic_cmpxchg(bits, expected, as_uint(as_float(expected) + v));
    if (seen == expected) break;
    expected = seen;
  }
}

/* Adds L to pixel `pixel` of the splat film; a non-finite L is counted as dropped instead. */
static inline void film_splat(__global float4* splat, u32 pixel, float3 L) {
  volatile __global float* px = (volatile __global float*)(splat + pixel);
  if (is_finite3(L)) {
    if (L.x != 0.0f) atomic_add_float(px + 0, L.x);
    if (L.y != 0.0f) atomic_add_float(px + 1, L.y);
    if (L.z != 0.0f) atomic_add_float(px + 2, L.z);
  } else {
    atomic_add_float(px + 3, 1.0f);
  }
}

#endif
