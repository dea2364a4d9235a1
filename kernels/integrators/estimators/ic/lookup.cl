/* Ward's interpolation from the irradiance cache (Ward, Rubinstein and Clear 1988; gradients:
 * Ward and Heckbert 1992). At point x with normal n, record i (position x_i, normal n_i,
 * radius R_i) has the error
 *     eps_i = |x - x_i| / R_i + sqrt(1 - n . n_i)
 * and contributes with weight w_i = 1 / eps_i when eps_i < a (--ic-error), when it was made
 * at the same depth (its hemisphere's paths have the same bounces left) and when it is not
 * in front of x: (x - x_i) . (n + n_i) / 2 >= -IC_IN_FRONT_TOLERANCE R_i (Ward's test: a
 * record above x's surface sees light x does not, the step in a staircase). The estimate is
 *     E(x) = sum_i w_i (E_i + (n_i x n) . grad_rot E_i + (x - x_i) . grad_trans E_i) / sum_i w_i
 * with the gradient terms unless --ic-no-gradients (the translational one capped, each
 * channel clamped at 0). eps_i < a
 * implies |x - x_i| < a R_i, so the records a query can use are those whose validity sphere
 * (radius a R_i) holds x: the grid of kernels/spatial/sphere_grid.cl indexes those spheres.
 * The host test (tests/ic_test.cpp) repeats this by brute force over all records. */
#ifndef CLPT_INTEGRATORS_IC_LOOKUP_CL
#define CLPT_INTEGRATORS_IC_LOOKUP_CL

#include "core/math.cl"
#include "shared/ic_types.h"
#include "spatial/sphere_grid.cl"

#define IC_IN_FRONT_TOLERANCE 1e-3f
/* eps below this counts as this: a query at a record's own point has a finite weight. */
#define IC_MIN_EPS 1e-6f

/* A kernel's arguments for the cache (bound by host/integrators/ic_records.cpp). */
#define IC_CACHE_ARGS                                                                       \
  __constant const IcParams *ic, __global const IcRecord *records, __global const u32 *starts, \
      __global const u32 *entries

typedef struct IcCache {
  __constant const IcParams* ic;
  __global const IcRecord* records;
  __global const u32* starts;   /* bucket b's entries are entries[starts[b] .. starts[b+1]) */
  __global const u32* entries;
} IcCache;

static inline IcCache ic_cache(__constant const IcParams* ic, __global const IcRecord* records,
                               __global const u32* starts, __global const u32* entries) {
  IcCache c;
  c.ic = ic;
  c.records = records;
  c.starts = starts;
  c.entries = entries;
  return c;
}

/* The luminance of a per-channel gradient (three world vectors, r g b): luminance()'s
 * weights applied to the vectors. */
static inline float3 ic_luminance_gradient(__global const float* g) {
  return CLPT_LUMINANCE_R * vload3(0, g) + CLPT_LUMINANCE_G * vload3(1, g) +
         CLPT_LUMINANCE_B * vload3(2, g);
}

typedef struct IcEstimate {
  float3 e;       /* the interpolated irradiance (valid when weight > 0) */
  float weight;   /* sum of the contributing records' weights; 0: no record covers x */
  u32 records;    /* how many contributed */
} IcEstimate;

/* Record i's weight at (x, n, depth) for the error bound a, 0 when it does not contribute. */
static inline float ic_record_weight(float a, __global const IcRecord* r, float3 x, float3 n,
                                     u32 depth) {
  if (r->depth != depth) return 0.0f;
  const float3 xi = vload3(0, r->p), ni = vload3(0, r->n);
  const float cos_n = dot(n, ni);
  if (!(cos_n > 0.0f)) return 0.0f;
  const float3 d = x - xi;
  const float eps = length(d) / r->r + sqrt(fmax(0.0f, 1.0f - cos_n));
  if (!(eps < a)) return 0.0f;
  if (dot(d, 0.5f * (n + ni)) < -IC_IN_FRONT_TOLERANCE * r->r) return 0.0f;
  return 1.0f / fmax(eps, IC_MIN_EPS);
}

/* E_i extrapolated to (x, n): with the gradients when the cache uses them. */
static inline float3 ic_record_irradiance(__constant const IcParams* ic, __global const IcRecord* r,
                                          float3 x, float3 n) {
  float3 e = vload3(0, r->e);
  if (!ic->gradients) return e;
  const float3 axis = cross(vload3(0, r->n), n), d = x - vload3(0, r->p);
  e += (float3)(dot(axis, vload3(0, r->rot)), dot(axis, vload3(1, r->rot)),
                dot(axis, vload3(2, r->rot)));
  /* The translational gradient, capped so that it changes E's luminance by at most E's
   * over the distance R_i (at most a E over the validity radius): where the spacing clamp
   * keeps R above the gradient limit E / |grad| (records at corners, whose gradients are
   * large and noisy), the uncapped gradient painted bright and dark specks along the edges. */
  const float3 t0 = vload3(0, r->trans), t1 = vload3(1, r->trans), t2 = vload3(2, r->trans);
  const float e_lum = luminance(vload3(0, r->e));
  const float g_len = length(ic_luminance_gradient(r->trans)) * r->r;
  const float cap = g_len > e_lum ? e_lum / g_len : 1.0f;
  e += cap * (float3)(dot(d, t0), dot(d, t1), dot(d, t2));
  return fmax(e, (float3)(0.0f));
}

/* The cache's estimate at x (normal n, oriented as the record normals are: to the viewer's
 * side) for a vertex with `depth` bounces before it, from the records with eps < a (the
 * image: --ic-error; the placement asks for a margin, kernels/integrators/ic.cl). */
static inline IcEstimate ic_lookup_within(const IcCache* c, float a, float3 x, float3 n,
                                          u32 depth) {
  IcEstimate est;
  est.e = (float3)(0.0f);
  est.weight = 0.0f;
  est.records = 0u;
  const u32 mask = c->ic->level_mask;
  for (u32 level = 0; level < IC_MAX_LEVELS; ++level) {
    if (!((mask >> level) & 1u)) continue;
    const u32 b = sphere_grid_bucket(level, sphere_grid_cell(x, c->ic->inv_cell, level),
                                     c->ic->bucket_mask);
    const u32 end = c->starts[b + 1u];
    for (u32 k = c->starts[b]; k < end; ++k) {
      const u32 entry = c->entries[k];
      /* A bucket another level's cell shares holds that level's records too: each record
       * counts at its own level only. */
      if (entry >> IC_ENTRY_LEVEL_SHIFT != level) continue;
      __global const IcRecord* r = &c->records[entry & IC_ENTRY_INDEX_MASK];
      const float w = ic_record_weight(a, r, x, n, depth);
      if (!(w > 0.0f)) continue;
      est.e += w * ic_record_irradiance(c->ic, r, x, n);
      est.weight += w;
      ++est.records;
    }
  }
  if (est.weight > 0.0f) est.e /= est.weight;
  return est;
}

static inline IcEstimate ic_lookup(const IcCache* c, float3 x, float3 n, u32 depth) {
  return ic_lookup_within(c, c->ic->error, x, n, depth);
}

#endif
