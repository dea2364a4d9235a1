// `mpirun -n 2 clpt ...` (issue 20, host/mpi/mpi_cluster.cpp, render/cluster.h): two ranks split
// the sample indices of one render and rank 0 adds their films (five ranks: through a tree), so the image equals one
// process's up to the rounding of the sums' order; a rank that fails stops every rank with its
// error and no output; a checkpoint two ranks wrote resumes to one process's image. Skipped,
// saying so, where clpt was built without MPI (CLPT_MPI off or no libopenmpi-dev).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/image_io.h"
#include "support/run.h"
#include "support/split_render.h"

namespace clpt::mpi_test {
namespace {

namespace fs = std::filesystem;

const std::string kCornell = std::string(CLPT_SOURCE_DIR) + "/scenes/cornell_box.gltf";

class Mpi : public test::TestFolder {
 protected:
  void SetUp() override {
    if (std::string(CLPT_MPIEXEC).empty())
      GTEST_SKIP() << "clpt was built without MPI (CLPT_MPI=OFF, or CMake found no MPI: "
                      "apt-get install libopenmpi-dev openmpi-bin)";
    // Whether the launcher can start two processes here at all (`true`, no MPI in it): checked
    // once, with the launcher's own message when it cannot. clpt's own MPI start-up is not
    // excused: a failure there fails the tests.
    static const test::RunResult launcher = test::run_program(
        CLPT_MPIEXEC, {"--oversubscribe", "--allow-run-as-root", "-n", "2", "true"});
    if (launcher.exit_code != 0)
      GTEST_SKIP() << "mpirun cannot start two processes here (exit " << launcher.exit_code
                   << "):\n" << launcher.err;
    make_folder("clpt-mpi");
  }

