// The irradiance cache whose records gather from a global photon map (Jensen 2001, ch. 9):
// ic --ic-photons, and pm --final-gather-cache (pm's final gather's diffuse part read from
// such a cache, caustics from pm's caustic map), on the PoCL device:
//   IcPhotons        in the furnace, both near the closed form (a density estimate of a
//                    uniform photon field is unbiased but for the kernel's edge: 1 %); on the
//                    Cornell box and the glossy-and-glass box (records behind glass, light
//                    through glass, the metal's path-traced rest) near their pt references:
//                    image mean within 2 %, every 8 x 8 block within 10 %, as ic's own test;
//   IcPhotonOptions  usage errors of the two options and of what they combine with;
//   IcPhotonCli      --stats: the records gather from photons, the lookups hit, and the
//                    cached final gather traces fewer rays than pm's own.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/renderer.h"
#include "stats/image_stats.h"
#include "support/parse_options.h"
#include "support/reference_match.h"
#include "support/reference_render.h"
#include "support/render.h"
#include "support/run.h"
#include "support/scenes.h"

namespace clpt::ic_photons_test {
namespace {

// ic with photon-gathering records, or pm with its final gather cached.
enum class Variant { IcPhotons, PmCache };

const char* variant_name(Variant v) { return v == Variant::IcPhotons ? "ic --ic-photons" : "pm --final-gather-cache"; }

RenderSettings settings_for(Variant v, uint64_t spp, uint32_t size) {
  RenderSettings s = test::render_settings(v == Variant::IcPhotons ? "ic" : "pm", spp, size);
  if (v == Variant::IcPhotons)
    s.ic.photons = 200000;
  else
    s.pm.final_gather_cache = true;
  return s;
}

// The largest |block mean / reference's - 1| over block x block pixels (all channels).
double worst_block(const Image& img, const Image& ref, uint32_t size, uint32_t block) {
  double worst = 0.0;
  for (uint32_t by = 0; by < size; by += block)
    for (uint32_t bx = 0; bx < size; bx += block) {
      double a = 0.0, b = 0.0;
      for (uint32_t y = by; y < by + block; ++y)
        for (uint32_t x = bx; x < bx + block; ++x)
          for (int c = 0; c < 3; ++c) {
            a += img.rgb[(size_t(y) * size + x) * 3 + c];
            b += ref.rgb[(size_t(y) * size + x) * 3 + c];
          }
      if (b > 0.0) worst = std::max(worst, std::fabs(a / b - 1.0));
    }
  return worst;
}

class IcPhotons : public ::testing::TestWithParam<Variant> {};

// The furnace (rho 0.5, depth 3): every surface point receives the same irradiance, so the
// photons lie uniformly and each record's estimate is the closed form's indirect part up to
// the photon noise, which batches of independent maps and caches average.
TEST_P(IcPhotons, FurnaceNearClosedForm) {
  const Variant v = GetParam();
  const Scene scene = test::furnace_scene(0.5f, 1.0f);
  const double expected = test::furnace_radiance(0.5f, 1.0, 3);
  RenderSettings s = settings_for(v, 2, 16);
  s.max_depth = 3;
  s.ic.rays = 64;
  s.pm.photons = 20000;
  s.ic.photons = v == Variant::IcPhotons ? 20000 : 0;
  s.pm.caustic_photons = 0;
  const BatchMean bm = batch_mean(test::render_batches(scene, s, 12, 5300));
  std::cout << "[ figures  ] " << variant_name(v) << " furnace rho 0.5 depth 3: mean " << bm.mean
            << " expected " << expected << " sigma " << bm.sigma << "\n";
  EXPECT_NEAR(bm.mean / expected, 1.0, 0.01);
}

TEST_P(IcPhotons, CornellBoxNearPt) {
  const Variant v = GetParam();
  const Scene scene = test::cornell_box();
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBox, 32, 8192, 4242);
  const FilmResult img = test::render(scene, settings_for(v, 256, 32), 31);
  const double ratio = image_mean(img.mean) / image_mean(ref.mean);
  const double worst = worst_block(img.mean, ref.mean, 32, 8);
  std::cout << "[ figures  ] " << variant_name(v) << " cornell 32x32: mean / reference " << ratio
            << ", relMSE " << compare_images(img.mean, ref.mean).rel_mse
            << ", worst 8x8 block off by " << worst << "\n";
  EXPECT_NEAR(ratio, 1.0, 0.02);
  EXPECT_LT(worst, 0.10);
}

// Records behind the smooth glass (depth > 0), light reaching walls through the glass
// (ic: emission beyond the records' first hits; pm: its caustic map), the metal's BSDF
// gathered in full (kd = 0).
TEST_P(IcPhotons, GlossyAndGlassBoxNearPt) {
  const Variant v = GetParam();
  const Scene scene = test::cornell_box_glossy_glass();
  const FilmResult ref =
      test::pt_reference(test::ReferenceScene::CornellBoxGlossyGlass, 32, 16384, 4343);
  RenderSettings s = settings_for(v, 256, 32);
  s.ic.rays = 1024;
  const FilmResult img = test::render(scene, s, 33);
  const double ratio = image_mean(img.mean) / image_mean(ref.mean);
  const double worst = worst_block(img.mean, ref.mean, 32, 8);
  std::cout << "[ figures  ] " << variant_name(v) << " glossy+glass 32x32: mean / reference "
            << ratio << ", relMSE " << compare_images(img.mean, ref.mean).rel_mse
            << ", worst 8x8 block off by " << worst << "\n";
  EXPECT_NEAR(ratio, 1.0, 0.02);
  EXPECT_LT(worst, 0.10);
}

INSTANTIATE_TEST_SUITE_P(Variants, IcPhotons,
                         ::testing::Values(Variant::IcPhotons, Variant::PmCache),
                         [](const auto& info) {
                           return std::string(info.param == Variant::IcPhotons ? "IcPhotons"
                                                                               : "PmCache");
                         });

using test::parse_error;

TEST(IcPhotonOptions, BadCombinationsAreUsageErrors) {
  // --ic-photons is ic's; pm's cache reads pm's own map.
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "pm", "--final-gather-cache", "--ic-photons", "10"}),
            ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "pt", "--ic-photons", "10"}), ExitCode::Usage);
  // --final-gather-cache is pm's, and needs a final gather to cache.
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--final-gather-cache"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "pm", "--final-gather-cache", "--final-gather", "0"}),
            ExitCode::Usage);
  // The --ic-* options need a cache; the photon estimate's options photon records.
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "pm", "--ic-error", "0.1"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--knn", "20"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "pm", "--final-gather-cache", "--ic-error", "0"}),
            ExitCode::Usage);
  // What does parse.
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "ic", "--ic-photons", "1000", "--knn", "20",
                         "--pm-filter", "box"}),
            ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "pm", "--final-gather-cache", "--ic-error",
                         "0.1", "--ic-rays", "64", "--final-gather", "4"}),
            ExitCode::Ok);
}

