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

std::vector<uint64_t> share_samples(std::vector<uint64_t> wanted, uint64_t left) {
  uint64_t want = 0;
  for (uint64_t w : wanted) want += w;
  if (left == 0 || want <= left || wanted.empty()) return wanted;
  uint64_t given = 0;
  // 128 bits: a share and what is left may each pass 2^32.
  for (uint64_t& w : wanted)
    given += w = static_cast<uint64_t>(static_cast<unsigned __int128>(w) * left / want);
  for (size_t i = 0; given < left; i = (i + 1) % wanted.size(), ++given) ++wanted[i];
  return wanted;
}

}  // namespace clpt
