// The grid the irradiance cache's lookups read (kernels/spatial/sphere_grid.cl): a hashed
// multi-level grid over the records' validity spheres (radius a R_i), built on the host after
// each placement pass from the records read back.
#pragma once

#include <cstdint>
#include <vector>

#include "shared/ic_types.h"

namespace clpt {

struct IcGrid {
  std::vector<uint32_t> starts;   // buckets + 1 offsets into entries
  std::vector<uint32_t> entries;  // level << IC_ENTRY_LEVEL_SHIFT | record index
  float inv_cell = 1.0f;          // 1 / the side of a level-0 cell
  uint32_t level_mask = 0;        // levels that hold records
  uint32_t bucket_mask = 0;       // buckets - 1
};

// The grid over records' spheres of radius error * r (records[i].r is R_i).
IcGrid build_ic_grid(const std::vector<dev::IcRecord>& records, float error);

// The same hash and cell rule as the kernels' (sphere_grid_bucket, sphere_grid_cell).
uint32_t sphere_grid_bucket(uint32_t level, int32_t cx, int32_t cy, int32_t cz, uint32_t mask);
int32_t sphere_grid_coordinate(float x, float inv_cell, uint32_t level);

}  // namespace clpt
