// ClptDiff: the clpt-diff program as scripts run it (figures in --json, exit codes 0/1/2,
// error maps), and EXR files with variance channels through image_io.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <OpenImageIO/imageio.h>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include "io/image_io.h"
#include "stats/image_stats.h"
#include "support/run.h"
#include "util/error.h"

namespace clpt::clpt_diff_test {
namespace {
namespace fs = std::filesystem;

// Runs CLPT_DIFF_BINARY with args (no shell), capturing exit code, stdout and stderr.
test::RunResult run_diff(const std::vector<std::string>& args) {
  return test::run_program(CLPT_DIFF_BINARY, args);
}

Image filled(uint32_t w, uint32_t h, float v) {
  Image img(w, h);
  for (float& x : img.rgb) x = v;
  return img;
}

class ClptDiff : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("clpt-diff-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const Image& img,
                    const std::vector<NamedChannel>& layers = {}) const {
    write_image(path(name), img, ImageMetadata{}, layers);
    return path(name);
  }
  // Runs with --json and parses stdout; fails the test when stdout is not JSON.
  nlohmann::json json(const std::vector<std::string>& args, int expected_exit = 0) const {
    std::vector<std::string> a = args;
    a.push_back("--json");
    const test::RunResult r = run_diff(a);
    EXPECT_EQ(r.exit_code, expected_exit) << r.err;
    try {
      return nlohmann::json::parse(r.out);
    } catch (const std::exception& e) {
      ADD_FAILURE() << "stdout is not JSON: " << e.what() << "\n" << r.out << "\n" << r.err;
      return {};
    }
  }
  fs::path dir_;
};

TEST_F(ClptDiff, IdenticalImagesHaveZeroError) {
  Image img(5, 3);
  for (size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = 0.1f * float(i);
  const std::string a = write("a.exr", img), b = write("b.exr", img);
  const test::RunResult r = run_diff({a, b});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("relMSE       0\n"), std::string::npos) << r.out;
  const nlohmann::json j = json({a, b});
  EXPECT_EQ(j["relmse"].get<double>(), 0.0);
  EXPECT_EQ(j["smape"].get<double>(), 0.0);
  EXPECT_EQ(j["compared"].get<int>(), 45);
  EXPECT_TRUE(j["z_test"].is_null());
}

// Constant 0.75 against constant 0.25: relMSE = 0.5² / 0.26², MSE 0.25, SMAPE 0.5 / 1.0001.
TEST_F(ClptDiff, KnownDifferenceInJson) {
  const std::string v = write("v.exr", filled(4, 2, 0.75f)), r = write("r.exr", filled(4, 2, 0.25f));
  const nlohmann::json j = json({v, r});
  const double rel = 0.25 / (0.26 * 0.26);
  EXPECT_NEAR(j["relmse"].get<double>(), rel, 1e-12 * rel);
  EXPECT_DOUBLE_EQ(j["mse"].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(j["rmse"].get<double>(), 0.5);
  EXPECT_NEAR(j["smape"].get<double>(), 0.5 / 1.0001, 1e-14);
  EXPECT_DOUBLE_EQ(j["max_abs_diff"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(j["image"]["mean"].get<double>(), 0.75);
  EXPECT_DOUBLE_EQ(j["reference"]["mean"].get<double>(), 0.25);
  EXPECT_EQ(j["image"]["width"].get<int>(), 4);
  EXPECT_EQ(j["image"]["height"].get<int>(), 2);
  EXPECT_EQ(j["image"]["nan"].get<int>(), 0);
  EXPECT_TRUE(j["checks_passed"].get<bool>());
}

TEST_F(ClptDiff, MaxRelMseSetsExitOne) {
  const std::string v = write("v.exr", filled(2, 2, 0.75f)), r = write("r.exr", filled(2, 2, 0.25f));
  // relMSE = 0.25 / 0.26² = 3.698
  test::RunResult res = run_diff({v, r, "--max-relmse", "3.6"});
  EXPECT_EQ(res.exit_code, 1) << res.err;
  EXPECT_NE(res.err.find("relMSE"), std::string::npos) << res.err;
  res = run_diff({v, r, "--max-relmse", "3.8"});
  EXPECT_EQ(res.exit_code, 0) << res.err;
  EXPECT_FALSE(json({v, r, "--max-relmse", "3.6"}, 1)["checks_passed"].get<bool>());
}

TEST_F(ClptDiff, MissingFileIsExitTwoNamingIt) {
  const std::string r = write("r.exr", filled(2, 2, 0.25f));
  test::RunResult res = run_diff({path("missing.exr"), r});
  EXPECT_EQ(res.exit_code, 2);
  EXPECT_NE(res.err.find("missing.exr"), std::string::npos) << res.err;
  res = run_diff({r, path("absent-reference.exr")});
  EXPECT_EQ(res.exit_code, 2);
  EXPECT_NE(res.err.find("absent-reference.exr"), std::string::npos) << res.err;
  // Not an image at all.
  std::ofstream(path("garbage.exr")) << "this is not an EXR";
  res = run_diff({path("garbage.exr"), r});
  EXPECT_EQ(res.exit_code, 2);
  EXPECT_NE(res.err.find("garbage.exr"), std::string::npos) << res.err;
}

TEST_F(ClptDiff, SizeMismatchIsExitTwo) {
  const std::string a = write("a.exr", filled(3, 2, 1.0f)), b = write("b.exr", filled(2, 3, 1.0f));
  const test::RunResult res = run_diff({a, b});
  EXPECT_EQ(res.exit_code, 2);
  EXPECT_NE(res.err.find("3x2"), std::string::npos) << res.err;
  EXPECT_NE(res.err.find("2x3"), std::string::npos) << res.err;
  EXPECT_NE(res.err.find("a.exr"), std::string::npos) << res.err;
  EXPECT_TRUE(res.out.empty()) << res.out;
}

TEST_F(ClptDiff, BadCommandLineIsExitTwo) {
  const std::string a = write("a.exr", filled(1, 1, 1.0f));
  EXPECT_EQ(run_diff({}).exit_code, 2);
  EXPECT_EQ(run_diff({a}).exit_code, 2);
  EXPECT_EQ(run_diff({a, a, "--no-such-option"}).exit_code, 2);
  EXPECT_EQ(run_diff({a, a, "--max-relmse", "abc"}).exit_code, 2);
  EXPECT_EQ(run_diff({a, a, "--min-z-pass", "1.5"}).exit_code, 2);
  EXPECT_EQ(run_diff({a, a, "--error-range", "1", "0.1"}).exit_code, 2);
  // --min-z-pass without any variance channels cannot be checked.
  const test::RunResult r = run_diff({a, a, "--min-z-pass", "0.99"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("variance"), std::string::npos) << r.err;
  const test::RunResult h = run_diff({"--help"});
  EXPECT_EQ(h.exit_code, 0);
  EXPECT_NE(h.out.find("--max-relmse"), std::string::npos);
  EXPECT_NE(h.out.find("relMSE"), std::string::npos);
}

// NaN and Inf pixels never crash; they are counted, left out of the figures and fail checks.
TEST_F(ClptDiff, NanImagesAndOnePixelImages) {
  Image v = filled(2, 1, 0.5f);
  v.rgb[0] = std::numeric_limits<float>::quiet_NaN();
  v.rgb[4] = std::numeric_limits<float>::infinity();
  const std::string a = write("nan.exr", v), b = write("ref.exr", filled(2, 1, 0.5f));
  nlohmann::json j = json({a, b});
  EXPECT_EQ(j["image"]["nan"].get<int>(), 1);
  EXPECT_EQ(j["image"]["inf"].get<int>(), 1);
  EXPECT_EQ(j["compared"].get<int>(), 4);
  EXPECT_EQ(j["relmse"].get<double>(), 0.0);
  EXPECT_EQ(run_diff({a, b, "--max-relmse", "1"}).exit_code, 1);
  EXPECT_EQ(run_diff({a, b, "--error-map", path("nan.png")}).exit_code, 0);

  // All NaN: no finite value at all; figures are null in JSON, no crash.
  const std::string all = write("all.exr", filled(1, 1, std::numeric_limits<float>::quiet_NaN()));
  j = json({all, all});
  EXPECT_EQ(j["compared"].get<int>(), 0);
  EXPECT_TRUE(j["relmse"].is_null());
  EXPECT_EQ(run_diff({all, all}).exit_code, 0);

  const std::string one = write("one.exr", filled(1, 1, 2.0f));
  j = json({one, one});
  EXPECT_EQ(j["relmse"].get<double>(), 0.0);
}

// Pixel 0 identical (darkest colour), pixel 1 with relative squared error ≈ 1 (the bright
// end of the default range 1e-6..1), pixel 2 NaN (red), pixel 3 error 15 (clamped to the
// bright end); 3x2 so that width and height differ.
TEST_F(ClptDiff, ErrorMapPng) {
  Image v = filled(3, 2, 0.5f), r = filled(3, 2, 0.5f);
  for (int c = 0; c < 3; ++c) {
    v.rgb[3 + c] = 1.01f;  // (0.51 / 0.51)² ≈ 1
    v.rgb[9 + c] = 2.5f;   // 2² / 0.51² ≈ 15.4
  }
  v.rgb[6] = std::numeric_limits<float>::quiet_NaN();
  const std::string a = write("v.exr", v), b = write("r.exr", r);
  const test::RunResult res = run_diff({a, b, "--error-map", path("err.png")});
  ASSERT_EQ(res.exit_code, 0) << res.err;
  auto in = OIIO::ImageInput::open(path("err.png"));
  ASSERT_TRUE(in) << "no error map written";
  EXPECT_EQ(in->spec().width, 3);
  EXPECT_EQ(in->spec().height, 2);
  ASSERT_GE(in->spec().nchannels, 3);
  std::vector<unsigned char> px(size_t(3 * 2 * in->spec().nchannels));
  ASSERT_TRUE(in->read_image(0, 0, 0, in->spec().nchannels, OIIO::TypeDesc::UINT8, px.data()));
  const int n = in->spec().nchannels;
  auto rgb = [&](int i) { return std::vector<int>{px[i * n], px[i * n + 1], px[i * n + 2]}; };
  EXPECT_EQ(rgb(0), (std::vector<int>{0x44, 0x01, 0x54})) << "viridis' dark end";
  EXPECT_EQ(rgb(3), (std::vector<int>{0xfd, 0xe7, 0x25})) << "viridis' bright end";
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(rgb(1)[k], rgb(3)[k], 1) << "error 1 is the top of 1e-6..1";
  EXPECT_EQ(rgb(2), (std::vector<int>{0xff, 0x00, 0x00})) << "non-finite marker";

  // The log scale: with --error-range 1e-4 1e4 an error of 1 sits at the middle stop.
  ASSERT_EQ(run_diff({a, b, "--error-map", path("mid.png"), "--error-range", "1e-4", "1e4"}).exit_code, 0);
  const Image mid = read_image(path("mid.png"));
  EXPECT_NEAR(mid.pixel(1, 0)[1], std::pow((0x91 / 255.0 + 0.055) / 1.055, 2.4), 1e-3)
      << "green of viridis(0.5) = #21918c";

  // An unwritable error map is trouble (exit 2), found before any work.
  EXPECT_EQ(run_diff({a, b, "--error-map", path("no/such/dir/e.png")}).exit_code, 2);
  // .exr: the raw relative squared errors.
  ASSERT_EQ(run_diff({a, b, "--error-map", path("err.exr")}).exit_code, 0);
  const Image raw = read_image(path("err.exr"));
  const double d = double(1.01f) - 0.5;
  EXPECT_FLOAT_EQ(raw.pixel(1, 0)[0], float(d * d / (0.51 * 0.51)));
  EXPECT_TRUE(std::isnan(raw.pixel(2, 0)[0]));
  EXPECT_EQ(raw.pixel(0, 0)[0], 0.0f);
}

TEST_F(ClptDiff, ExrVarianceChannelsRoundTrip) {
  Image img(3, 2), var(3, 2), other(3, 2);
  for (size_t i = 0; i < img.rgb.size(); ++i) {
    img.rgb[i] = 0.25f * float(i);
    var.rgb[i] = 1e-3f * float(i + 1);
    other.rgb[i] = -float(i);
  }
  ImageMetadata meta;
  meta.ints = {{"clpt:spp", 64}};
  meta.strings = {{"clpt:integrator", "pt"}};
  write_image(path("v.exr"), img, meta, {{kVarianceLayer, var}, {"albedo", other}});

  // The file has the channels by their EXR names.
  {
    auto in = OIIO::ImageInput::open(path("v.exr"));
    ASSERT_TRUE(in);
    const auto& names = in->spec().channelnames;
    for (const char* n : {"R", "G", "B", "variance.R", "variance.G", "variance.B", "albedo.R"})
      EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
    EXPECT_EQ(in->spec().nchannels, 9);
  }
  const ImageChannels back = read_image_channels(path("v.exr"));
  EXPECT_EQ(back.image.rgb, img.rgb);
  ASSERT_NE(back.variance(), nullptr);
  EXPECT_EQ(back.variance()->rgb, var.rgb);
  ASSERT_NE(back.layer("albedo"), nullptr);
  EXPECT_EQ(back.layer("albedo")->rgb, other.rgb);
  EXPECT_EQ(back.layer("nope"), nullptr);
  EXPECT_EQ(back.int_attribute("clpt:spp"), 64);
  EXPECT_EQ(read_image(path("v.exr")).rgb, img.rgb) << "read_image keeps reading R, G, B";

  // No temporary file is left behind.
  size_t files = 0;
  for (auto it = fs::directory_iterator(dir_); it != fs::directory_iterator(); ++it) ++files;
  EXPECT_EQ(files, 1u);

  // PNG ignores the layers.
  write_image(path("v.png"), img, meta, {{kVarianceLayer, var}});
  const ImageChannels png = read_image_channels(path("v.png"));
  EXPECT_TRUE(png.layers.empty());
  EXPECT_EQ(png.image.width, 3u);

  // A layer of the wrong size or a bad name is refused, and nothing is written.
  EXPECT_THROW(write_image(path("bad.exr"), img, meta, {{kVarianceLayer, Image(2, 2)}}), Error);
  EXPECT_THROW(write_image(path("bad.exr"), img, meta, {{"a.b", var}}), Error);
  EXPECT_THROW(write_image(path("bad.exr"), img, meta, {{"v", var}, {"v", var}}), Error);
  EXPECT_FALSE(fs::exists(path("bad.exr")));
}

// A seeded simulated render with its variance channels against a reference: the same
// expectation passes the z-test (≥ 99 %), a biased one fails --min-z-pass (exit 1).
TEST_F(ClptDiff, ZTestFromVarianceChannels) {
  std::mt19937 rng(11);
  const uint32_t w = 16, h = 16;
  Image mu(w, h);
  std::uniform_real_distribution<float> u(0.2f, 1.5f);
  for (float& x : mu.rgb) x = u(rng);
  auto render = [&](int spp, float scale, Image* var) {
    Image m(w, h);
    *var = Image(w, h);
    for (size_t i = 0; i < mu.rgb.size(); ++i) {
      std::exponential_distribution<double> d(1.0 / (mu.rgb[i] * scale));  // sd = mean
      double s = 0.0, sq = 0.0;
      for (int k = 0; k < spp; ++k) {
        const double x = d(rng);
        s += x;
        sq += x * x;
      }
      const double mean = s / spp;
      m.rgb[i] = float(mean);
      var->rgb[i] = float((sq - spp * mean * mean) / (spp - 1) / spp);
    }
    return m;
  };
  Image ref_var, good_var, bad_var;
  const Image ref = render(4096, 1.0f, &ref_var);
  const Image good = render(256, 1.0f, &good_var);
  const Image bad = render(256, 1.5f, &bad_var);
  const std::string r = write("ref.exr", ref, {{kVarianceLayer, ref_var}});
  const std::string g = write("good.exr", good, {{kVarianceLayer, good_var}});
  const std::string b = write("bad.exr", bad, {{kVarianceLayer, bad_var}});

  nlohmann::json j = json({g, r, "--min-z-pass", "0.99"}, 0);
  EXPECT_EQ(j["z_test"]["variance_from"], "both");
  EXPECT_EQ(j["z_test"]["tested"].get<int>(), int(w * h * 3));
  EXPECT_GE(j["z_test"]["pass_fraction"].get<double>(), 0.99);
  EXPECT_NEAR(j["z_test"]["threshold"].get<double>(), sidak_z_threshold(0.01, w * h * 3), 1e-12);

  j = json({b, r, "--min-z-pass", "0.99"}, 1);
  EXPECT_LT(j["z_test"]["pass_fraction"].get<double>(), 0.5);
  EXPECT_FALSE(j["checks_passed"].get<bool>());

  // Variance in one file only: the other is taken as exact.
  const std::string plain_ref = write("plain.exr", ref);
  j = json({g, plain_ref});
  EXPECT_EQ(j["z_test"]["variance_from"], "image");
  j = json({plain_ref, g});
  EXPECT_EQ(j["z_test"]["variance_from"], "reference");
  const test::RunResult text = run_diff({g, r});
  EXPECT_NE(text.out.find("z-test"), std::string::npos);
  EXPECT_NE(text.out.find("pass |z| <"), std::string::npos) << text.out;
}

}  // namespace
}  // namespace clpt::clpt_diff_test
