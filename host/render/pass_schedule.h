// How many samples per pixel each pass of Renderer::render takes. Passes aim at a length of
// time (--pass-seconds: 0.1 s on CPUs, 0.03 s on GPUs), so that progress, Ctrl-C and --time
// act between them and a GPU kernel stays far below a display driver's watchdog (about 2 s
// on Windows, 5 s under an X server).
#pragma once

#include <cstdint>
#include <vector>

namespace clpt {

struct PassSchedule {
  double pass_seconds = 0.1;  // the length a pass aims at
  // false: passes double from 1 sample up to fixed_cap whatever the clock says, for
  // integrators whose image depends on how samples are split into passes (Metropolis), so
  // that a seed gives one image on any machine.
  bool by_clock = true;
  uint64_t fixed_cap = 1;
};

// The next pass's samples per pixel after a pass planned at `planned` samples ran `n` of them
// (fewer in a render's last pass) in `seconds`. By the clock: what fits pass_seconds at the
// speed just seen, at least 1 and at most twice n; otherwise twice `planned`, up to fixed_cap.
uint64_t next_pass_samples(const PassSchedule& schedule, uint64_t planned, uint64_t n,
                           double seconds);

// A pass's shares over several devices: each device's own next_pass_samples (`wanted`), and
// when they add up to more than `left` (the samples per pixel the target leaves; 0: no target),
// scaled down in proportion, the first devices taking the remainder one sample each, so that
// the shares add up to `left` and the first device always works (it takes the render's sample
// 0). Device i then renders the indices after those of devices 0 to i - 1.
std::vector<uint64_t> share_samples(std::vector<uint64_t> wanted, uint64_t left);

// One pass of a single sample per pixel that runs this long on a GPU is worth a warning: no
// smaller pass exists, and a display's watchdog may stop the kernel.
constexpr double kWatchdogWarningSeconds = 1.0;

}  // namespace clpt
