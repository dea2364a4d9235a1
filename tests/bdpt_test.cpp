// Bidirectional path tracing (--integrator bdpt) on the PoCL device:
//   SphereFurnaceBdpt   the furnace's closed form, z-test over independent batches;
//   CrossIntegrator     bdpt against a high-spp pt reference on the Cornell box and on the
//                       Cornell box with a glossy metal block and a glass block
//                       (support/reference_match.h: block means, per-pixel z, image mean);
//   BdptStrategies      each strategy of 2-bounce paths rendered alone and unweighted
//                       (--bdpt-strategy S,T --bdpt-unweighted) converges to the same image
//                       as pt's 2-bounce light; the weighted strategies add up to it;
//   Bdpt.*              usage errors and the light vertex buffer's tiling.
// The MIS weights themselves are checked path by path against explicit whole-path densities
// in tests/bdpt_mis_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numeric>
#include <vector>

#include "integrators/bdpt.h"
#include "render/renderer.h"
#include "stats/image_stats.h"
#include "support/device.h"
#include "support/reference_match.h"
#include "support/scenes.h"
#include "util/error.h"

namespace clpt {
namespace {

struct FurnaceCase {
  float rho;
  uint32_t max_depth;
};

class SphereFurnaceBdpt : public ::testing::TestWithParam<FurnaceCase> {};

TEST_P(SphereFurnaceBdpt, MatchesClosedForm) {
  const FurnaceCase c = GetParam();
  const Scene scene = test::furnace_scene(c.rho, 1.0f);
  const double expected = test::furnace_radiance(c.rho, 1.0, c.max_depth);
  constexpr int kBatches = 30;
  std::vector<Image> batches;
  for (int b = 0; b < kBatches; ++b) {
    RenderSettings s;
    s.width = s.height = 16;
    s.spp = 32;
    s.max_depth = c.max_depth;
    s.seed = 3000 + b;
    s.integrator = "bdpt";
    Renderer r(test::device_context(), scene, s);
    const RenderOutput out = r.render();
    ASSERT_EQ(out.film.samples_per_pixel, 32u);
    ASSERT_EQ(out.film.dropped_samples, 0u);
    batches.push_back(out.film.mean);
  }
  const BatchMean bm = batch_mean(batches);
  if (c.max_depth == 0) {
    // Only the camera seeing the emitters (s = 0, t = 2, weight 1): exact, no variance.
    EXPECT_NEAR(bm.mean, expected, 1e-6 * expected);
    return;
  }
  const double z = (bm.mean - expected) / bm.sigma;
  EXPECT_LT(std::fabs(z), 4.0) << "mean " << bm.mean << " expected " << expected << " sigma " << bm.sigma;
  EXPECT_LT(4.0 * bm.sigma, 0.01 * expected) << "too few samples for a meaningful test";
  std::cout << "[ figures  ] bdpt furnace rho " << c.rho << " depth " << c.max_depth << ": mean "
            << bm.mean << " expected " << expected << " sigma " << bm.sigma << " z " << z << "\n";
}

INSTANTIATE_TEST_SUITE_P(Cases, SphereFurnaceBdpt,
                         ::testing::Values(FurnaceCase{0.5f, 0}, FurnaceCase{0.5f, 1},
                                           FurnaceCase{0.5f, 3}, FurnaceCase{0.8f, 8}),
                         [](const auto& info) {
                           return "rho" + std::to_string(int(info.param.rho * 100)) + "_depth" +
                                  std::to_string(info.param.max_depth);
                         });

constexpr uint32_t kSize = 32;

FilmResult render(const Scene& scene, const std::string& integrator, uint64_t spp, uint32_t seed,
                  uint32_t max_depth = 8, uint32_t bdpt_s = BDPT_ALL_STRATEGIES,
                  uint32_t bdpt_t = 0, bool unweighted = false, uint32_t size = kSize,
                  uint32_t lvc = 0) {
  RenderSettings s;
  s.bdpt_lvc = lvc;
  s.width = s.height = size;
  s.spp = spp;
  s.seed = seed;
  s.max_depth = max_depth;
  s.integrator = integrator;
  s.bdpt_s = bdpt_s;
  s.bdpt_t = bdpt_t;
  s.bdpt_unweighted = unweighted;
  Renderer r(test::device_context(), scene, s);
  return r.render().film;
}

std::vector<Image> bdpt_batches(const Scene& scene, uint32_t batches, uint64_t spp, uint32_t seed0,
                                uint32_t lvc = 0) {
  std::vector<Image> out;
  for (uint32_t b = 0; b < batches; ++b) {
    const FilmResult f =
        render(scene, "bdpt", spp, seed0 + b, 8, BDPT_ALL_STRATEGIES, 0, false, kSize, lvc);
    EXPECT_EQ(f.dropped_samples, 0u);
    out.push_back(f.mean);
  }
  return out;
}

TEST(CrossIntegrator, BdptMatchesPtOnCornellBox) {
  const Scene scene = test::cornell_box();
  const FilmResult ref = render(scene, "pt", 8192, 4242);
  test::expect_matches_reference(bdpt_batches(scene, 16, 32, 700), ref, "bdpt cornell");
}

// Light vertex caching: each camera vertex connects to 2 vertices drawn from all the light
// subpaths' vertices of the tile, scaled by cache size / (2 paths); with a tiny memory budget
// the tiles (and so the caches) are small, which must not matter either.
TEST(CrossIntegrator, BdptWithLightVertexCachingMatchesPt) {
  const Scene scene = test::cornell_box();
  const FilmResult ref = render(scene, "pt", 8192, 4242);
  test::expect_matches_reference(bdpt_batches(scene, 16, 32, 1700, 2), ref, "bdpt lvc 2");
  std::vector<Image> small;
  for (uint32_t b = 0; b < 12; ++b) {
    RenderSettings s;
    s.width = s.height = kSize;
    s.spp = 32;
    s.seed = 1800 + b;
    s.integrator = "bdpt";
    s.bdpt_lvc = 3;
    s.bdpt_memory_bytes = 7 * 128 * 100;  // about 100 light paths per tile and cache
    small.push_back(Renderer(test::device_context(), scene, s).render().film.mean);
  }
  test::expect_matches_reference(small, ref, "bdpt lvc 3, caches of ~100 paths");
}

TEST(CrossIntegrator, BdptMatchesPtWithGlossyAndGlass) {
  const Scene scene = test::cornell_box_glossy_glass();
  const FilmResult ref = render(scene, "pt", 16384, 4343);
  // The floor under the glass block, seen through it, is lit only by S D S paths: bdpt has
  // one strategy for them (s = 0, the camera path hits the light), as pt has, and at 512 spp
  // per pixel their batch variance underestimates a heavy tail (measured: a handful of those
  // pixels at |z| 5 to 7.4, both signs at higher spp, region means within 3 % of pt). Block
  // means and the image mean stay strict; the per-pixel pass fraction allows 1 %.
  test::expect_matches_reference(bdpt_batches(scene, 16, 32, 800), ref, "bdpt glossy+glass", 4, 0.99);
}

// Infinite and delta lights take their own branches of the MIS weights (no distance factor
// on the first segment, emission from a disk of the scene's bounding radius, delta
// positions and directions). The Cornell box is open towards the camera: with its ceiling
// light, a constant background and a directional light shining in through the open side,
// and a point and a spot light inside, every light type contributes.
TEST(CrossIntegrator, BdptMatchesPtWithEnvironmentAndPunctualLights) {
  Scene scene = test::cornell_box();
  PunctualLight sun;
  sun.type = PunctualLight::Type::Directional;
  sun.intensity = 2.0f;
  sun.direction = glm::normalize(glm::vec3(0.3f, -0.5f, -1.0f));
  scene.lights.push_back(sun);
  PunctualLight point;
  point.type = PunctualLight::Type::Point;
  point.intensity = 0.02f;
  point.color = glm::vec3(0.5f, 0.7f, 1.0f);
  point.position = glm::vec3(0.15f, 0.45f, -0.15f);
  scene.lights.push_back(point);
  PunctualLight spot;
  spot.type = PunctualLight::Type::Spot;
  spot.intensity = 0.05f;
  spot.position = glm::vec3(0.45f, 0.5f, -0.45f);
  spot.direction = glm::normalize(glm::vec3(-0.5f, -1.0f, 0.4f));
  spot.inner_cone = 0.2f;
  spot.outer_cone = 0.5f;
  scene.lights.push_back(spot);
  auto settings = [](const std::string& integrator, uint64_t spp, uint32_t seed) {
    RenderSettings s;
    s.width = s.height = kSize;
    s.spp = spp;
    s.seed = seed;
    s.integrator = integrator;
    s.background = glm::vec3(0.3f, 0.4f, 0.5f);
    return s;
  };
  const FilmResult ref = Renderer(test::device_context(), scene, settings("pt", 8192, 4545)).render().film;
  std::vector<Image> batches;
  for (uint32_t b = 0; b < 16; ++b) {
    const FilmResult f = Renderer(test::device_context(), scene, settings("bdpt", 32, 900 + b)).render().film;
    EXPECT_EQ(f.dropped_samples, 0u);
    batches.push_back(f.mean);
  }
  test::expect_matches_reference(batches, ref, "bdpt environment+punctual");
}

using test::channel_means;
using test::ChannelMeans;

// Paths of exactly 2 bounces (4 vertices) have the strategies (s, t) = (0, 4), (1, 3), (2, 2)
// and (3, 1). Each alone, unweighted, is an unbiased estimator of the light those paths
// carry; pt's estimate of it is the difference of max depth 2 and 1 with the same seeds (the
// paths agree up to their first bounce, so the difference is exactly their 2-bounce part).
TEST(BdptStrategies, UnweightedStrategiesAgreeWithPt) {
  const Scene scene = test::cornell_box();
  constexpr uint32_t kBatches = 12, kSize16 = 16;
  std::vector<Image> pt2;
  for (uint32_t b = 0; b < kBatches; ++b) {
    const FilmResult d2 = render(scene, "pt", 256, 900 + b, 2, BDPT_ALL_STRATEGIES, 0, false, kSize16);
    const FilmResult d1 = render(scene, "pt", 256, 900 + b, 1, BDPT_ALL_STRATEGIES, 0, false, kSize16);
    Image diff = d2.mean;
    for (size_t i = 0; i < diff.rgb.size(); ++i) diff.rgb[i] -= d1.mean.rgb[i];
    pt2.push_back(diff);
  }
  const ChannelMeans ref = channel_means(pt2);
  struct Strategy {
    uint32_t s, t;
    uint64_t spp;
  };
  // s = 0 must hit the small light by chance: more samples.
  const Strategy strategies[] = {{0, 4, 1024}, {1, 3, 128}, {2, 2, 128}, {3, 1, 128}};
  std::vector<Image> weighted_sum(kBatches, Image(kSize16, kSize16));
  for (const Strategy& st : strategies) {
    std::vector<Image> unweighted;
    for (uint32_t b = 0; b < kBatches; ++b) {
      const uint32_t seed = 1000 + 37 * st.s + b;
      unweighted.push_back(render(scene, "bdpt", st.spp, seed, 2, st.s, st.t, true, kSize16).mean);
      const Image w = render(scene, "bdpt", 128, seed, 2, st.s, st.t, false, kSize16).mean;
      for (size_t i = 0; i < w.rgb.size(); ++i) weighted_sum[b].rgb[i] += w.rgb[i];
    }
    const ChannelMeans m = channel_means(unweighted);
    for (int c = 0; c < 3; ++c) {
      const double z = (m.mean[c] - ref.mean[c]) / std::hypot(m.sigma[c], ref.sigma[c]);
      EXPECT_LT(std::fabs(z), 4.0) << "strategy " << st.s << "," << st.t << " channel " << c << ": "
                                   << m.mean[c] << " pt " << ref.mean[c];
      std::cout << "[ figures  ] unweighted (" << st.s << "," << st.t << ") channel " << c << ": "
                << m.mean[c] << " +- " << m.sigma[c] << ", pt " << ref.mean[c] << " +- "
                << ref.sigma[c] << ", z " << z << "\n";
    }
  }
  const ChannelMeans sum = channel_means(weighted_sum);
  for (int c = 0; c < 3; ++c) {
    const double z = (sum.mean[c] - ref.mean[c]) / std::hypot(sum.sigma[c], ref.sigma[c]);
    EXPECT_LT(std::fabs(z), 4.0) << "weighted sum, channel " << c;
    std::cout << "[ figures  ] weighted strategies summed, channel " << c << ": " << sum.mean[c]
              << " +- " << sum.sigma[c] << ", z " << z << "\n";
  }
}

TEST(Bdpt, TilesGiveTheSameImageAsOnePass) {
  // A budget of a few paths forces many tiles; the estimate must not change beyond float
  // summation order (splats are atomic adds in no fixed order).
  const Scene scene = test::cornell_box();
  RenderSettings s;
  s.width = s.height = 16;
  s.spp = 8;
  s.seed = 5;
  s.integrator = "bdpt";
  Renderer whole(test::device_context(), scene, s);
  const FilmResult a = whole.render().film;
  s.bdpt_memory_bytes = 7 * 128 * 37;  // 37 light paths per tile at max depth 8
  Renderer tiled(test::device_context(), scene, s);
  const FilmResult b = tiled.render().film;
  ASSERT_EQ(a.mean.rgb.size(), b.mean.rgb.size());
  double max_rel = 0.0;
  for (size_t i = 0; i < a.mean.rgb.size(); ++i)
    max_rel = std::max(max_rel, std::fabs(double(a.mean.rgb[i]) - b.mean.rgb[i]) /
                                    (std::fabs(double(a.mean.rgb[i])) + 1e-3));
  EXPECT_LT(max_rel, 1e-4);
  EXPECT_EQ(BidirectionalPathTracer::tile_paths(7 * 128 * 37 + 37 * 4, 7, 256), 37u);
  EXPECT_EQ(BidirectionalPathTracer::tile_paths(size_t(1) << 30, 7, 256), 256u);
  EXPECT_EQ(BidirectionalPathTracer::vertex_capacity(8), 7u);
  EXPECT_EQ(BidirectionalPathTracer::vertex_capacity(0), 1u);
}

TEST(Bdpt, RefusesOrthographicCameras) {
  Scene scene = test::furnace_scene(0.5f, 1.0f);
  scene.cameras[0].type = Camera::Type::Orthographic;
  try {
    render(scene, "bdpt", 1, 0, 8, BDPT_ALL_STRATEGIES, 0, false, 8);
    FAIL() << "an orthographic camera was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::Usage);
    EXPECT_NE(std::string(e.what()).find("orthographic"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace clpt
