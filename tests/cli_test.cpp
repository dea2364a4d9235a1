// The clpt program as users run it: exit codes, messages, output files, --help vs README.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <utility>
#include <vector>

#include "io/image_io.h"
#include "io/view_transform.h"
#include "stats/image_stats.h"
#include "support/parse_options.h"
#include "support/run.h"

namespace clpt::cli_test {
namespace {
namespace fs = std::filesystem;
using test::run_clpt;

const std::string kCornell = std::string(CLPT_SOURCE_DIR) + "/scenes/cornell_box.gltf";

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("clpt-cli-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(Cli, HelpMatchesReadme) {
  const test::RunResult r = run_clpt({"--help"});
  ASSERT_EQ(r.exit_code, 0);
  const std::string readme = test::read_file(std::string(CLPT_SOURCE_DIR) + "/README.md");
  const std::string begin = "<!-- clpt --help begins -->\n```\n", end = "```\n<!-- clpt --help ends -->";
  const size_t b = readme.find(begin), e = readme.find(end);
  ASSERT_NE(b, std::string::npos) << "README.md lacks the --help block markers";
  ASSERT_NE(e, std::string::npos);
  EXPECT_EQ(readme.substr(b + begin.size(), e - b - begin.size()), r.out)
      << "README.md's --help block differs from `clpt --help`; paste the new text in";
}

TEST_F(Cli, NoSceneIsAUsageError) {
  const test::RunResult r = run_clpt({});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no scene"), std::string::npos) << r.err;
}

TEST_F(Cli, UnknownOptionIsAUsageError) {
  const test::RunResult r = run_clpt({kCornell, "--no-such-option"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no-such-option"), std::string::npos) << r.err;
}

// --view and --exposure shape PNG and JPEG only (issue 24): every PNG byte is the view
// transform of the linear EXR pixel the same render writes (same seed, same samples), the EXR's
// pixels do not change with them, and both files record them in their metadata.
TEST_F(Cli, ViewTransformsShapePngOnly) {
  const std::vector<std::string> base = {kCornell, "--device", "pocl", "--resolution", "24x24",
                                         "--spp", "4", "--quiet", "--exposure", "3"};
  auto render = [&](const std::string& out, const std::string& view) {
    std::vector<std::string> args = base;
    args.insert(args.end(), {"--view", view, "-o", path(out)});
    const test::RunResult r = run_clpt(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
  };
  render("plain.exr", "standard");
  render("agx.exr", "agx");
  const Image linear = read_image(path("plain.exr"));
  EXPECT_EQ(read_image(path("agx.exr")).rgb, linear.rgb) << "an EXR stays linear scene radiance";
  auto in = OIIO::ImageInput::open(path("agx.exr"));
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().get_string_attribute("clpt:view"), "agx");
  EXPECT_FLOAT_EQ(in->spec().get_float_attribute("clpt:exposure"), 3.0f);
  in.reset();

  size_t saturated_standard = 0, saturated_neutral = 0;
  for (const std::string view : {"standard", "khronos-neutral", "agx", "aces"}) {
    SCOPED_TRACE(view);
    render(view + ".png", view);
    auto png = OIIO::ImageInput::open(path(view + ".png"));
    ASSERT_TRUE(png);
    EXPECT_EQ(png->spec().get_string_attribute("clpt:view"), view);
    std::vector<unsigned char> bytes(24 * 24 * 3);
    ASSERT_TRUE(png->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, bytes.data()));
    const DisplaySettings display{*parse_view_transform(view), 3.0f};
    size_t differ = 0, saturated = 0;
    for (size_t i = 0; i < 24 * 24; ++i) {
      const auto d = display_encode(display, {linear.rgb[3 * i], linear.rgb[3 * i + 1], linear.rgb[3 * i + 2]});
      for (int c = 0; c < 3; ++c) {
        differ += bytes[3 * i + size_t(c)] != (unsigned char)std::lround(d[size_t(c)] * 255.0f);
        saturated += bytes[3 * i + size_t(c)] == 255;
      }
    }
    EXPECT_EQ(differ, 0u);
    if (view == "standard") saturated_standard = saturated;
    if (view == "khronos-neutral") saturated_neutral = saturated;
  }
  // 3 EV over the Cornell box burns much of a standard PNG out; the neutral view keeps it.
  EXPECT_GT(saturated_standard, 200u);
  EXPECT_LT(saturated_neutral * 4, saturated_standard);

  const test::RunResult bad = run_clpt({kCornell, "--view", "filmic", "-o", path("x.png")});
  EXPECT_EQ(bad.exit_code, 1) << bad.err;
  EXPECT_NE(bad.err.find("--view"), std::string::npos) << bad.err;
}

// --save-every (issue 24): the output is rewritten while rendering, each time with more
// samples, through the same atomic write as the final one (no temporary file left behind).
TEST_F(Cli, SaveEveryRewritesTheOutputWhileRendering) {
  const test::RunResult r =
      run_clpt({kCornell, "--device", "pocl", "--resolution", "16x16", "--time", "1.5", "--save-every", "0.2",
                "--verbose", "--view", "agx", "-o", path("progress.exr")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::vector<long> saved;
  for (size_t at = r.err.find("saved "); at != std::string::npos; at = r.err.find("saved ", at + 1))
    saved.push_back(std::stol(r.err.substr(at + 6)));
  ASSERT_GE(saved.size(), 2u) << r.err;
  for (size_t i = 1; i < saved.size(); ++i) EXPECT_GT(saved[i], saved[i - 1]) << r.err;
  auto in = OIIO::ImageInput::open(path("progress.exr"));
  ASSERT_TRUE(in);
  EXPECT_GT(in->spec().get_int_attribute("clpt:spp"), saved.back()) << "the final write has every sample";
  EXPECT_EQ(in->spec().get_string_attribute("clpt:view"), "agx");
  in.reset();
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir_)) files += e.is_regular_file();
  EXPECT_EQ(files, 1u) << "a temporary file was left behind";

  const test::RunResult mosaic = run_clpt({kCornell, "--integrator", "bdpt", "--bdpt-mosaic", "--save-every", "1",
                                           "-o", path("m.exr")});
  EXPECT_EQ(mosaic.exit_code, 1) << mosaic.err;
  EXPECT_NE(mosaic.err.find("--save-every"), std::string::npos) << mosaic.err;
}

TEST_F(Cli, BadValuesAreUsageErrors) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{kCornell, "--resolution", "0x10"},
        std::vector<std::string>{kCornell, "--resolution", "abc"},
        std::vector<std::string>{kCornell, "--spp", "-3"},
        std::vector<std::string>{kCornell, "--time", "0"},
        std::vector<std::string>{kCornell, "--integrator", "nope"},
        std::vector<std::string>{kCornell, "-o", path("x.bmpx")}}) {
    const test::RunResult r = run_clpt(args);
    EXPECT_EQ(r.exit_code, 1) << args[1] << " " << args[2] << ": " << r.err;
    EXPECT_FALSE(r.err.empty());
  }
}

