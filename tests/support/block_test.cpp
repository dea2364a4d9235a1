#include "support/block_test.h"

#include <boost/math/distributions/students_t.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace clpt::test {

std::string BlockTestResult::summary() const {
  std::ostringstream s;
  s << failed << " of " << tests << " block-channels have |t| >= " << threshold << " (max |t| "
    << max_abs_t << ")";
  return s.str();
}

BlockTestResult block_means_test(const std::vector<Image>& batches, const Image& reference,
                                 const Image& reference_variance, uint32_t block, double alpha) {
  BlockTestResult r;
  const uint32_t bx = reference.width / block, by = reference.height / block;
  const size_t nb = batches.size();
  if (nb < 2 || bx == 0 || by == 0) return r;
  const double pixels = double(block) * block;
  auto block_mean = [&](const Image& img, uint32_t i, int c) {
    double sum = 0.0;
    for (uint32_t y = 0; y < block; ++y)
      for (uint32_t x = 0; x < block; ++x)
        sum += img.pixel((i % bx) * block + x, (i / bx) * block + y)[c];
    return sum / pixels;
  };
  r.tests = size_t(bx) * by * 3;
  const double per_test = 1.0 - std::pow(1.0 - alpha, 1.0 / double(r.tests));
  r.threshold = boost::math::quantile(
      boost::math::complement(boost::math::students_t(double(nb - 1)), per_test / 2.0));
  for (uint32_t i = 0; i < bx * by; ++i)
    for (int c = 0; c < 3; ++c) {
      std::vector<double> m(nb);
      double mean = 0.0;
      for (size_t b = 0; b < nb; ++b) mean += (m[b] = block_mean(batches[b], i, c));
      mean /= double(nb);
      double var = 0.0;
      for (double v : m) var += (v - mean) * (v - mean);
      var /= double(nb - 1) * double(nb);  // variance of the mean of the batch means
      // The reference's block mean and its variance (pixels independent).
      const double ref = block_mean(reference, i, c);
      const double ref_var = block_mean(reference_variance, i, c) / pixels;
      const double t = std::fabs(mean - ref) / std::sqrt(var + ref_var + 1e-12);
      r.max_abs_t = std::max(r.max_abs_t, t);
      r.failed += t >= r.threshold;
    }
  return r;
}

}  // namespace clpt::test
