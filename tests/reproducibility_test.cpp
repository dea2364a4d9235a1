// The same seed gives the same image, however the renderer splits the samples into passes:
// clpt run twice as a user would, once with passes of about a microsecond (1 spp each) and
// once with passes of 100 s (1, 2, 4, ... spp), on one PoCL thread (so that atomic splats
// land in one order), must write bit-identical pixels. pt's samples depend on their index
// alone; mlt's passes run whole mutations per chain, so the renderer gives it a schedule
// that does not look at the clock (host/render/renderer.cpp). Without that schedule both
// mlt cases fail here.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "io/image_io.h"
#include "support/run.h"

namespace clpt::reproducibility_test {
namespace {

namespace fs = std::filesystem;

struct Case {
  const char* name;
  std::vector<std::string> args;
};

class Reproducible : public ::testing::TestWithParam<Case> {};

TEST_P(Reproducible, WhateverThePassLength) {
  const Case& c = GetParam();
  const fs::path dir = fs::temp_directory_path() / ("clpt-repro-" + std::to_string(::getpid()) + "-" + c.name);
  fs::create_directories(dir);
  test::RunOptions env;
  env.env = {{"POCL_MAX_PTHREAD_COUNT", "1"}, {"POCL_MAX_CPU_CU_COUNT", "1"}};
  std::vector<Image> images;
  for (const char* seconds : {"1e-6", "100"}) {
    const std::string out = (dir / (std::string("pass") + seconds + ".exr")).string();
    std::vector<std::string> args = {std::string(CLPT_SOURCE_DIR) + "/scenes/cornell_box.gltf",
                                     "--device", "pocl", "-q", "--resolution", "24x24", "--spp", "8",
                                     "--pass-seconds", seconds, "-o", out};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const test::RunResult r = test::run_program(CLPT_BINARY, args, env);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    images.push_back(read_image(out));
  }
  fs::remove_all(dir);
  ASSERT_EQ(images[0].rgb.size(), images[1].rgb.size());
  size_t differ = 0;
  for (size_t i = 0; i < images[0].rgb.size(); ++i)
    differ += std::memcmp(&images[0].rgb[i], &images[1].rgb[i], sizeof(float)) != 0;
  EXPECT_EQ(differ, 0u) << differ << " of " << images[0].rgb.size() << " values differ between the pass lengths";
}

INSTANTIATE_TEST_SUITE_P(Integrators, Reproducible,
                         ::testing::Values(Case{"pt", {"--integrator", "pt"}},
                                           Case{"pssmlt", {"--integrator", "mlt", "--mlt-mode", "pssmlt",
                                                           "--mlt-bootstrap", "5000"}},
                                           Case{"mmlt", {"--integrator", "mlt", "--mlt-bootstrap", "5000"}}),
                         [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

}  // namespace
}  // namespace clpt::reproducibility_test
