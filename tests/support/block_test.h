// Agreement of a heavy-tailed estimator with a reference image, by block means over
// independent batches (../shared/TESTING.md): per-pixel sample variances are unreliable when
// most samples of a pixel miss a small light, but the mean of a block of pixels over a batch
// is close to normal, and with B batches the statistic is Student-t with B - 1 degrees of
// freedom. The threshold is Sidak-corrected over all block-channels (alpha 0.01 in all).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "io/image.h"

namespace clpt::test {

struct BlockTestResult {
  size_t tests = 0;        // block-channels
  size_t failed = 0;
  double threshold = 0.0;  // |t| at the Sidak level
  double max_abs_t = 0.0;
  std::string summary() const;
};

// batches: images of independent renders (same size as `reference`); reference_variance:
// the variance of the reference's per-pixel mean. Blocks are block x block pixels; the image
// size must be a multiple of `block`.
BlockTestResult block_means_test(const std::vector<Image>& batches, const Image& reference,
                                 const Image& reference_variance, uint32_t block,
                                 double alpha = 0.01);

}  // namespace clpt::test
