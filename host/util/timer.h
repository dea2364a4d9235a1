// Wall-clock timing of host work (BVH build, passes, photon maps).
#pragma once

#include <chrono>

namespace clpt {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace clpt
