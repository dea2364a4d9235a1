/* A hashed multi-level grid over spheres (the irradiance cache's validity spheres), built on
 * the host (host/integrators/ic_grid.cpp) and read here. Level L has cubic cells of side
 * 2^L / inv_cell; a sphere of radius v lives at the lowest level whose cells are at least 2v
 * wide, in each of the (at most 2 x 2 x 2) cells its bounding box touches. A point query then
 * reads one cell per level in use (level_mask). Cell (L, i, j, k) lives in bucket
 * sphere_grid_bucket & mask; the bucket's entries are entries[starts[b] .. starts[b + 1]),
 * each once per bucket: level << IC_ENTRY_LEVEL_SHIFT | sphere index. Buckets are shared by
 * colliding cells, of one level or of several, so a query tests every sphere it meets and
 * skips the entries of other levels (each sphere is then met at most once). */
#ifndef CLPT_SPATIAL_SPHERE_GRID_CL
#define CLPT_SPATIAL_SPHERE_GRID_CL

#include "shared/ic_types.h"

/* The hash of cell (level, c); the host's sphere_grid_bucket is the same function. */
static inline u32 sphere_grid_bucket(u32 level, int3 c, u32 mask) {
  return (((u32)c.x * 73856093u) ^ ((u32)c.y * 19349663u) ^ ((u32)c.z * 83492791u) ^
          ((level + 1u) * 2654435761u)) & mask;
}

/* The cell of point x at `level`. */
static inline int3 sphere_grid_cell(float3 x, float inv_cell, u32 level) {
  return convert_int3_sat_rtn(x * ldexp(inv_cell, -(int)level));
}

#endif
