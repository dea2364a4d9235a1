// --vcm-light-paths auto: how many light subpaths per pixel and pass (K) vcm traces, chosen
// by measured efficiency, the course's 1 / (variance x cost). More subpaths make merging
// denser (caustics seen through glass) at a light subpath's cost each; where the light is
// mostly direct they cost without helping (docs/BENCHMARKS.md, session 34: K = 4 is 1.6x
// better than K = 1 on the glass table at equal time and 1.9x worse in the glass room). No
// property of a scene known before rendering tells the two apart, so passes measure: after
// kWarmUp passes at K = 1 (the first passes' wide radii and cold caches are not the render's
// steady state), rounds of one pass per candidate K, each pass's image (the film's sums and
// splats after it less before it: one sample per pixel) and its seconds. Per candidate the
// relMSE one second of such passes would give (docs/concepts/vcm.md):
//   cost_K = seconds per pass x mean over pixels and channels of var_K / (|I| + 0.01)^2,
// var_K the sample variance of its passes, I the mean of all pilot passes blurred over 5 x 5
// pixels, and each pixel's term held at most at its 99.9th percentile. The candidate of least
// cost wins (ties: the smaller K). The blur and the bound are what make the estimate work
// with three passes per candidate on heavy-tailed light: with each pixel's own mean in the
// denominator a rare bright pass raises both and hides the variance (the glass table then
// measured K = 1 best, where at equal time K = 4 has 1.6x less error), and one firefly in
// one candidate's passes would otherwise decide alone (docs/BENCHMARKS.md, session 35). Every
// pass is an unbiased pass of the render, so none is wasted.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace clpt {

class LightPathPilot {
 public:
  static constexpr std::array<uint32_t, 3> kCandidates = {1, 2, 4};
  static constexpr uint32_t kWarmUp = 16;  // passes at K = 1 before the pilot
  static constexpr uint32_t kRounds = 3;   // passes per candidate (2 degrees of freedom each)
  static constexpr uint32_t kPasses = kRounds * uint32_t(kCandidates.size());
  // Renders with fewer passes planned than this take K = 1 without a pilot: the pilot would
  // be most of the render.
  static constexpr uint64_t kMinPlannedPasses = 2 * (kWarmUp + kPasses);
  // Pixels the statistics read at most: larger films are read on a grid of every s-th row
  // and column.
  static constexpr size_t kMaxPixels = size_t(1) << 16;
  static constexpr int kBlurRadius = 2;         // the denominator's box blur, in grid pixels
  static constexpr double kTermQuantile = 0.999;  // the bound on a pixel's term

  struct Candidate {
    uint32_t k = 0;
    uint32_t passes = 0;
    double seconds = 0.0;            // all its passes
    double relative_variance = 0.0;  // of one pass, relMSE-like (see above); after the pilot
    // relMSE per second of such passes: relative_variance x seconds per pass (after the pilot).
    double cost = 0.0;
  };

  // A pilot over a film of width x height pixels.
  LightPathPilot(uint32_t width, uint32_t height);

  bool done() const { return passes_ == kPasses; }
  // The candidate K the next pilot pass renders (rounds alternate ascending and descending,
  // so that a drift in the machine's speed falls on all alike).
  uint32_t next_k() const;
  // The sampled pixels (at most kMaxPixels): the film index of sampled pixel i.
  size_t pixel(size_t i) const {
    return (i / grid_width_) * stride_ * width_ + (i % grid_width_) * stride_;
  }
  size_t sampled_pixels() const { return grid_width_ * grid_height_; }
  // Adds the pass next_k() rendered: its image at the sampled pixels (RGB, 3 floats each)
  // and its seconds. The last one decides.
  void add_pass(const std::vector<float>& rgb, double seconds);
  // After done(): the K chosen, and every candidate's figures.
  uint32_t chosen() const { return chosen_; }
  const std::array<Candidate, kCandidates.size()>& candidates() const { return candidates_; }

 private:
  void decide();

  size_t width_ = 0, stride_ = 1, grid_width_ = 0, grid_height_ = 0;
  uint32_t passes_ = 0;
  uint32_t chosen_ = 0;
  std::array<Candidate, kCandidates.size()> candidates_{};
  // Per candidate, per sampled pixel and channel: the sum and the sum of squares of its passes.
  std::array<std::vector<double>, kCandidates.size()> sum_, sum_sq_;
  std::vector<uint8_t> finite_;  // per sampled pixel and channel: 0 once a pass gave NaN or inf
};

}  // namespace clpt
