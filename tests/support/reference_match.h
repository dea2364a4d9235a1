// Whether independent batches of a splatting estimator (lt, bdpt) agree with a pt reference
// that has per-pixel variance: three checks, as EXPECTs in the calling test.
//   blocks   block means over the batches against the reference (support/block_test.h):
//            no block-channel may fail the Sidak-corrected Student-t test;
//   pixels   per-pixel z-test, the batches' sample variance / B as the mean's variance:
//            at least `min_pixel_pass` of the pixel-channels pass;
//   image    the image mean per channel, sigma from the batches' image means: |z| < 4.
#pragma once

#include <string>
#include <vector>

#include "io/image.h"
#include "render/film.h"

namespace clpt::test {

// The image mean of each channel over a set of batches, with the standard error of that
// mean from the spread of the batches' image means.
struct ChannelMeans {
  double mean[3], sigma[3];
};
ChannelMeans channel_means(const std::vector<Image>& batches);

void expect_matches_reference(const std::vector<Image>& batches, const FilmResult& reference,
                              const std::string& label, uint32_t block = 4,
                              double min_pixel_pass = 0.9975);

}  // namespace clpt::test
