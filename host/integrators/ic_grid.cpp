#include "integrators/ic_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "util/error.h"

namespace clpt {

uint32_t sphere_grid_bucket(uint32_t level, int32_t cx, int32_t cy, int32_t cz, uint32_t mask) {
  return ((uint32_t(cx) * 73856093u) ^ (uint32_t(cy) * 19349663u) ^ (uint32_t(cz) * 83492791u) ^
          ((level + 1u) * 2654435761u)) &
         mask;
}

int32_t sphere_grid_coordinate(float x, float inv_cell, uint32_t level) {
  // convert_int_sat_rtn(x * ldexp(inv_cell, -level)): floor, saturated (NaN to 0).
  const float v = std::floor(x * std::ldexp(inv_cell, -int(level)));
  if (!(v == v)) return 0;
  if (v <= float(std::numeric_limits<int32_t>::min())) return std::numeric_limits<int32_t>::min();
  if (v >= float(std::numeric_limits<int32_t>::max())) return std::numeric_limits<int32_t>::max();
  return int32_t(v);
}

IcGrid build_ic_grid(const std::vector<dev::IcRecord>& records, float error) {
  IcGrid g;
  if (records.size() > IC_ENTRY_INDEX_MASK)
    throw Error(ExitCode::Usage, "ic: " + std::to_string(records.size()) +
                                     " records, more than the grid indexes; raise --ic-error");
  float v_min = std::numeric_limits<float>::infinity();
  for (const dev::IcRecord& r : records)
    if (error * r.r > 0.0f) v_min = std::min(v_min, error * r.r);
  if (!std::isfinite(v_min)) {
    g.starts.assign(2, 0u);
    return g;
  }
  // Level 0's cells are twice the smallest sphere's radius; a sphere of radius v goes to the
  // lowest level whose cells are at least 2v wide.
  g.inv_cell = 1.0f / (2.0f * v_min);
  std::vector<std::pair<uint32_t, uint32_t>> pairs;  // (cell key for sorting, entry)
  pairs.reserve(records.size() * 8);
  size_t buckets = 1024;
  while (buckets < 2 * records.size()) buckets *= 2;
  g.bucket_mask = uint32_t(buckets - 1);
  for (uint32_t i = 0; i < records.size(); ++i) {
    const dev::IcRecord& r = records[i];
    const float v = error * r.r;
    if (!(v > 0.0f) || !std::isfinite(v)) continue;
    uint32_t level = 0;
    while (level + 1 < IC_MAX_LEVELS && std::ldexp(2.0f * v_min, int(level)) < 2.0f * v) ++level;
    g.level_mask |= 1u << level;
    // The box the sphere touches, a little wider so that a point the kernel finds inside
    // the sphere lands in one of its cells whatever the rounding of x * inv_cell.
    int32_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const float pad = 1e-3f * v + 4e-7f * std::fabs(r.p[a]);
      lo[a] = sphere_grid_coordinate(r.p[a] - v - pad, g.inv_cell, level);
      hi[a] = sphere_grid_coordinate(r.p[a] + v + pad, g.inv_cell, level);
    }
    for (int a = 0; a < 3; ++a)
      if (int64_t(hi[a]) - lo[a] > 4)  // only at the top level: radii 2^23 apart
        throw Error(ExitCode::Usage, "ic: record radii too far apart for the grid");
    const uint32_t entry = (level << IC_ENTRY_LEVEL_SHIFT) | i;
    for (int64_t z = lo[2]; z <= hi[2]; ++z)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t x = lo[0]; x <= hi[0]; ++x)
          pairs.emplace_back(
              sphere_grid_bucket(level, int32_t(x), int32_t(y), int32_t(z), g.bucket_mask), entry);
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  g.starts.assign(buckets + 1, 0u);
  g.entries.resize(pairs.size());
  for (size_t k = 0; k < pairs.size(); ++k) {
    ++g.starts[pairs[k].first + 1];
    g.entries[k] = pairs[k].second;
  }
  for (size_t b = 0; b < buckets; ++b) g.starts[b + 1] += g.starts[b];
  return g;
}

}  // namespace clpt
