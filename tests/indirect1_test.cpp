// The one-bounce indirect integrator (--integrator indirect1) and its three generators of
// paths x <- y <- light (kernels/integrators/indirect/generators.cl):
//   IndirectFurnace   each generator against the closed form: in a closed enclosure whose
//                     every surface emits Le and reflects rho (Lambert), the light after
//                     exactly one bounce is rho^2 Le (direct light is rho Le, whatever the
//                     enclosure's shape: its view factors sum to 1);
//   IndirectGenerators on the Cornell box, receiver gathering against pt's one-bounce light
//                     (pt at --max-depth 2 less pt at --max-depth 1 with the same seeds: the
//                     difference of each sample is exactly pt's paths of one bounce), then
//                     source shooting and surface sampling against receiver gathering;
//                     batches, block means and image means (support/reference_match.h),
//                     as the heavy tails of G(x, y) near the box's edges need;
//   IndirectArea      the surface-area distribution;
//   IndirectCli       --indirect's usage rules and --stats.
#include <gtest/gtest.h>

#include <algorithm>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "integrators/indirect1.h"
#include "render/renderer.h"
#include "shared/indirect_types.h"
#include "stats/image_stats.h"
#include "support/device.h"
#include "support/parse_options.h"
#include "support/reference_match.h"
#include "support/render.h"
#include "support/run.h"
#include "support/scenes.h"
#include "util/error.h"

