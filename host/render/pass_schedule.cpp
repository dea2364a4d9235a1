#include "render/pass_schedule.h"

#include <algorithm>

namespace clpt {

uint64_t next_pass_samples(const PassSchedule& schedule, uint64_t planned, uint64_t n,
                           double seconds) {
  if (!schedule.by_clock) return std::min(2 * planned, schedule.fixed_cap);
  const double seconds_per_spp = seconds / double(n);
  const double fit = seconds_per_spp > 0.0 ? schedule.pass_seconds / seconds_per_spp : 2.0 * n;
  return std::clamp<uint64_t>(uint64_t(fit), 1, 2 * n);
}

}  // namespace clpt
