// End-to-end estimator tests of the path tracer on the PoCL device:
// SphereFurnace (analytic answer, z-test over independent batches) and Determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numeric>

#include "render/renderer.h"
#include "stats/image_stats.h"
#include "support/device.h"
#include "support/reference_match.h"
#include "support/scenes.h"

namespace clpt::render_test {
namespace {

using test::FurnaceCase;

class SphereFurnace : public ::testing::TestWithParam<FurnaceCase> {};

// Each batch is an independent render (its own seed); the batch means are i.i.d. with the
// integrator's expectation, so z = (mean - L) / (sd / sqrt(B)) is ~N(0,1) when it is right.
TEST_P(SphereFurnace, PtMatchesClosedForm) {
  const FurnaceCase c = GetParam();
  const Scene scene = test::furnace_scene(c.rho, 1.0f);
  const double expected = test::furnace_radiance(c.rho, 1.0, c.max_depth);
  RenderSettings s;
  s.width = s.height = 24;
  s.spp = 8;
  s.max_depth = c.max_depth;
  const BatchMean bm = batch_mean(test::render_batches(scene, s, 12, 1000));
  const double mean = bm.mean, sigma = bm.sigma;
  if (sigma == 0.0) {
    EXPECT_NEAR(mean, expected, 1e-6) << "deterministic case (no scattering)";
  } else {
    const double z = (mean - expected) / sigma;
    EXPECT_LT(std::fabs(z), 4.0) << "rho " << c.rho << " depth " << c.max_depth << ": mean "
                                 << mean << " expected " << expected << " sigma " << sigma;
    // The test must be able to see a wrong answer: a 2% error must be far outside 4 sigma.
    EXPECT_LT(4.0 * sigma, 0.02 * expected) << "too few samples for a meaningful test";
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, SphereFurnace,
                         ::testing::Values(FurnaceCase{0.5f, 0}, FurnaceCase{0.5f, 1},
                                           FurnaceCase{0.5f, 3}, FurnaceCase{0.8f, 8},
                                           FurnaceCase{0.95f, 20}),
                         [](const auto& info) { return test::furnace_case_name(info.param); });

FilmResult render_cornell(uint32_t seed, uint64_t spp, uint32_t max_per_pass) {
  static const Scene scene = test::cornell_box();
  RenderSettings s;
  s.width = s.height = 32;
  s.spp = spp;
  s.seed = seed;
  s.max_samples_per_pass = max_per_pass;
  s.target_pass_seconds = 1e9;  // one pass for everything unless capped
  Renderer r(test::device_context(), scene, s);
  return r.render().film;
}

bool bitwise_equal(const Image& a, const Image& b) {
  return a.rgb.size() == b.rgb.size() &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

TEST(Determinism, SameSeedSameImage) {
  const FilmResult a = render_cornell(7, 4, 0), b = render_cornell(7, 4, 0);
  EXPECT_TRUE(bitwise_equal(a.mean, b.mean));
  EXPECT_GT(image_mean(a.mean), 0.0);
}

TEST(Determinism, PassesOfOneEqualOneRun) {
  const FilmResult one_run = render_cornell(7, 4, 0), passes = render_cornell(7, 4, 1);
  EXPECT_TRUE(bitwise_equal(one_run.mean, passes.mean));
  EXPECT_TRUE(bitwise_equal(one_run.variance, passes.variance));
}

TEST(Determinism, OtherSeedOtherImage) {
  const FilmResult a = render_cornell(7, 4, 0), b = render_cornell(8, 4, 0);
  EXPECT_FALSE(bitwise_equal(a.mean, b.mean));
}

}  // namespace
}  // namespace clpt::render_test
