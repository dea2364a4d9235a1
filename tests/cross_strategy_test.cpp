// CrossStrategy: every estimator choice renders the same Cornell box. A default path-traced
// reference (32 x 32, 8192 spp, with its per-pixel variance) is compared with
//  - well-behaved estimators by a per-pixel z-test (1024 spp, both images' variances,
//    Sidak threshold over all pixel-channels; >= 99.75 % must pass, ../shared/TESTING.md);
//  - heavy-tailed ones (BSDF sampling alone, against a small light: most pixels' samples
//    never find it, so a pixel's sample variance is unreliable) by 8 x 8-pixel block means
//    over 8 independent batches, whose distribution is close to normal; with 8 batches the
//    statistic is Student-t distributed with 7 degrees of freedom.
#include <gtest/gtest.h>

#include <cmath>
#include <ostream>

#include "render/renderer.h"
#include "stats/image_stats.h"
#include "support/block_test.h"
#include "support/device.h"
#include "support/reference_render.h"
#include "support/scenes.h"

namespace clpt::cross_strategy_test {
namespace {

struct Strategy {
  const char* name;
  uint32_t direct, mis, light_samples, hemisphere, rr;
  float rr_absorb;
  uint32_t branching, sampler;
};
void PrintTo(const Strategy& s, std::ostream* os) { *os << s.name; }

constexpr uint32_t kSize = 32;

RenderSettings settings_for(const Strategy& st, uint64_t spp, uint32_t seed) {
  RenderSettings s;
  s.width = s.height = kSize;
  s.spp = spp;
  s.seed = seed;
  s.direct = st.direct;
  s.mis = st.mis;
  s.light_samples = st.light_samples;
  s.hemisphere = st.hemisphere;
  s.rr = st.rr;
  s.rr_absorb = st.rr_absorb;
  s.branching = st.branching;
  s.sampler = st.sampler;
  return s;
}

const Scene& cornell() {
  static const Scene scene = test::cornell_box();
  return scene;
}

// pt with the default estimator choices (shared with other test processes, on disk).
const FilmResult& reference() {
  static const FilmResult ref =
      test::pt_reference(test::ReferenceScene::CornellBox, kSize, 8192, 4242);
  return ref;
}

class CrossStrategyPixels : public ::testing::TestWithParam<Strategy> {};

TEST_P(CrossStrategyPixels, MatchesReferencePerPixel) {
  const FilmResult& ref = reference();
  Renderer r(test::device_context(), cornell(), settings_for(GetParam(), 1024, 17));
  const FilmResult f = r.render().film;
  ASSERT_EQ(f.dropped_samples, 0u);
  const Image v = variance_of_mean(f.variance, f.samples_per_pixel);
  const Image rv = variance_of_mean(ref.variance, ref.samples_per_pixel);
  const ZTestResult z = z_test(f.mean, &v, ref.mean, &rv);
  EXPECT_GE(z.pass_fraction(), 0.9975)
      << z.failed() << " of " << z.tested << " pixel-channels fail |z| < " << z.threshold
      << " (max |z| " << z.max_abs_z << ")";
  // Per-pixel tests have little power against a small global bias; the image mean has a
  // 32x smaller sigma (pixels are independent: its variance is the sum of theirs / N^2).
  for (int c = 0; c < 3; ++c) {
    double m = 0.0, rm = 0.0, var = 0.0;
    const size_t n = size_t(kSize) * kSize;
    for (size_t i = 0; i < n; ++i) {
      m += f.mean.rgb[i * 3 + c];
      rm += ref.mean.rgb[i * 3 + c];
      var += v.rgb[i * 3 + c] + rv.rgb[i * 3 + c];
    }
    const double image_z = std::fabs(m - rm) / std::sqrt(var);
    EXPECT_LT(image_z, 4.0) << "channel " << c << ": image mean " << m / n << " vs reference "
                            << rm / n;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cornell, CrossStrategyPixels,
    ::testing::Values(
        Strategy{"mis_balance", dev::DIRECT_MIS, dev::MIS_BALANCE, 1, 0, 0, 0.0f, 1, 0},
        Strategy{"light_only", dev::DIRECT_LIGHT, 0, 1, 0, 0, 0.0f, 1, 0},
        Strategy{"light_samples_4", dev::DIRECT_MIS, 0, 4, 0, 0, 0.0f, 1, 0},
        Strategy{"cosine_hemisphere", dev::DIRECT_MIS, 0, 1, dev::HEMISPHERE_COSINE, 0, 0.0f, 1, 0},
        Strategy{"uniform_hemisphere", dev::DIRECT_MIS, 0, 1, dev::HEMISPHERE_UNIFORM, 0, 0.0f, 1, 0},
        Strategy{"rr_fixed_0_5", dev::DIRECT_MIS, 0, 1, 0, dev::RR_FIXED, 0.5f, 1, 0},
        Strategy{"branching_4", dev::DIRECT_MIS, 0, 1, 0, 0, 0.0f, 4, 0},
        Strategy{"stratified", dev::DIRECT_MIS, 0, 1, 0, 0, 0.0f, 1, dev::SAMPLER_STRATIFIED},
        Strategy{"lhs", dev::DIRECT_MIS, 0, 1, 0, 0, 0.0f, 1, dev::SAMPLER_LHS},
        Strategy{"sobol", dev::DIRECT_MIS, 0, 1, 0, 0, 0.0f, 1, dev::SAMPLER_SOBOL}),
    [](const auto& info) { return std::string(info.param.name); });

class CrossStrategyBlocks : public ::testing::TestWithParam<Strategy> {};

TEST_P(CrossStrategyBlocks, MatchesReferenceInBlockMeans) {
  constexpr uint32_t kBlock = 8, kBatches = 8;
  const FilmResult& ref = reference();
  std::vector<Image> batches;
  for (uint32_t b = 0; b < kBatches; ++b) {
    Renderer r(test::device_context(), cornell(), settings_for(GetParam(), 256, 300 + b));
    const FilmResult f = r.render().film;
    ASSERT_EQ(f.dropped_samples, 0u);
    batches.push_back(f.mean);
  }
  const test::BlockTestResult t = test::block_means_test(
      batches, ref.mean, variance_of_mean(ref.variance, ref.samples_per_pixel), kBlock);
  EXPECT_EQ(t.failed, 0u) << t.summary();
}

INSTANTIATE_TEST_SUITE_P(
    Cornell, CrossStrategyBlocks,
    ::testing::Values(
        Strategy{"bsdf_only", dev::DIRECT_BSDF, 0, 1, 0, 0, 0.0f, 1, 0},
        Strategy{"bsdf_only_uniform_hemisphere", dev::DIRECT_BSDF, 0, 1, dev::HEMISPHERE_UNIFORM, 0, 0.0f, 1, 0}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace clpt::cross_strategy_test
