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
#include "render/renderer.h"
#include "scene/scene.h"

namespace clpt::test {

// `count` independent renders of `scene` with `settings` and seeds seed0, seed0 + 1, ...:
// their mean images. Each must reach settings.spp with no dropped sample, and report a
// per-pixel variance exactly when its integrator does not splat.
std::vector<Image> render_batches(const Scene& scene, RenderSettings settings, uint32_t count,
                                  uint32_t seed0);

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
