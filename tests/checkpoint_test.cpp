// ResumeAndSave: checkpoints written atomically, resumed renders equal uninterrupted ones
// bit for bit, and damaged or mismatched checkpoints are clear errors.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "io/image_io.h"
#include "support/run.h"

namespace clpt::checkpoint_test {
namespace {
namespace fs = std::filesystem;
using test::run_clpt;

const std::string kCornell = std::string(CLPT_SOURCE_DIR) + "/scenes/cornell_box.gltf";

class ResumeAndSave : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("clpt-ckpt-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& n) const { return (dir_ / n).string(); }
  test::RunResult render(std::vector<std::string> extra) {
    std::vector<std::string> args = {kCornell, "--device", "pocl", "--resolution", "24x24", "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_clpt(args);
  }
  static bool same_pixels(const std::string& a, const std::string& b) {
    const Image x = read_image(a), y = read_image(b);
    return x.rgb.size() == y.rgb.size() &&
           std::memcmp(x.rgb.data(), y.rgb.data(), x.rgb.size() * sizeof(float)) == 0;
  }
  fs::path dir_;
};

TEST_F(ResumeAndSave, ResumedEqualsUninterruptedBitForBit) {
  ASSERT_EQ(render({"--spp", "6", "--checkpoint", path("c.ckpt"), "-o", path("half.exr")}).exit_code, 0);
  ASSERT_TRUE(fs::exists(path("c.ckpt")));
  const test::RunResult r = render({"--spp", "12", "--resume", path("c.ckpt"), "-o", path("resumed.exr")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_EQ(render({"--spp", "12", "-o", path("full.exr")}).exit_code, 0);
  EXPECT_TRUE(same_pixels(path("resumed.exr"), path("full.exr")));
  EXPECT_FALSE(same_pixels(path("half.exr"), path("full.exr")));
  const ImageChannels resumed = read_image_channels(path("resumed.exr"));
  EXPECT_EQ(resumed.int_attribute("clpt:spp"), 12);
}

TEST_F(ResumeAndSave, StratifiedResumesWithTheSameTotal) {
  ASSERT_EQ(render({"--spp", "16", "--sampler", "stratified", "--time", "60", "--checkpoint",
                    path("s.ckpt"), "-o", path("s.exr")}).exit_code, 0);
  // The strata depend on --spp: a different total is refused.
  const test::RunResult r = render({"--spp", "32", "--sampler", "stratified", "--resume",
                                    path("s.ckpt"), "-o", path("t.exr")});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("other settings"), std::string::npos) << r.err;
}

TEST_F(ResumeAndSave, InterruptedRenderLeavesAResumableCheckpoint) {
  const test::RunResult r = run_clpt({kCornell, "--device", "pocl", "--resolution", "48x48",
                                      "--spp", "100000", "--checkpoint", path("i.ckpt"), "-o",
                                      path("i.exr")},
                                     "rendering ", 1.5);
  ASSERT_EQ(r.exit_code, 130) << r.err;
  ASSERT_TRUE(fs::exists(path("i.ckpt")));
  const int spp = read_image_channels(path("i.exr")).int_attribute("clpt:spp");
  ASSERT_GT(spp, 0);
  // Resuming to exactly the samples already taken renders nothing new: same image.
  const test::RunResult again =
      run_clpt({kCornell, "--device", "pocl", "--resolution", "48x48", "--spp", std::to_string(spp),
                "--resume", path("i.ckpt"), "-o", path("j.exr"), "-q"});
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_TRUE(same_pixels(path("i.exr"), path("j.exr")));
}

TEST_F(ResumeAndSave, MismatchedSettingsAreRefused) {
  ASSERT_EQ(render({"--spp", "2", "--checkpoint", path("c.ckpt"), "-o", path("a.exr")}).exit_code, 0);
  for (const std::vector<std::string>& extra :
       {std::vector<std::string>{"--seed", "9"}, std::vector<std::string>{"--max-depth", "3"},
        std::vector<std::string>{"--direct", "light"}}) {
    std::vector<std::string> args = {"--spp", "4", "--resume", path("c.ckpt"), "-o", path("b.exr")};
    args.insert(args.end(), extra.begin(), extra.end());
    const test::RunResult r = render(args);
    EXPECT_EQ(r.exit_code, 1) << extra[0];
    EXPECT_NE(r.err.find("cannot be resumed"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("b.exr")));
  }
}

TEST_F(ResumeAndSave, DamagedCheckpointsAreClearErrors) {
  ASSERT_EQ(render({"--spp", "2", "--checkpoint", path("c.ckpt"), "-o", path("a.exr")}).exit_code, 0);
  const auto size = fs::file_size(path("c.ckpt"));
  fs::copy_file(path("c.ckpt"), path("flipped.ckpt"));
  {
    std::fstream f(path("flipped.ckpt"), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size - 100));
    f.write("\x7f", 1);
  }
  fs::copy_file(path("c.ckpt"), path("short.ckpt"));
  fs::resize_file(path("short.ckpt"), size / 2);
  std::ofstream(path("foreign.ckpt")) << "not a checkpoint at all";
  // The header's sample count (bytes 16 to 23) halved: covered by the checksum (issue 23,
  // class 8; format 1 resumed it, an image twice as dark).
  fs::copy_file(path("c.ckpt"), path("header.ckpt"));
  {
    std::fstream f(path("header.ckpt"), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(16);
    const uint64_t one = 1;
    f.write(reinterpret_cast<const char*>(&one), sizeof one);
  }
  // A format-1 file (its magic's last byte '1'): refused by name.
  fs::copy_file(path("c.ckpt"), path("v1.ckpt"));
  {
    std::fstream f(path("v1.ckpt"), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(7);
    f.write("1", 1);
  }
  for (const char* name : {"flipped.ckpt", "short.ckpt", "foreign.ckpt", "missing.ckpt",
                           "header.ckpt", "v1.ckpt"}) {
    const test::RunResult r = render({"--spp", "4", "--resume", path(name), "-o", path("b.exr")});
    EXPECT_EQ(r.exit_code, 2) << name << ": " << r.err;
    EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("b.exr")));
    if (std::string(name) == "header.ckpt") {
      EXPECT_NE(r.err.find("checksum"), std::string::npos) << r.err;
    }
    if (std::string(name) == "v1.ckpt") {
      EXPECT_NE(r.err.find("format 1"), std::string::npos) << r.err;
    }
  }
}

}  // namespace
}  // namespace clpt::checkpoint_test