TEST_F(Cli, BadBdptStrategiesAreUsageErrors) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{kCornell, "--integrator", "bdpt", "--bdpt-strategy", "1,1"},
        std::vector<std::string>{kCornell, "--integrator", "bdpt", "--bdpt-strategy", "2,0"},
        std::vector<std::string>{kCornell, "--integrator", "bdpt", "--bdpt-strategy", "x,2"},
        std::vector<std::string>{kCornell, "--integrator", "bdpt", "--bdpt-strategy", "6,6"},
        std::vector<std::string>{kCornell, "--integrator", "pt", "--bdpt-strategy", "2,2"},
        std::vector<std::string>{kCornell, "--integrator", "bdpt", "--bdpt-unweighted"},
        std::vector<std::string>{kCornell, "--integrator", "bdpt", "--bdpt-mosaic",
                                 "--bdpt-strategy", "2,2"},
        std::vector<std::string>{kCornell, "--integrator", "bdpt", "--variance"}}) {
    const test::RunResult r = run_clpt(args);
    EXPECT_EQ(r.exit_code, 1) << args.back() << ": " << r.err;
    EXPECT_NE(r.err.find("bdpt"), std::string::npos) << r.err;
  }
}

TEST_F(Cli, BdptWritesStatsAndAStrategyMosaic) {
  test::RunResult r = run_clpt({kCornell, "--device", "pocl", "--integrator", "bdpt",
                                "--resolution", "16x16", "--spp", "2", "-o", path("b.exr"),
                                "--stats", path("b.json"), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(test::read_file(path("b.json")));
  EXPECT_GT(j["connections"].get<double>(), 16.0 * 16 * 2);
  EXPECT_GT(j["camera_paths_per_second"].get<double>(), 0.0);
  EXPECT_TRUE(j["mean_variance"].is_null());

  r = run_clpt({kCornell, "--device", "pocl", "--integrator", "bdpt", "--bdpt-mosaic",
                "--resolution", "24x24", "--spp", "2", "-o", path("m.exr"), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Image m = read_image(path("m.exr"));
  ASSERT_EQ(m.width, 24u * 6);
  ASSERT_EQ(m.height, 24u * 5);
  // Row 0 (no bounce): only s = 0, the light seen directly; s = 1, t = 1 is not a strategy.
  auto cell_sum = [&](uint32_t row, uint32_t column) {
    double sum = 0.0;
    for (uint32_t y = 0; y < 24; ++y)
      for (uint32_t x = 0; x < 24; ++x) sum += m.pixel(column * 24 + x, row * 24 + y)[1];
    return sum;
  };
  EXPECT_GT(cell_sum(0, 0), 0.0);
  EXPECT_EQ(cell_sum(0, 1), 0.0);
  EXPECT_GT(cell_sum(1, 1), 0.0);  // next-event estimation of one-bounce paths
  EXPECT_EQ(cell_sum(1, 3), 0.0);  // no such strategy
  EXPECT_GT(cell_sum(4, 5), 0.0);  // light tracing of four-bounce paths
}

// mlt renders, reports its chains, and refuses what a splatted film cannot give.
TEST_F(Cli, MltWritesStatsAndRefusesVarianceAndCheckpoints) {
  test::RunResult r = run_clpt({kCornell, "--device", "pocl", "--integrator", "mlt",
                                "--resolution", "16x16", "--spp", "4", "--mlt-chains", "64",
                                "--mlt-bootstrap", "5000", "-o", path("m.exr"), "--stats",
                                path("m.json"), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(test::read_file(path("m.json")));
  const nlohmann::json& m = j["mlt"];
  EXPECT_EQ(m["mode"].get<std::string>(), "mmlt");  // the default
  EXPECT_EQ(m["chains"].get<uint32_t>(), 64u);
  // --max-depth 8: camera and light streams of 4 + 8 * 9 dimensions each; 5000 paths for
  // each of the 9 path lengths, and the chains shared out over them.
  EXPECT_EQ(m["dimensions"].get<uint32_t>(), 2u * (4u + 8u * 9u));
  EXPECT_EQ(m["bootstrap_paths"].get<uint64_t>(), 9u * 5000u);
  ASSERT_EQ(m["b_by_depth"].size(), 9u);
  ASSERT_EQ(m["chains_by_depth"].size(), 9u);
  double b_sum = 0.0;
  uint32_t chain_sum = 0;
  for (size_t d = 0; d < 9; ++d) {
    b_sum += m["b_by_depth"][d].get<double>();
    chain_sum += m["chains_by_depth"][d].get<uint32_t>();
  }
  EXPECT_NEAR(b_sum, m["b"].get<double>(), 1e-9 * b_sum);
  EXPECT_EQ(chain_sum, 64u);
  // The direct light (bounces 0 and 1) rendered apart (--mlt-direct auto): no chains there,
  // and at least one direct sample per pixel a pass, at most one per mutation per pixel.
  EXPECT_EQ(m["chains_by_depth"][0].get<uint32_t>(), 0u);
  EXPECT_EQ(m["chains_by_depth"][1].get<uint32_t>(), 0u);
  EXPECT_GT(m["chains_by_depth"][2].get<uint32_t>(), m["chains_by_depth"][8].get<uint32_t>());
  EXPECT_GT(m["direct_ratio"].get<double>(), 0.0);
  EXPECT_LT(m["direct_ratio"].get<double>(), 1.0);
  EXPECT_GE(m["direct_samples"].get<uint64_t>(), 1u);
  EXPECT_LE(m["direct_samples"].get<uint64_t>(), 4u);
  // 4 mutations per pixel of 256 pixels: 16 per chain, whatever the passes (each pass
  // rounds its mutations per chain up, and 64 chains divide 256 pixels).
  EXPECT_EQ(m["mutations"].get<uint64_t>(), 1024u);
  EXPECT_GT(m["b"].get<double>(), 0.0);
  EXPECT_GT(m["b_standard_error"].get<double>(), 0.0);
  // b adds the large steps' targets to the bootstrap's (1 024 mutations, about 0.3 of them
  // large steps); no length's pool grows to 4 x its 2 500 bootstrap paths here.
  EXPECT_GT(m["b_bootstrap"].get<double>(), 0.0);
  EXPECT_GT(m["b_large_steps"].get<uint64_t>(), 200u);
  EXPECT_LT(m["b_large_steps"].get<uint64_t>(), 1024u);
  EXPECT_EQ(m["restarts"].get<uint32_t>(), 0u);
  for (const char* key : {"acceptance", "large_step_acceptance", "small_step_acceptance"}) {
    EXPECT_GT(m[key].get<double>(), 0.0) << key;
    EXPECT_LT(m[key].get<double>(), 1.0) << key;
  }
  EXPECT_TRUE(j["mean_variance"].is_null());
  EXPECT_GT(image_mean(read_image(path("m.exr"))), 0.01);
  // pssmlt: one stream, one bootstrap for all lengths.
  r = run_clpt({kCornell, "--device", "pocl", "--integrator", "mlt", "--mlt-mode", "pssmlt",
                "--resolution", "16x16", "--spp", "4", "--mlt-chains", "64", "--mlt-bootstrap",
                "5000", "-o", path("p.exr"), "--stats", path("p.json"), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json p = nlohmann::json::parse(test::read_file(path("p.json")))["mlt"];
  EXPECT_EQ(p["mode"].get<std::string>(), "pssmlt");
  EXPECT_EQ(p["dimensions"].get<uint32_t>(), 4u + 8u * 9u);
  EXPECT_EQ(p["bootstrap_paths"].get<uint64_t>(), 5000u);
  EXPECT_FALSE(p.contains("b_by_depth"));
  // Its direct light apart too, R from the first direct samples.
  EXPECT_GT(p["direct_ratio"].get<double>(), 0.0);
  EXPECT_LT(p["direct_ratio"].get<double>(), 1.0);
  EXPECT_GE(p["direct_samples"].get<uint64_t>(), 1u);
  EXPECT_LE(p["direct_samples"].get<uint64_t>(), 4u);
  EXPECT_GT(image_mean(read_image(path("p.exr"))), 0.01);
  // --mlt-direct 0: the chains sample every length, the light seen directly the most.
  r = run_clpt({kCornell, "--device", "pocl", "--integrator", "mlt", "--mlt-direct", "0",
                "--resolution", "16x16", "--spp", "4", "--mlt-chains", "64", "--mlt-bootstrap",
                "5000", "-o", path("d.exr"), "--stats", path("d.json"), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json d = nlohmann::json::parse(test::read_file(path("d.json")))["mlt"];
  EXPECT_GT(d["chains_by_depth"][0].get<uint32_t>(), d["chains_by_depth"][8].get<uint32_t>());
  EXPECT_EQ(d["direct_samples"].get<uint64_t>(), 0u);
  EXPECT_EQ(d["direct_ratio"].get<double>(), 0.0);
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{kCornell, "--integrator", "mlt", "--variance", "-o", path("v.exr")},
        std::vector<std::string>{kCornell, "--integrator", "mlt", "--checkpoint", path("c.ckpt")},
        std::vector<std::string>{kCornell, "--integrator", "mlt", "--branching", "2"},
        std::vector<std::string>{kCornell, "--integrator", "mlt", "--mlt-large-step", "2"}}) {
    r = run_clpt(args);
    EXPECT_EQ(r.exit_code, 1) << args[3] << ": " << r.err;
    EXPECT_FALSE(r.err.empty());
  }
}

TEST_F(Cli, BadPhotonOptionsAreUsageErrors) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{kCornell, "--integrator", "pt", "--photons", "1000"},
        std::vector<std::string>{kCornell, "--integrator", "sppm", "--knn", "10"},
        std::vector<std::string>{kCornell, "--integrator", "sppm", "--final-gather", "4"},
        std::vector<std::string>{kCornell, "--integrator", "pm", "--sppm-radius", "0.1"},
        std::vector<std::string>{kCornell, "--integrator", "pm", "--knn", "0"},
        std::vector<std::string>{kCornell, "--integrator", "pm", "--knn", "257"},
        std::vector<std::string>{kCornell, "--integrator", "pm", "--final-gather", "256"},
        std::vector<std::string>{kCornell, "--integrator", "pm", "--pm-filter", "gauss"},
        std::vector<std::string>{kCornell, "--integrator", "pm", "--pm-max-radius", "0"},
        std::vector<std::string>{kCornell, "--integrator", "sppm", "--sppm-alpha", "1.5"},
        std::vector<std::string>{kCornell, "--integrator", "sppm", "--sppm-radius", "-1"},
        std::vector<std::string>{kCornell, "--integrator", "sppm", "--variance"},
        std::vector<std::string>{kCornell, "--integrator", "sppm", "--checkpoint", path("c.ckpt")}}) {
    const test::RunResult r = run_clpt(args);
    EXPECT_EQ(r.exit_code, 1) << args[2] << " " << args[3] << ": " << r.err;
    EXPECT_FALSE(r.err.empty());
  }
}

// pm and sppm render and report their photons; sppm has no per-pixel variance.
TEST_F(Cli, PhotonMappersWriteStats) {
  for (const std::string integrator : {"pm", "sppm"}) {
    std::vector<std::string> args = {kCornell, "--device", "pocl", "--integrator", integrator,
                                     "--resolution", "16x16", "--spp", "3", "--photons", "5000",
                                     "-o", path(integrator + ".exr"), "--stats",
                                     path(integrator + ".json"), "-q"};
    if (integrator == "pm") args.insert(args.end(), {"--caustic-photons", "2000"});
    const test::RunResult r = run_clpt(args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(test::read_file(path(integrator + ".json")));
    const nlohmann::json& ph = j["photons"];
    // pm: the global map's 5000 paths and the caustic map's 2000; sppm: 5000 per pass.
    EXPECT_EQ(ph["paths"].get<uint64_t>(), integrator == "pm" ? 5000u + 2000u : 3u * 5000u);
    EXPECT_GT(ph["stored"].get<uint64_t>(), 1000u);  // pm: the box has no caustic photons
    EXPECT_GT(ph["rays"].get<uint64_t>(), ph["paths"].get<uint64_t>() / 2);
    EXPECT_EQ(ph[integrator == "pm" ? "maps" : "grid_builds"].get<uint64_t>(), integrator == "pm" ? 2u : 3u);
    EXPECT_GT(ph["device_bytes"].get<uint64_t>(), 64u * 1000u);
    EXPECT_EQ(j["spp"].get<uint64_t>(), 3u);
    EXPECT_EQ(j["mean_variance"].is_null(), integrator == "sppm");
    const Image img = read_image(path(integrator + ".exr"));
    EXPECT_GT(image_mean(img), 0.01) << integrator;
  }
}

TEST_F(Cli, MissingSceneNamesTheFile) {
  const test::RunResult r = run_clpt({path("missing.gltf"), "-o", path("o.png")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("missing.gltf"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("o.png")));
}

TEST_F(Cli, FailedRunKeepsTheExistingOutput) {
  { std::ofstream(path("keep.png")) << "precious"; }
  std::ofstream(path("broken.gltf")) << "{ this is not json";
  const test::RunResult r = run_clpt({path("broken.gltf"), "-o", path("keep.png")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("broken.gltf"), std::string::npos) << r.err;
  EXPECT_EQ(test::read_file(path("keep.png")), "precious");
  size_t files = 0;
  for (auto it = fs::directory_iterator(dir_); it != fs::directory_iterator(); ++it) ++files;
  EXPECT_EQ(files, 2u) << "no temporary file may be left behind";
}

TEST_F(Cli, UnwritableOutputFolderFailsBeforeRendering) {
  const test::RunResult r = run_clpt({kCornell, "-o", path("no/such/folder/out.exr")});
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
}

TEST_F(Cli, UnknownDeviceListsDevices) {
  const test::RunResult r = run_clpt({kCornell, "--device", "no-such-device-xyz", "-o", path("o.exr")});
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("no-such-device-xyz"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("OpenCL devices found"), std::string::npos) << r.err;
}

TEST_F(Cli, ListDevicesShowsPocl) {
  const test::RunResult r = run_clpt({"--list-devices"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("Portable Computing Language"), std::string::npos) << r.out;
}

// clpt asks PoCL for its plain work-item loops (cl::apply_runtime_settings: faster than PoCL's
// default for clpt's kernels, docs/BENCHMARKS.md session 45) before the first OpenCL call, and
// keeps a method the user names.
TEST_F(Cli, PoclWorkGroupMethodIsLoopsUnlessTheUserNamesOne) {
  test::RunResult r = test::run_program(CLPT_BINARY, {"--verbose", "--list-devices"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("PoCL work-group method: loops"), std::string::npos) << r.err;
  test::RunOptions own;
  own.env = {{"POCL_WORK_GROUP_METHOD", "cbs"}};
  r = test::run_program(CLPT_BINARY, {"--verbose", "--list-devices"}, own);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("PoCL work-group method: cbs (POCL_WORK_GROUP_METHOD)"), std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("method: loops"), std::string::npos) << r.err;
}

TEST_F(Cli, RendersExrWithMetadataAndStats) {
  const test::RunResult r = run_clpt({kCornell, "--device", "pocl", "--resolution", "40x30",
                                      "--spp", "3", "-o", path("c.exr"), "--stats",
                                      path("stats.json"), "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << "--quiet prints nothing on success: " << r.err;
  auto in = OIIO::ImageInput::open(path("c.exr"));
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().width, 40);
  EXPECT_EQ(in->spec().height, 30);
  EXPECT_EQ(in->spec().format, OIIO::TypeDesc::FLOAT);
  EXPECT_EQ(in->spec().get_int_attribute("clpt:spp"), 3);
  EXPECT_EQ(in->spec().get_string_attribute("clpt:integrator"), "pt");
  const nlohmann::json j = nlohmann::json::parse(test::read_file(path("stats.json")));
  EXPECT_EQ(j["spp"], 3);
  EXPECT_GT(j["rays"].get<double>(), 40.0 * 30 * 3);
  EXPECT_GT(j["camera_paths_per_second"].get<double>(), 0.0);
  EXPECT_TRUE(j["kernel"].contains("from_cache"));
  // PoCL's device tests a leaf's triangles four at a time, so the tree's leaves hold up to 8.
  EXPECT_EQ(j["bvh"]["max_leaf"], 8);
}

TEST_F(Cli, RendersPngThatLooksLikeACornellBox) {
  const test::RunResult r = run_clpt({kCornell, "--device", "pocl", "--resolution", "32x32",
                                      "--spp", "16", "-o", path("c.png"), "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Image img = read_image(path("c.png"));
  ASSERT_EQ(img.width, 32u);
  // Left wall red, right wall green (middle row, near the edges).
  const float* left = img.pixel(2, 16);
  const float* right = img.pixel(29, 16);
  EXPECT_GT(left[0], 2.0f * left[1]) << "left wall should be red";
  EXPECT_GT(right[1], 2.0f * right[0]) << "right wall should be green";
}

TEST_F(Cli, InterruptSavesWhatWasRendered) {
  const test::RunResult r = run_clpt({kCornell, "--device", "pocl", "--resolution", "64x64",
                                      "--time", "60", "-o", path("i.exr")},
                                     "rendering ", 1.5);
  EXPECT_EQ(r.exit_code, 130) << r.err;
  auto in = OIIO::ImageInput::open(path("i.exr"));
  ASSERT_TRUE(in) << "the interrupted render must be saved";
  EXPECT_GT(in->spec().get_int_attribute("clpt:spp"), 0);
}

// A second Ctrl-C leaves at once, without touching the output. Each pass is long (1 spp of
// 2048 x 2048: seconds on 2 cores). The control run shows that one SIGINT at that moment
// lands inside a pass, which is then finished and written; a second SIGINT 0.2 s after the
// first must end the process before that.
TEST_F(Cli, SecondInterruptLeavesAtOnceWithoutWriting) {
  auto render = [&](const std::string& out, int interrupts) {
    {
      std::ofstream f(out, std::ios::binary);
      f << "previous result";
    }
    test::RunOptions ro;
    ro.interrupt_after = "rendering ";
    ro.delay = 1.0;
    ro.interrupts = interrupts;
    ro.interval = 0.2;
    return test::run_program(
        CLPT_BINARY,
        {kCornell, "--device", "pocl", "--resolution", "2048x2048", "--spp", "2", "-o", out}, ro);
  };
  const std::string once = path("once.exr"), twice = path("twice.exr");
  const test::RunResult control = render(once, 1);
  EXPECT_EQ(control.exit_code, 130) << control.err;
  ASSERT_NE(test::read_file(once), "previous result")
      << "control: one SIGINT should land inside a pass and save it: " << control.err;
  const test::RunResult r = render(twice, 2);
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_EQ(test::read_file(twice), "previous result") << "the second Ctrl-C must not write";
}

}  // namespace
}  // namespace clpt::cli_test

namespace clpt::cli_test {
namespace {

TEST_F(Cli, CameraByIndexAndByName) {
  const std::string shared = std::string(CLPT_SHARED_SCENES_DIR) + "/Cameras/glTF/Cameras.gltf";
  if (!std::filesystem::exists(shared)) GTEST_SKIP() << shared << " not found (../shared/scenes absent)";
  // Cameras.gltf: camera 0 perspective, camera 1 orthographic (xmag 1, ymag 1).
  test::RunResult r = run_clpt({shared, "--camera", "1", "--spp", "1", "-o", path("c1.exr"), "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  auto in = OIIO::ImageInput::open(path("c1.exr"));
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().width, 640);
  EXPECT_EQ(in->spec().height, 640) << "orthographic xmag/ymag 1:1 gives a square default image";
  r = run_clpt({shared, "--camera", "2", "--spp", "1", "-o", path("c2.exr")});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("the scene has 2 camera(s)"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path("c2.exr")));
  // The camera named after its node.
  const std::string named = std::string(CLPT_TEST_DATA_DIR) + "/valid/quad_trs_u8.gltf";
  r = run_clpt({named, "--camera", "CameraNode", "--spp", "1", "--resolution", "8x8", "-o", path("n.exr"), "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run_clpt({named, "--camera", "NoSuchCamera", "--spp", "1", "-o", path("m.exr")});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("'CameraNode'"), std::string::npos) << "the error lists the cameras: " << r.err;
}

// Numbers on the command line (issue 23, class 10): every real-valued option refuses NaN,
// infinities and values past a float's range with exit 1 naming the option (CLI11's range
// checks let NaN through); a camera index too long for any count is out of range, not an
// internal error; a --time too short for one pass still renders one.
TEST(CliNumbers, NonFiniteRealsAreUsageErrorsNamingTheOption) {
  // option, and what it needs beside it to be read at all
  const std::vector<std::pair<const char*, std::vector<const char*>>> reals = {
      {"--time", {}}, {"--exposure", {}}, {"--save-every", {}}, {"--aperture", {}}, {"--focus-distance", {}}, {"--env-scale", {}},
      {"--env-rotate", {}}, {"--ao-radius", {"--integrator", "ao"}},
      {"--pm-max-radius", {"--integrator", "pm"}}, {"--sppm-radius", {"--integrator", "sppm"}},
      {"--sppm-alpha", {"--integrator", "sppm"}}, {"--mlt-large-step", {"--integrator", "mlt"}},
      {"--mlt-sigma", {"--integrator", "mlt"}}, {"--ic-error", {"--integrator", "ic"}},
      {"--ic-min-spacing", {"--integrator", "ic"}}, {"--ic-max-spacing", {"--integrator", "ic"}},
      {"--vcm-radius", {"--integrator", "vcm"}}, {"--vcm-alpha", {"--integrator", "vcm"}},
      {"--filter-radius", {"--filter", "gaussian"}}, {"--checkpoint-interval", {"--checkpoint", "c.ckpt"}}};
  for (const auto& [name, context] : reals)
    for (const char* value : {"nan", "NaN", "inf", "-inf", "1e39", "1e999"}) {
      std::vector<const char*> args = {"s.gltf", name, value};
      args.insert(args.end(), context.begin(), context.end());
      EXPECT_EQ(test::parse_error(args), ExitCode::Usage) << name << " " << value;
    }
  // The same options still take ordinary values.
  EXPECT_EQ(test::parse_error({"s.gltf", "--env-rotate", "-45.5", "--aperture", "0", "--time", "2.5"}),
            ExitCode::Ok);
  const test::RunResult r = test::run_clpt({kCornell, "--env-scale", "nan", "-o", "/tmp/never.exr"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--env-scale"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not a finite number"), std::string::npos) << r.err;
}

// --filter (issue 24): the names and radii it takes, for every integrator, and its record in
// the image's metadata and --stats.
TEST(CliFilter, NamesRadiiAndIntegrators) {
  for (const char* f : {"box", "tent", "gaussian", "blackman-harris"})
    EXPECT_EQ(test::parse_error({"s.gltf", "--filter", f}), ExitCode::Ok) << f;
  EXPECT_EQ(test::parse_error({"s.gltf", "--filter", "mitchell"}), ExitCode::Usage);
  EXPECT_EQ(test::parse_error({"s.gltf", "--filter-radius", "0"}), ExitCode::Usage);
  EXPECT_EQ(test::parse_error({"s.gltf", "--filter-radius", "9"}), ExitCode::Usage);
  for (const char* integrator : {"pt", "lt", "bdpt", "pm", "sppm", "vcm", "mlt", "ic", "ao", "direct", "indirect1"})
    EXPECT_EQ(test::parse_error({"s.gltf", "--integrator", integrator, "--filter", "tent", "--filter-radius", "1.5"}),
              ExitCode::Ok)
        << integrator;
}

TEST_F(Cli, FilterIsInTheMetadataAndStats) {
  const test::RunResult r = run_clpt({kCornell, "--filter", "blackman-harris", "--spp", "2", "--resolution", "8x8",
                                      "-q", "-o", path("f.exr"), "--stats", path("f.json")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto in = OIIO::ImageInput::open(path("f.exr"));
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().get_string_attribute("clpt:filter"), "blackman-harris");
  EXPECT_FLOAT_EQ(in->spec().get_float_attribute("clpt:filter_radius"), 2.0f);
  std::ifstream f(path("f.json"));
  const nlohmann::json j = nlohmann::json::parse(f);
  EXPECT_EQ(j["filter"]["name"], "blackman-harris");
  EXPECT_EQ(j["filter"]["radius"], 2.0);
}

TEST_F(Cli, HugeCameraIndexIsOutOfRangeAndATinyTimeStillRenders) {
  test::RunResult r = run_clpt({kCornell, "--camera", "99999999999999999999999", "-o", path("c.exr")});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("the scene has 1 camera(s)"), std::string::npos) << r.err;
  r = run_clpt({kCornell, "--time", "1e-300", "--resolution", "8x8", "-o", path("t.exr"), "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(path("t.exr"))) << "a render under --time takes at least one pass";
}

}  // namespace
}  // namespace clpt::cli_test
