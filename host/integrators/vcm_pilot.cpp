#include "integrators/vcm_pilot.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "stats/image_stats.h"

namespace clpt {

LightPathPilot::LightPathPilot(uint32_t width, uint32_t height) : width_(width) {
  const size_t pixels = size_t(width) * height;
  while (pixels / (stride_ * stride_) > kMaxPixels) ++stride_;
  grid_width_ = width ? (width - 1) / stride_ + 1 : 0;
  grid_height_ = height ? (height - 1) / stride_ + 1 : 0;
  for (size_t c = 0; c < kCandidates.size(); ++c) {
    candidates_[c].k = kCandidates[c];
    sum_[c].assign(3 * sampled_pixels(), 0.0);
    sum_sq_[c].assign(3 * sampled_pixels(), 0.0);
  }
  finite_.assign(3 * sampled_pixels(), 1);
}

uint32_t LightPathPilot::next_k() const {
  const size_t n = kCandidates.size();
  const size_t round = passes_ / n, at = passes_ % n;
  return kCandidates[round % 2 == 0 ? at : n - 1 - at];
}

void LightPathPilot::add_pass(const std::vector<float>& rgb, double seconds) {
  if (done()) throw std::logic_error("LightPathPilot: a pass after the pilot");
  if (rgb.size() != 3 * sampled_pixels())
    throw std::logic_error("LightPathPilot: a pass of another size");
  const uint32_t k = next_k();
  size_t c = 0;
  while (kCandidates[c] != k) ++c;
  for (size_t i = 0; i < rgb.size(); ++i) {
    const double x = rgb[i];
    if (!std::isfinite(x)) finite_[i] = 0;
    sum_[c][i] += x;
    sum_sq_[c][i] += x * x;
  }
  candidates_[c].passes += 1;
  candidates_[c].seconds += seconds;
  if (++passes_ == kPasses) decide();
}

void LightPathPilot::decide() {
  const size_t n = kCandidates.size(), w = grid_width_, h = grid_height_, values = 3 * w * h;
  // The relMSE's reference: every pilot pass's mean, blurred over (2 kBlurRadius + 1)^2 grid
  // pixels (those inside the image), so that no pixel's own few passes set its weight. A
  // pixel-channel that was ever NaN or infinite (the kernels drop such samples, so none
  // should be) is left out of all of it.
  std::vector<double> mean(values, 0.0);
  for (size_t c = 0; c < n; ++c)
    for (size_t i = 0; i < values; ++i) mean[i] += finite_[i] ? sum_[c][i] / double(kPasses) : 0.0;
  std::vector<double> weight(values, 0.0);
  for (size_t y = 0; y < h; ++y)
    for (size_t x = 0; x < w; ++x) {
      const size_t y0 = y >= size_t(kBlurRadius) ? y - kBlurRadius : 0, y1 = std::min(h, y + kBlurRadius + 1);
      const size_t x0 = x >= size_t(kBlurRadius) ? x - kBlurRadius : 0, x1 = std::min(w, x + kBlurRadius + 1);
      for (size_t ch = 0; ch < 3; ++ch) {
        double s = 0.0;
        size_t count = 0;
        for (size_t yy = y0; yy < y1; ++yy)
          for (size_t xx = x0; xx < x1; ++xx) {
            const size_t j = 3 * (yy * w + xx) + ch;
            s += std::abs(mean[j]);
            count += finite_[j];
          }
        const double d = (count ? s / double(count) : 0.0) + kRelMseOffset;
        weight[3 * (y * w + x) + ch] = 1.0 / (d * d);
      }
    }
  std::vector<double> terms;
  terms.reserve(values);
  for (size_t c = 0; c < n; ++c) {
    Candidate& cand = candidates_[c];
    const double m = cand.passes;
    terms.clear();
    for (size_t i = 0; i < values; ++i) {
      if (!finite_[i]) continue;
      const double var = (sum_sq_[c][i] - sum_[c][i] * sum_[c][i] / m) / (m - 1.0);
      terms.push_back(std::max(0.0, var) * weight[i]);
    }
    double rel = 0.0;
    if (!terms.empty()) {
      std::vector<double> sorted = terms;
      const size_t q = std::min(terms.size() - 1, size_t(kTermQuantile * double(terms.size())));
      std::nth_element(sorted.begin(), sorted.begin() + q, sorted.end());
      for (double t : terms) rel += std::min(t, sorted[q]);
      rel /= double(terms.size());
    }
    cand.relative_variance = rel;
    cand.cost = cand.relative_variance * cand.seconds / m;
  }
  // The smallest cost wins; ties keep the smaller K.
  chosen_ = kCandidates[0];
  double best = candidates_[0].cost;
  for (size_t c = 1; c < n; ++c)
    if (candidates_[c].cost < best) {
      best = candidates_[c].cost;
      chosen_ = candidates_[c].k;
    }
  sum_ = {};
  sum_sq_ = {};
  finite_ = {};
}

}  // namespace clpt
