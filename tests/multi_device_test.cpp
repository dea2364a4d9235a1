// Several devices in one process (--device A,B; issue 20). PoCL shows two devices with
// POCL_DEVICES="pthread pthread": they share one pool of worker threads, so they do not render
// side by side ("basic basic" would, docs/scaling.md), but what is checked here is what the
// devices render, not how fast; and pthread devices use the kernels the rest of the suite has
// built, where "basic" ones would build every integrator again (about a minute of a clean
// run). Every
// sample is a function of (seed, pixel, sample index), so two devices that split the sample
// indices between them render the image one device renders, up to the rounding of the film
// sums' order: that equality, for every integrator that splits, is what these tests check.
// They run clpt as a user does: the device list must be set before OpenCL is first touched.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "integrators/integrator.h"
#include "io/image_io.h"
#include "support/split_render.h"
#include "support/run.h"

namespace clpt::multi_device_test {
namespace {

namespace fs = std::filesystem;

const std::string kCornell = std::string(CLPT_SOURCE_DIR) + "/scenes/cornell_box.gltf";

class MultiDevice : public test::TestFolder {
 protected:
  void SetUp() override { make_folder("clpt-multi-device"); }

  // clpt with two PoCL devices visible; `args` after the scene.
  test::RunResult clpt(const std::vector<std::string>& args) const {
    std::vector<std::string> all = {kCornell, "-q"};
    all.insert(all.end(), args.begin(), args.end());
    test::RunOptions o;
    o.env = {{"POCL_DEVICES", "pthread pthread"}};
    return test::run_program(CLPT_BINARY, all, o);
  }
  // Renders `name`.exr (and its --stats) on `devices`; a failed run fails the test.
  nlohmann::json render(const std::string& name, const std::string& devices,
                        std::vector<std::string> args) const {
    args.insert(args.end(), {"--device", devices, "-o", path(name + ".exr"),
                             "--stats=" + path(name + ".json")});
    const test::RunResult r = clpt(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    if (r.exit_code != 0) return nullptr;
    return nlohmann::json::parse(test::read_file(path(name + ".json")));
  }
};

// Options some integrators need to render small and quick (pm's maps), or that show more of
// what splits (vcm's merged layer).
std::vector<std::string> extra_options(const std::string& integrator) {
  if (integrator == "pm") return {"--photons", "20000", "--caustic-photons", "5000", "--final-gather", "2"};
  // Per-pixel radii shrink with each device's own passes, so two devices render another
  // (equally consistent) image than one: the identity holds for the pass rule.
  if (integrator == "vcm") return {"--vcm-merged", "--vcm-shrink", "pass"};
  return {};
}

// Every row of the integrator table that says it splits (IntegratorInfo::multi_device), so an
// integrator added to the table is tested here without a word changed.
TEST_F(MultiDevice, TwoDevicesRenderWhatOneRenders) {
  size_t tested = 0;
  for (const IntegratorInfo& row : integrator_table()) {
    if (!row.implemented || row.split != DeviceSplit::Samples) continue;
    ++tested;
    // Float rounding of the sums' order: per-pixel sums differ in the last bits only; splats
    // add many contributions per pixel in another grouping, a little more.
    const double max_rel_mse = row.film == FilmKind::Splats ? 1e-8 : 1e-10;
    const std::vector<std::string> extra = extra_options(row.name);
    SCOPED_TRACE(row.name);
    std::vector<std::string> args = {"--integrator", row.name, "--resolution", "32x32",
                                     "--spp", "24", "--seed", "7", "--max-depth", "4"};
    args.insert(args.end(), extra.begin(), extra.end());
    const std::string name = row.name;
    const nlohmann::json one = render(name + "-one", "0:0", args);
    const nlohmann::json two = render(name + "-two", "0:0,0:1", args);
    if (one.is_null() || two.is_null()) continue;
    test::expect_device_shares(one, 1, 24);
    test::expect_device_shares(two, 2, 24);
    if (name == "vcm") {  // its figures add up over the devices
      EXPECT_EQ(two["vcm"]["passes"], 24);
      EXPECT_EQ(two["vcm"]["first_radius"], one["vcm"]["first_radius"]);
      EXPECT_EQ(two["vcm"]["last_radius"], one["vcm"]["last_radius"]);
      EXPECT_EQ(two["vcm"]["merges"], one["vcm"]["merges"]);
    }
    const Image a = read_image(path(name + "-two.exr"));
    const Image b = read_image(path(name + "-one.exr"));
    const test::Agreement g = test::agreement(a, b);
    EXPECT_LT(g.rel_mse, max_rel_mse);
    EXPECT_NEAR(g.mean_ratio, 1.0, 1e-6);
    std::printf("%-9s two devices against one: relMSE %.3g, mean ratio 1 %+.3g\n", row.name,
                g.rel_mse, g.mean_ratio - 1.0);
    // Extra layers (vcm's merged part) add up over the devices too.
    const ImageChannels la = read_image_channels(path(name + "-two.exr"));
    for (const NamedChannel& l : read_image_channels(path(name + "-one.exr")).layers) {
      SCOPED_TRACE(l.name);
      const Image* other = la.layer(l.name);
      ASSERT_NE(other, nullptr);
      EXPECT_LT(test::agreement(*other, l.image).rel_mse, max_rel_mse);
    }
    // The comparison can fail: the same render with another seed is far off.
    if (name == "pt") {
      std::vector<std::string> other = args;
      other[std::find(other.begin(), other.end(), "--seed") - other.begin() + 1] = "8";
      render("pt-seed", "0:0", other);
      EXPECT_GT(test::agreement(a, read_image(path("pt-seed.exr"))).rel_mse, 1e-4);
    }
  }
  EXPECT_GE(tested, 9u) << "pt, direct, ao, indirect1, lt, bdpt, pm, vcm and ic split";
}

// mlt splits by chains (DeviceSplit::Chains): each device runs chains of its own from the same
// bootstrap, so two devices' image is another estimate of one device's, not the same sums. The
// chains add up (twice one device's, with the mutations of the render between them), the
// bootstrap is one device's, the image agrees with one device's within the estimators' noise,
// and the devices do not repeat each other: two devices running the same chains (the same
// random numbers, each half the mutations) would render exactly one device's image at half
// the samples per pixel.
TEST_F(MultiDevice, MetropolisDevicesRunChainsOfTheirOwn) {
  // The chains carry the whole image (--mlt-direct 0): the direct light apart is pt's, whose
  // image mean at these few samples is noisier than the chains' (next test).
  auto args = [](const char* spp) {
    return std::vector<std::string>{"--integrator", "mlt", "--resolution", "32x32", "--spp", spp,
                                    "--seed", "7", "--max-depth", "4", "--mlt-direct", "0"};
  };
  const nlohmann::json one = render("mlt-one", "0:0", args("48"));
  const nlohmann::json two = render("mlt-two", "0:0,0:1", args("48"));
  render("mlt-half", "0:0", args("24"));
  if (one.is_null() || two.is_null()) return;
  test::expect_device_shares(two, 2, 48);
  const nlohmann::json& m1 = one["mlt"];
  const nlohmann::json& m2 = two["mlt"];
  EXPECT_EQ(m2["chains"].get<uint64_t>(), 2 * m1["chains"].get<uint64_t>());
  EXPECT_EQ(m2["mutations"], m1["mutations"]);  // --spp 48 x 32 x 32, over both devices
  // The bootstrap's b is alike (b itself adds each device's own large steps).
  EXPECT_EQ(m2["b_bootstrap"], m1["b_bootstrap"]);
  EXPECT_EQ(m2["bootstrap_paths"], m1["bootstrap_paths"]);
  for (size_t d = 0; d < m1["chains_by_depth"].size(); ++d)
    EXPECT_EQ(m2["chains_by_depth"][d].get<uint64_t>(), 2 * m1["chains_by_depth"][d].get<uint64_t>());

  const Image a = read_image(path("mlt-two.exr"));
  const Image b = read_image(path("mlt-one.exr"));
  // The image's mean is pinned near b by the estimator (the splats of every chain add up to
  // b per mutation, less the tile target's weights), and so are its quadrants' to within
  // their noise: measured 0.5 % (image) and 0.4 % to 5 % (quadrants) apart at this size. A
  // device whose splats were scaled for another device's share of the mutations would be 50 %
  // or 100 % off.
  const test::Agreement g = test::agreement(a, b);
  EXPECT_NEAR(g.mean_ratio, 1.0, 0.03);
  for (uint32_t q = 0; q < 4; ++q) {
    double sa = 0.0, sb = 0.0;
    for (uint32_t y = (q / 2) * 16; y < (q / 2) * 16 + 16; ++y)
      for (uint32_t x = (q % 2) * 16; x < (q % 2) * 16 + 16; ++x)
        for (int c = 0; c < 3; ++c) {
          sa += a.rgb[3 * (size_t(y) * 32 + x) + c];
          sb += b.rgb[3 * (size_t(y) * 32 + x) + c];
        }
    std::printf("mlt quadrant %u: two devices / one = %.4f\n", q, sa / sb);
    EXPECT_NEAR(sa / sb, 1.0, 0.15) << "quadrant " << q;
  }
  const test::Agreement same = test::agreement(a, read_image(path("mlt-half.exr")));
  std::printf("mlt two devices against one: mean ratio %.4f, relMSE %.3g; against one device's "
              "chains at half the samples: relMSE %.3g\n",
              g.mean_ratio, g.rel_mse, same.rel_mse);
  EXPECT_GT(same.rel_mse, 1e-3) << "the two devices ran the same chains";
}

// mmlt's direct light apart (--mlt-direct): each device takes direct samples of its own, for
// its own share of the mutations. At --max-depth 1 with R = 1 the chains have no length left
// and one device renders exactly what `direct` renders; two devices, each half the samples,
// must not render `direct`'s image at half the samples (the second device repeating the
// first's samples), and their image agrees with a long `direct` render.
TEST_F(MultiDevice, MetropolisDirectLightSamplesAreEachDevicesOwn) {
  auto args = [](const char* integrator, const char* spp, const char* seed) {
    std::vector<std::string> a = {"--integrator", integrator, "--resolution", "32x32", "--spp",
                                  spp, "--seed", seed, "--max-depth", "1"};
    if (std::string(integrator) == "mlt") a.insert(a.end(), {"--mlt-direct", "1"});
    return a;
  };
  const nlohmann::json two = render("mlt-direct-two", "0:0,0:1", args("mlt", "256", "7"));
  render("direct-half", "0:0", args("direct", "128", "7"));
  render("direct-ref", "0:0", args("direct", "4096", "99"));
  if (two.is_null()) return;
  test::expect_device_shares(two, 2, 256);
  EXPECT_EQ(two["mlt"]["direct_samples"].get<uint64_t>(), 256u);  // R = 1: one per mutation
  const Image a = read_image(path("mlt-direct-two.exr"));
  const test::Agreement half = test::agreement(a, read_image(path("direct-half.exr")));
  const test::Agreement ref = test::agreement(a, read_image(path("direct-ref.exr")));
  std::printf("mlt's direct light on two devices: against direct at half the samples relMSE "
              "%.3g; against a 4096-spp direct render mean ratio %.4f, relMSE %.3g\n",
              half.rel_mse, ref.mean_ratio, ref.rel_mse);
  EXPECT_GT(half.rel_mse, 1e-4) << "the second device repeated the first's direct samples";
  // The image mean of 256 direct samples per pixel scatters by about 1 % (seeds 7 to 10 of
  // one device: 0.9770 to 1.0065 of the 4096-spp mean).
  EXPECT_NEAR(ref.mean_ratio, 1.0, 0.04);
}

// A checkpoint of a two-device render holds the first N sample indices exactly: resumed on one
// device to 2N, it equals one device's 2N; the AOVs of two devices equal one device's.
TEST_F(MultiDevice, CheckpointsAndAovsAreOneDevicesToo) {
  const std::vector<std::string> base = {"--resolution", "24x24", "--seed", "3", "--max-depth", "3"};
  auto with = [&](std::vector<std::string> more) {
    std::vector<std::string> a = base;
    a.insert(a.end(), more.begin(), more.end());
    return a;
  };
  render("half", "0:0,0:1", with({"--spp", "8", "--checkpoint", path("half.ckpt")}));
  render("resumed", "0:0", with({"--spp", "16", "--resume", path("half.ckpt")}));
  render("whole", "0:0", with({"--spp", "16"}));
  const test::Agreement g = test::agreement(read_image(path("resumed.exr")), read_image(path("whole.exr")));
  EXPECT_LT(g.rel_mse, 1e-10);
  EXPECT_NEAR(g.mean_ratio, 1.0, 1e-6);

  const std::vector<std::string> aov = with({"--spp", "12", "--aov", "albedo,normal,depth,material-id"});
  const nlohmann::json two = render("aov-two", "0:0,0:1", aov);
  render("aov-one", "0:0", aov);
  if (two.is_null()) return;
  test::expect_device_shares(two, 2, 12);
  const ImageChannels a = read_image_channels(path("aov-two.exr"));
  const ImageChannels b = read_image_channels(path("aov-one.exr"));
  for (const char* layer : {"Albedo", "Normal", "Depth", "IndexMA"}) {
    SCOPED_TRACE(layer);
    const Image* la = a.layer(layer);
    const Image* lb = b.layer(layer);
    ASSERT_TRUE(la && lb);
    double worst = 0.0;
    for (size_t i = 0; i < la->rgb.size(); ++i) {
      if (std::isinf(lb->rgb[i])) {
        EXPECT_TRUE(std::isinf(la->rgb[i]));
        continue;
      }
      worst = std::max(worst, std::abs(double(la->rgb[i]) - lb->rgb[i]) / (std::abs(lb->rgb[i]) + 1e-3));
    }
    EXPECT_LT(worst, 1e-5);
  }
}

// vcm's per-pixel radii (its default with the box filter) follow from every pass before, as
// sppm's: on two devices vcm takes the pass rule (with that rule's alpha) and renders what
// `--vcm-shrink pass` renders on one; naming the per-pixel rule there is a usage error.
TEST_F(MultiDevice, VcmTakesThePassRuleWhenSplit) {
  const std::vector<std::string> args = {"--integrator", "vcm", "--resolution", "24x24",
                                         "--spp", "8", "--seed", "5", "--max-depth", "3"};
  auto with = [&](std::vector<std::string> more) {
    std::vector<std::string> a = args;
    a.insert(a.end(), more.begin(), more.end());
    return a;
  };
  const nlohmann::json two = render("vcm-two", "0:0,0:1", args);
  const nlohmann::json one = render("vcm-one", "0:0", with({"--vcm-shrink", "pass"}));
  const nlohmann::json own = render("vcm-own", "0:0", args);
  if (two.is_null() || one.is_null() || own.is_null()) return;
  EXPECT_EQ(two["vcm"]["shrink"], "pass");
  EXPECT_FLOAT_EQ(two["vcm"]["alpha"].get<float>(), 0.75f);
  EXPECT_EQ(two["vcm"]["first_radius"], one["vcm"]["first_radius"]);
  EXPECT_EQ(own["vcm"]["shrink"], "pixel");
  const test::Agreement g = test::agreement(read_image(path("vcm-two.exr")), read_image(path("vcm-one.exr")));
  EXPECT_LT(g.rel_mse, 1e-8);
  const test::RunResult named = clpt(with({"--device", "0:0,0:1", "--vcm-shrink", "pixel", "-o",
                                           path("named.exr")}));
  EXPECT_EQ(named.exit_code, int(ExitCode::Usage));
  EXPECT_NE(named.err.find("--vcm-shrink pixel renders on one device"), std::string::npos) << named.err;
  EXPECT_FALSE(fs::exists(path("named.exr")));
}

// pm's final-gather cache (an irradiance cache over the global map) is built alike on every
// device from the seed, as the maps are: two devices render one device's image.
TEST_F(MultiDevice, FinalGatherCacheIsBuiltAlikeOnEveryDevice) {
  const std::vector<std::string> args = {
      "--integrator", "pm", "--resolution", "24x24", "--spp", "8", "--seed", "4", "--max-depth", "4",
      "--photons", "20000", "--caustic-photons", "5000", "--final-gather", "2", "--final-gather-cache"};
  const nlohmann::json one = render("fgc-one", "0:0", args);
  const nlohmann::json two = render("fgc-two", "0:0,0:1", args);
  if (one.is_null() || two.is_null()) return;
  test::expect_device_shares(two, 2, 8);
  const test::Agreement g =
      test::agreement(read_image(path("fgc-two.exr")), read_image(path("fgc-one.exr")));
  EXPECT_LT(g.rel_mse, 1e-10);
  EXPECT_NEAR(g.mean_ratio, 1.0, 1e-6);
}

TEST_F(MultiDevice, AllNamesEveryDeviceAndAListIsChecked) {
  const nlohmann::json all = render("all", "all", {"--resolution", "16x16", "--spp", "4"});
  if (!all.is_null()) test::expect_device_shares(all, 2, 4);

  struct Refusal {
    std::vector<std::string> args;
    const char* says;
  };
  const std::vector<Refusal> refusals = {
      {{"--device", "0:0,0:0"}, "named twice"},
      {{"--device", "0:0,"}, "empty entry"},
      {{"--device", "0:0,0:7"}, "no such platform:device"},
      {{"--device", "0:0,0:1", "--integrator", "bdpt", "--bdpt-mosaic"}, "one device"},
  };
  // Every row of the table that does not split (sppm) is refused.
  std::vector<Refusal> checked = refusals;
  for (const IntegratorInfo& row : integrator_table())
    if (row.implemented && row.split == DeviceSplit::OneDevice)
      checked.push_back({{"--device", "0:0,0:1", "--integrator", row.name}, "renders on one device"});
  EXPECT_GE(checked.size(), refusals.size() + 1);
  for (const Refusal& r : checked) {
    std::vector<std::string> args = {"--resolution", "8x8", "--spp", "1", "-o", path("refused.exr")};
    args.insert(args.end(), r.args.begin(), r.args.end());
    const test::RunResult run = clpt(args);
    SCOPED_TRACE(run.err);
    EXPECT_NE(run.exit_code, 0);
    EXPECT_NE(run.err.find(r.says), std::string::npos);
    EXPECT_FALSE(fs::exists(path("refused.exr")));
  }
}

}  // namespace
}  // namespace clpt::multi_device_test