TEST(IcPhotonCli, StatsShowTheCacheAtWork) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("clpt_icph_cli_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string scene = std::string(CLPT_SOURCE_DIR) + "/scenes/cornell_box.gltf";
  auto run = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args = {"--resolution", "32x32", "--spp", "4", "--photons", "20000",
                                     "--caustic-photons", "20000"};
    if (extra[0] == "ic") args = {"--resolution", "32x32", "--spp", "4"};
    args.insert(args.end(), {"--integrator", extra[0]});
    args.insert(args.end(), extra.begin() + 1, extra.end());
    return test::run_clpt_stats(dir, name, scene, args);
  };
  const nlohmann::json pm = run("pm", {"pm"});
  const nlohmann::json cached = run("cached", {"pm", "--final-gather-cache"});
  const nlohmann::json ic = run("ic", {"ic", "--ic-photons", "20000"});
  ASSERT_FALSE(pm.is_null() || cached.is_null() || ic.is_null());
  EXPECT_FALSE(pm.contains("ic")) << "pm without a cache reports none";
  for (const nlohmann::json* j : {&cached, &ic}) {
    const nlohmann::json& c = (*j)["ic"];
    EXPECT_EQ(c["gather"], "photons");
    EXPECT_GT(c["records"].get<uint64_t>(), 10u);
    EXPECT_GT(c["lookups"].get<uint64_t>(), 32u * 32u);
    EXPECT_LT(c["lookup_misses"].get<uint64_t>(), c["lookups"].get<uint64_t>() / 10);
  }
  EXPECT_EQ(ic["photons"]["paths"].get<uint64_t>(), 20000u);
  EXPECT_GT(ic["photons"]["stored"].get<uint64_t>(), 20000u);
  // On the Lambertian box the cache holds the whole diffuse part: the cached gather traces
  // no gather rays where a record covers the point (the records' rays are the photon pass's
  // and the build's, not the image's).
  const double pm_rays = pm["rays"].get<double>(), cached_rays = cached["rays"].get<double>();
  std::cout << "[ figures  ] pm rays " << pm_rays << ", pm --final-gather-cache rays "
            << cached_rays << "\n";
  EXPECT_LT(cached_rays, 0.5 * pm_rays);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace clpt::ic_photons_test