  // mpirun with one program per rank (MPMD: "prog args : prog args"), as CI's container needs
  // it: as root, more ranks than cores allowed, and shared memory without cross-memory attach
  // (which containers forbid).
  test::RunResult mpirun(const std::vector<std::vector<std::string>>& ranks,
                         const std::vector<std::pair<std::string, std::string>>& env = {},
                         const std::string& interrupt_after = "") const {
    std::vector<std::string> args = {"--oversubscribe", "--allow-run-as-root",
                                     "--mca", "btl_vader_single_copy_mechanism", "none"};
    for (size_t r = 0; r < ranks.size(); ++r) {
      if (r) args.push_back(":");
      args.insert(args.end(), {"-n", "1", CLPT_BINARY});
      args.insert(args.end(), ranks[r].begin(), ranks[r].end());
    }
    test::RunOptions o;
    // One PoCL thread per rank: two ranks on two cores.
    o.env = {{"POCL_MAX_PTHREAD_COUNT", "1"}, {"OMPI_MCA_rmaps_base_oversubscribe", "1"}};
    o.env.insert(o.env.end(), env.begin(), env.end());
    o.interrupt_after = interrupt_after;
    return test::run_program(CLPT_MPIEXEC, args, o);
  }
  // clpt on the Cornell box with `args`, writing `name`.exr and its --stats, by `ranks` MPI
  // ranks (0: one process without mpirun); a failed run fails the test.
  nlohmann::json render(const std::string& name, int ranks, std::vector<std::string> args) const {
    args.insert(args.begin(), {kCornell, "-q", "--device", "pocl"});
    args.insert(args.end(), {"-o", path(name + ".exr"), "--stats=" + path(name + ".json")});
    test::RunResult r;
    if (ranks == 0) {
      test::RunOptions o;
      o.env = {{"POCL_MAX_PTHREAD_COUNT", "1"}};
      r = test::run_program(CLPT_BINARY, args, o);
    } else {
      r = mpirun(std::vector<std::vector<std::string>>(ranks, args));
    }
    EXPECT_EQ(r.exit_code, 0) << r.err;
    if (r.exit_code != 0) return nullptr;
    return nlohmann::json::parse(test::read_file(path(name + ".json")));
  }
};

TEST_F(Mpi, TwoRanksRenderWhatOneProcessRenders) {
  struct Case {
    const char* integrator;
    double max_rel_mse;  // float rounding of the sums' order (splats: a little more)
    std::vector<std::string> more;
  };
  for (const Case& c : {Case{"pt", 1e-10, {}}, Case{"lt", 1e-8, {}}, Case{"bdpt", 1e-8, {}},
                        Case{"vcm", 1e-8, {"--vcm-merged", "--vcm-shrink", "pass"}}  /* per-pixel radii do not split */, Case{"ic", 1e-10, {}}}) {
    SCOPED_TRACE(c.integrator);
    std::vector<std::string> args = {"--integrator", c.integrator, "--resolution", "32x32",
                                     "--spp", "16", "--seed", "5", "--max-depth", "4"};
    args.insert(args.end(), c.more.begin(), c.more.end());
    const std::string name = c.integrator;
    const nlohmann::json one = render(name + "-one", 0, args);
    const nlohmann::json two = render(name + "-two", 2, args);
    if (one.is_null() || two.is_null()) continue;
    test::expect_device_shares(two, 2, 16);
    if (name == "vcm") {
      // Its figures add up over the ranks: every pass once, the same radii, the same merges
      // (to float atomics' order, which does not change counts).
      EXPECT_EQ(two["vcm"]["passes"], 16);
      EXPECT_EQ(two["vcm"]["passes"], one["vcm"]["passes"]);
      EXPECT_EQ(two["vcm"]["first_radius"], one["vcm"]["first_radius"]);
      EXPECT_EQ(two["vcm"]["last_radius"], one["vcm"]["last_radius"]);
      EXPECT_EQ(two["vcm"]["merges"], one["vcm"]["merges"]);
      EXPECT_EQ(two["vcm"]["light_vertices"], one["vcm"]["light_vertices"]);
    }
    EXPECT_EQ(two["devices"][1]["device"].get<std::string>().rfind("rank 1: ", 0), 0u)
        << two["devices"].dump();
    const test::Agreement g =
        test::agreement(read_image(path(name + "-two.exr")), read_image(path(name + "-one.exr")));
    std::printf("%-4s two ranks against one process: relMSE %.3g, mean ratio 1 %+.3g\n",
                c.integrator, g.rel_mse, g.mean_ratio - 1.0);
    EXPECT_LT(g.rel_mse, c.max_rel_mse);
    EXPECT_NEAR(g.mean_ratio, 1.0, 1e-6);
    // Extra layers (vcm's merged part) are gathered from the ranks too.
    const ImageChannels la = read_image_channels(path(name + "-two.exr"));
    for (const NamedChannel& l : read_image_channels(path(name + "-one.exr")).layers) {
      SCOPED_TRACE(l.name);
      const Image* other = la.layer(l.name);
      ASSERT_NE(other, nullptr);
      EXPECT_LT(test::agreement(*other, l.image).rel_mse, c.max_rel_mse);
    }
  }
}

// mlt's ranks run chains of their own (DeviceSplit::Chains, tests/multi_device_test.cpp): rank
// 0's --stats counts every rank's chains, and the image is not one rank's chains at half the
// samples.
TEST_F(Mpi, MetropolisRanksRunChainsOfTheirOwn) {
  auto args = [](const char* spp) {
    return std::vector<std::string>{"--integrator", "mlt", "--resolution", "24x24", "--spp", spp,
                                    "--seed", "3", "--max-depth", "3"};
  };
  const nlohmann::json one = render("mlt-one", 0, args("32"));
  const nlohmann::json two = render("mlt-two", 2, args("32"));
  render("mlt-half", 0, args("16"));
  if (one.is_null() || two.is_null()) return;
  test::expect_device_shares(two, 2, 32);
  EXPECT_EQ(two["mlt"]["chains"].get<uint64_t>(), 2 * one["mlt"]["chains"].get<uint64_t>());
  EXPECT_EQ(two["mlt"]["mutations"], one["mlt"]["mutations"]);
  EXPECT_EQ(two["mlt"]["b_bootstrap"], one["mlt"]["b_bootstrap"]);  // b adds each rank's large steps
  const Image a = read_image(path("mlt-two.exr"));
  const test::Agreement g = test::agreement(a, read_image(path("mlt-one.exr")));
  const test::Agreement same = test::agreement(a, read_image(path("mlt-half.exr")));
  std::printf("mlt two ranks against one process: mean ratio %.4f; against one process's chains "
              "at half the samples: relMSE %.3g\n", g.mean_ratio, same.rel_mse);
  EXPECT_NEAR(g.mean_ratio, 1.0, 0.03);
  EXPECT_GT(same.rel_mse, 1e-3) << "the two ranks ran the same chains";
}

// A film whose arrays are larger than the 16 MiB chunks rank 0 receives in (1100 x 1000 pixels:
// 17.6 MB of sums), with AOVs (64 bytes a pixel): chunk boundaries inside the arrays.
TEST_F(Mpi, LargeFilmsAndAovsArriveWhole) {
  const std::vector<std::string> args = {"--resolution", "1100x1000", "--spp", "2", "--seed", "2",
                                         "--max-depth", "2", "--aov", "albedo,depth,material-id"};
  const nlohmann::json one = render("one", 0, args);
  const nlohmann::json two = render("two", 2, args);
  if (one.is_null() || two.is_null()) return;
  test::expect_device_shares(two, 2, 2);
  const ImageChannels a = read_image_channels(path("two.exr"));
  const ImageChannels b = read_image_channels(path("one.exr"));
  const test::Agreement g = test::agreement(a.image, b.image);
  EXPECT_LT(g.rel_mse, 1e-10);
  EXPECT_NEAR(g.mean_ratio, 1.0, 1e-6);
  for (const char* layer : {"Albedo", "Depth", "IndexMA"}) {
    SCOPED_TRACE(layer);
    const Image* la = a.layer(layer);
    const Image* lb = b.layer(layer);
    ASSERT_TRUE(la && lb);
    size_t differ = 0;
    for (size_t i = 0; i < la->rgb.size(); ++i)
      if (!(std::abs(la->rgb[i] - lb->rgb[i]) <= 1e-5f * std::abs(lb->rgb[i]) + 1e-6f) &&
          !(std::isinf(la->rgb[i]) && std::isinf(lb->rgb[i])))
        ++differ;
    EXPECT_EQ(differ, 0u);
  }
}

// Five ranks: the films reach rank 0 through the binomial tree (rank 1 into 0, 3 into 2, then
// 2 into 0, then 4 into 0), so ranks 2 and 0 add what they received to their own before
// passing it on; an odd count leaves rank 4 without a partner in the first two rounds. The
// image, the vcm merged layer and the AOVs (the material id kept from rank 0's first sample)
// equal one process's.
TEST_F(Mpi, FiveRanksAddUpThroughTheTree) {
  for (const char* integrator : {"pt", "vcm"}) {
    SCOPED_TRACE(integrator);
    const std::string name = integrator;
    std::vector<std::string> args = {"--integrator", integrator, "--resolution", "24x24", "--spp", "10",
                                     "--seed", "3", "--max-depth", "3"};
    if (name == "pt") args.insert(args.end(), {"--aov", "albedo,material-id"});
    else args.insert(args.end(), {"--vcm-merged", "--vcm-shrink", "pass"});  // split: the pass rule
    const nlohmann::json one = render(name + "-one", 0, args);
    const nlohmann::json five = render(name + "-five", 5, args);
    if (one.is_null() || five.is_null()) continue;
    test::expect_device_shares(five, 5, 10);
    const ImageChannels a = read_image_channels(path(name + "-five.exr"));
    const ImageChannels b = read_image_channels(path(name + "-one.exr"));
    const test::Agreement g = test::agreement(a.image, b.image);
    std::printf("%-4s five ranks against one process: relMSE %.3g, mean ratio 1 %+.3g\n", integrator,
                g.rel_mse, g.mean_ratio - 1.0);
    EXPECT_LT(g.rel_mse, 1e-8);
    EXPECT_NEAR(g.mean_ratio, 1.0, 1e-6);
    ASSERT_EQ(a.layers.size(), b.layers.size());
    for (const NamedChannel& l : b.layers) {
      SCOPED_TRACE(l.name);
      const Image* other = a.layer(l.name);
      ASSERT_NE(other, nullptr);
      if (l.name == "IndexMA") {
        EXPECT_EQ(other->rgb, l.image.rgb);
      } else {
        EXPECT_LT(test::agreement(*other, l.image).rel_mse, 1e-8);
      }
    }
  }
}

// Rank 1 is given a scene that does not exist: both ranks exit 2 with rank 1's error, and
// nothing is written.
TEST_F(Mpi, ARankThatFailsStopsEveryRankWithItsError) {
  const std::vector<std::string> tail = {"-q", "--device", "pocl", "--spp", "4", "--resolution",
                                         "16x16", "-o", path("never.exr")};
  std::vector<std::string> good = {kCornell}, bad = {path("missing.gltf")};
  good.insert(good.end(), tail.begin(), tail.end());
  bad.insert(bad.end(), tail.begin(), tail.end());
  const test::RunResult r = mpirun({good, bad});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("rank 1: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("missing.gltf"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("never.exr")));

  // What cannot be split is refused by every rank alike.
  std::vector<std::string> sppm = good;
  sppm.insert(sppm.end(), {"--integrator", "sppm"});
  const test::RunResult s = mpirun({sppm, sppm});
  EXPECT_EQ(s.exit_code, 1) << s.err;
  EXPECT_NE(s.err.find("renders on one device"), std::string::npos) << s.err;
  EXPECT_FALSE(fs::exists(path("never.exr")));
}

// --device rank: each rank takes the device numbered by its rank on the node (two PoCL devices
// here); without a launcher it is a usage error.
TEST_F(Mpi, DeviceRankGivesEachRankItsOwnDevice) {
  const std::vector<std::string> args = {kCornell, "-q", "--device", "rank", "--resolution", "16x16",
                                         "--spp", "8", "-o", path("r.exr"), "--stats=" + path("r.json")};
  const test::RunResult r = mpirun({args, args}, {{"POCL_DEVICES", "pthread pthread"}});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json stats = nlohmann::json::parse(test::read_file(path("r.json")));
  ASSERT_EQ(stats["devices"].size(), 2u);
  EXPECT_EQ(stats["devices"][0]["device"].get<std::string>().rfind("rank 0: 0:0 ", 0), 0u)
      << stats["devices"].dump();
  EXPECT_EQ(stats["devices"][1]["device"].get<std::string>().rfind("rank 1: 0:1 ", 0), 0u)
      << stats["devices"].dump();

  const test::RunResult alone = test::run_program(CLPT_BINARY, args);
  EXPECT_EQ(alone.exit_code, 1) << alone.err;
  EXPECT_NE(alone.err.find("no MPI launcher"), std::string::npos) << alone.err;
}

// --time: rank 0's clock ends the render for both, which both took samples in; Ctrl-C to
// mpirun (which passes SIGTERM to every rank): the ranks finish the pass, rank 0 writes what
// was rendered.
TEST_F(Mpi, TimeLimitAndCtrlCEndEveryRank) {
  const std::vector<std::string> timed = {kCornell, "--device", "pocl", "--resolution", "16x16",
                                          "--time", "1.5", "-o", path("t.exr"),
                                          "--stats=" + path("t.json")};
  const test::RunResult t = mpirun({timed, timed});
  ASSERT_EQ(t.exit_code, 0) << t.err;
  const nlohmann::json stats = nlohmann::json::parse(test::read_file(path("t.json")));
  EXPECT_GE(stats["render_seconds"].get<double>(), 1.5);
  EXPECT_LT(stats["render_seconds"].get<double>(), 5.0);
  test::expect_device_shares(stats, 2, read_image_channels(path("t.exr")).int_attribute("clpt:spp"));

  const std::vector<std::string> long_run = {kCornell, "--device", "pocl", "--resolution", "16x16",
                                             "--spp", "100000000", "-o", path("i.exr")};
  const auto t0 = std::chrono::steady_clock::now();
  const test::RunResult i = mpirun({long_run, long_run}, {}, "rendering ");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_NE(i.exit_code, 0) << "interrupted";
  EXPECT_LT(seconds, 30.0);
  ASSERT_TRUE(fs::exists(path("i.exr"))) << i.err;
  const int spp = read_image_channels(path("i.exr")).int_attribute("clpt:spp");
  EXPECT_GT(spp, 0);
  EXPECT_LT(spp, 100000000);
}

// A checkpoint two ranks wrote holds the first N sample indices, summed: resumed by two ranks
// to 2N, the image equals one process's 2N.
TEST_F(Mpi, CheckpointsOfRanksResumeToOneProcesssImage) {
  const std::vector<std::string> base = {"--resolution", "24x24", "--seed", "9", "--max-depth", "3"};
  auto with = [&](std::vector<std::string> more) {
    std::vector<std::string> a = base;
    a.insert(a.end(), more.begin(), more.end());
    return a;
  };
  render("half", 2, with({"--spp", "8", "--checkpoint", path("half.ckpt")}));
  const nlohmann::json resumed = render("resumed", 2, with({"--spp", "16", "--resume", path("half.ckpt")}));
  render("whole", 0, with({"--spp", "16"}));
  if (!resumed.is_null()) test::expect_device_shares(resumed, 2, 8);  // the 8 spp after the resume
  const test::Agreement g =
      test::agreement(read_image(path("resumed.exr")), read_image(path("whole.exr")));
  EXPECT_LT(g.rel_mse, 1e-10);
  EXPECT_NEAR(g.mean_ratio, 1.0, 1e-6);
}

}  // namespace
}  // namespace clpt::mpi_test