namespace clpt::indirect1_test {
namespace {

using test::parse_error;

struct Generator {
  const char* name;
  uint32_t id;
};
void PrintTo(const Generator& g, std::ostream* os) { *os << g.name; }  // gtest's description
const Generator kGenerators[] = {{"receiver", dev::INDIRECT_RECEIVER},
                                 {"source", dev::INDIRECT_SOURCE},
                                 {"surface", dev::INDIRECT_SURFACE}};

RenderSettings indirect_settings(uint32_t generator, uint64_t spp, uint32_t size) {
  RenderSettings s = test::render_settings("indirect1", spp, size);
  s.indirect = generator;
  return s;
}

class IndirectFurnace : public ::testing::TestWithParam<Generator> {};

TEST_P(IndirectFurnace, MatchesClosedForm) {
  const Generator g = GetParam();
  const float rho = 0.5f;
  const Scene scene = test::furnace_scene(rho, 1.0f);
  const double expected = double(rho) * rho;
  const BatchMean bm =
      batch_mean(test::render_batches(scene, indirect_settings(g.id, 32, 24), 12, 3000));
  const double z = (bm.mean - expected) / bm.sigma;
  EXPECT_LT(std::fabs(z), 4.0) << g.name << ": mean " << bm.mean << " expected " << expected
                               << " sigma " << bm.sigma;
  EXPECT_LT(4.0 * bm.sigma, 0.02 * expected) << "too few samples for a meaningful test";
  std::cout << "[ figures  ] indirect1 " << g.name << " furnace: mean " << bm.mean
            << " expected " << expected << " z " << z << "\n";
}

INSTANTIATE_TEST_SUITE_P(Generators, IndirectFurnace, ::testing::ValuesIn(kGenerators),
                         [](const auto& info) { return std::string(info.param.name); });

constexpr uint32_t kSize = 32;

const Scene& cornell() {
  static const Scene scene = test::cornell_box();
  return scene;
}

const FilmResult& receiver_reference() {
  static const FilmResult ref =
      test::render(cornell(), indirect_settings(dev::INDIRECT_RECEIVER, 8192, kSize), 4243);
  return ref;
}

TEST(IndirectGenerators, ReceiverMatchesPtOneBounceLight) {
  // Batches of pt's one-bounce light: each pair of renders shares its seed, so the pixel
  // difference is the sum of the same samples' depth-2 terms (NEE at y and the emission its
  // BSDF ray finds, MIS-weighted); Cornell's surfaces are all Lambertian, so those paths are
  // exactly the ones indirect1 counts.
  std::vector<Image> batches;
  for (uint32_t b = 0; b < 16; ++b) {
    RenderSettings s = test::render_settings("pt", 256, kSize);
    s.seed = 5000 + b;
    s.max_depth = 2;
    const FilmResult two = Renderer(test::device_context(), cornell(), s).render().film;
    s.max_depth = 1;
    const FilmResult one = Renderer(test::device_context(), cornell(), s).render().film;
    Image d = two.mean;
    for (size_t i = 0; i < d.rgb.size(); ++i) d.rgb[i] -= one.mean.rgb[i];
    batches.push_back(d);
  }
  test::expect_matches_reference(batches, receiver_reference(), "pt one-bounce vs receiver");
}

// The Cornell box with a varnished floor: a diffuse base under a smooth (delta) coat, so x
// has a smooth lobe and a delta one. No generator may count a path through the coat's delta
// lobe (a light sample or a connection cannot pick its one direction; receiver gathering
// must drop its BSDF's delta samples): the image means of receiver and source gathering then
// agree, where a receiver that kept the coat's samples would add the lit walls' reflection
// in the floor.
TEST(IndirectGenerators, AgreeWithADeltaCoat) {
  Scene scene = test::cornell_box();
  Material varnish = scene.materials[0];
  varnish.name = "varnished";
  varnish.metallic = 0.0f;
  varnish.roughness = 0.0f;
  varnish.specular = 1.0f;
  const auto index = static_cast<uint32_t>(scene.materials.size());
  scene.materials.push_back(varnish);
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    const glm::uvec3 t = scene.triangles[i];
    if (std::max({scene.positions[t.x].y, scene.positions[t.y].y, scene.positions[t.z].y}) < 1e-4f)
      scene.triangle_materials[i] = index;  // the floor's triangles
  }
  // The floor's pixels (the bottom quarter of the image, where the floor is all the camera
  // sees beside the blocks' feet), whose light the coat's reflection would raise by several
  // per cent; batch means of the region's mean.
  auto floor_means = [](const std::vector<Image>& batches) {
    std::vector<double> m;
    for (const Image& img : batches) {
      double sum = 0.0;
      size_t n = 0;
      for (uint32_t y = img.height * 3 / 4; y < img.height; ++y)
        for (uint32_t x = 0; x < img.width; ++x, ++n)
          for (int c = 0; c < 3; ++c) sum += img.pixel(x, y)[c] / 3.0;
      m.push_back(sum / double(n));
    }
    double mean = 0.0, var = 0.0;
    for (double v : m) mean += v / double(m.size());
    for (double v : m) var += (v - mean) * (v - mean) / double(m.size() - 1);
    return std::pair{mean, std::sqrt(var / double(m.size()))};
  };
  const auto [r, r_sigma] = floor_means(
      test::render_batches(scene, indirect_settings(dev::INDIRECT_RECEIVER, 64, 24), 12, 7000));
  const auto [src, src_sigma] = floor_means(
      test::render_batches(scene, indirect_settings(dev::INDIRECT_SOURCE, 2048, 24), 16, 7100));
  const double z = (r - src) / std::sqrt(r_sigma * r_sigma + src_sigma * src_sigma);
  std::cout << "[ figures  ] indirect1 delta-coated floor, the floor's pixels: receiver " << r
            << " +- " << r_sigma << ", source " << src << " +- " << src_sigma << ", z " << z
            << "\n";
  EXPECT_LT(std::fabs(z), 4.0);
  EXPECT_LT(4.0 * src_sigma, 0.06 * src) << "too few samples to see the coat (+13 % on the floor)";
}

class IndirectGeneratorsAgree : public ::testing::TestWithParam<Generator> {};

TEST_P(IndirectGeneratorsAgree, MatchReceiverOnCornellBox) {
  const Generator g = GetParam();
  // Where x lies near another wall (the box's edges), G(x, y) = cos cos / d^2 makes these two
  // estimators heavy-tailed: a rare y next to x carries a large weight, and a pixel there
  // converges slowly (at 32768 spp a few edge pixels of source shooting still read |z| > 3
  // against receiver gathering, always low). So blocks are 8 x 8 pixels over 32 batches, and
  // 2 % of the pixel-channels may fail the per-pixel test (12 and 29 of 3072 do here, for
  // source and surface); a bias anywhere else still fails
  // the blocks and the image means.
  const std::vector<Image> batches =
      test::render_batches(cornell(), indirect_settings(g.id, 128, kSize), 32, 6000);
  test::expect_matches_reference(batches, receiver_reference(),
                                 std::string("indirect1 ") + g.name + " vs receiver", 8, 0.98);
}

INSTANTIATE_TEST_SUITE_P(Generators, IndirectGeneratorsAgree,
                         ::testing::Values(kGenerators[1], kGenerators[2]),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(IndirectArea, CdfFollowsTheAreas) {
  double total = 0.0;
  const std::vector<float> cdf = OneBounceIndirect::area_cdf({1.0f, 0.0f, 3.0f, 4.0f}, &total);
  EXPECT_DOUBLE_EQ(total, 8.0);
  ASSERT_EQ(cdf.size(), 5u);
  EXPECT_EQ(cdf[0], 0.0f);
  EXPECT_FLOAT_EQ(cdf[1], 0.125f);
  EXPECT_EQ(cdf[2], cdf[1]);  // the empty triangle has an interval of 0: never drawn
  EXPECT_FLOAT_EQ(cdf[3], 0.5f);
  EXPECT_EQ(cdf[4], 1.0f);
  // Areas that are not finite positive numbers (a degenerate or broken triangle) weigh 0.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> bad = OneBounceIndirect::area_cdf({2.0f, nan, -1.0f, inf, 2.0f}, &total);
  EXPECT_DOUBLE_EQ(total, 4.0);
  ASSERT_EQ(bad.size(), 6u);
  EXPECT_FLOAT_EQ(bad[1], 0.5f);
  EXPECT_EQ(bad[4], bad[1]);
  EXPECT_EQ(bad[5], 1.0f);
  EXPECT_TRUE(OneBounceIndirect::area_cdf({0.0f, 0.0f}, &total).empty());
  EXPECT_TRUE(OneBounceIndirect::area_cdf({}, &total).empty());
}

TEST(IndirectCli, UsageRules) {
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "indirect1"}), ExitCode::Ok);
  for (const char* g : {"receiver", "source", "surface"})
    EXPECT_EQ(parse_error({"s.gltf", "--integrator", "indirect1", "--indirect", g}), ExitCode::Ok)
        << g;
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "indirect1", "--indirect", "photon"}),
            ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--indirect", "source"}), ExitCode::Usage);  // pt
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--indirect", "source"}), ExitCode::Usage);
}

TEST(IndirectCli, StatsNameTheGeneratorAndImagesAgree) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("clpt_indirect_cli_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string scene = std::string(CLPT_SOURCE_DIR) + "/scenes/cornell_box.gltf";
  for (const Generator& g : kGenerators) {
    const nlohmann::json j = test::run_clpt_stats(
        dir, g.name, scene,
        {"--integrator", "indirect1", "--indirect", g.name, "--resolution", "16x16", "--spp", "8"});
    ASSERT_FALSE(j.is_null()) << g.name;
    EXPECT_EQ(j["integrator"].get<std::string>(), "indirect1");
    EXPECT_EQ(j["indirect"]["generator"].get<std::string>(), g.name);
    EXPECT_EQ(j["spp"].get<uint64_t>(), 8u);
    // Every generator traces the camera ray and at least one more ray for most samples.
    EXPECT_GT(j["rays"].get<uint64_t>(), 16u * 16u * 8u) << g.name;
    EXPECT_TRUE(j["efficiency"].is_number()) << g.name;  // per-pixel variance exists
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace clpt::indirect1_test
