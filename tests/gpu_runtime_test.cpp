// What a GPU needs of the host that a CPU device never shows (issue 19):
//   PassSchedule.SlowDeviceStaysWithinThePassTime   on a simulated device where a sample per
//       pixel costs from 1 us to 50 ms, every pass after the first fits the time aimed at
//       (0.03 s, the GPU default) unless it is the single sample no pass can go below; passes
//       grow at most 2x and settle at the largest count that fits
//   PassSchedule.FixedScheduleDoublesToItsCap       Metropolis' clock-free schedule
//   DeviceErrors.ResourceErrorsNameTheKernelAndTheBuffers  a lack of memory or resources
//       reported at a blocking call names the last kernel launched and the buffers alive
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "cl/buffer.h"
#include "cl/program.h"
#include "render/pass_schedule.h"
#include "support/device.h"
#include "util/error.h"

namespace clpt::gpu_runtime_test {
namespace {

TEST(PassSchedule, SlowDeviceStaysWithinThePassTime) {
  PassSchedule s;
  s.pass_seconds = 0.03;
  for (const double cost : {1e-6, 1e-4, 1e-3, 0.007, 0.01, 0.029, 0.031, 0.05}) {
    SCOPED_TRACE(cost);
    const uint64_t fits = std::max<uint64_t>(1, uint64_t(s.pass_seconds / cost));
    uint64_t n = 1;
    for (int pass = 0; pass < 60; ++pass) {
      const double seconds = double(n) * cost;  // the device's time for this pass
      if (pass > 0 && n > 1) {
        EXPECT_LE(seconds, s.pass_seconds * (1 + 1e-9)) << "pass " << pass;
      }
      const uint64_t next = next_pass_samples(s, n, n, seconds);
      EXPECT_GE(next, 1u);
      EXPECT_LE(next, 2 * n);
      n = next;
    }
    // Settled: the largest count that fits (rounding of s / cost may leave it one short).
    EXPECT_LE(n, fits);
    EXPECT_GE(n + 1, fits);
  }
  // A clock that read 0 (a pass faster than its resolution) doubles.
  EXPECT_EQ(next_pass_samples(s, 8, 8, 0.0), 16u);
  // The last pass of a render ran fewer than planned: the speed is per sample run.
  EXPECT_EQ(next_pass_samples(s, 64, 2, 0.02), 3u);
}

// Several devices' shares (render/pass_schedule.h): unchanged below what is left; above it,
// in proportion and adding up to it exactly, the first device always working.
TEST(PassSchedule, SharesAddUpToWhatIsLeft) {
  using V = std::vector<uint64_t>;
  EXPECT_EQ(share_samples({3, 5}, 100), (V{3, 5}));
  EXPECT_EQ(share_samples({3, 5}, 0), (V{3, 5}));  // no target
  EXPECT_EQ(share_samples({30, 10}, 8), (V{6, 2}));
  EXPECT_EQ(share_samples({1, 1, 1}, 1), (V{1, 0, 0}));
  EXPECT_EQ(share_samples({1, 1, 1}, 2), (V{1, 1, 0}));
  EXPECT_EQ(share_samples({1, 100}, 10), (V{1, 9}));  // floor(0.099) = 0, then the remainder
  const V big = share_samples({uint64_t(1) << 33, uint64_t(1) << 33}, (uint64_t(1) << 32) + 1);
  EXPECT_EQ(big[0] + big[1], (uint64_t(1) << 32) + 1);
  EXPECT_GE(big[0], big[1]);
}

TEST(PassSchedule, FixedScheduleDoublesToItsCap) {
  PassSchedule s;
  s.by_clock = false;
  s.fixed_cap = 40;
  uint64_t planned = 1;
  std::vector<uint64_t> seen;
  for (int pass = 0; pass < 8; ++pass) {
    seen.push_back(planned);
    planned = next_pass_samples(s, planned, planned, 100.0 /* slow: ignored */);
  }
  EXPECT_EQ(seen, (std::vector<uint64_t>{1, 2, 4, 8, 16, 32, 40, 40}));
}

TEST(DeviceErrors, ResourceErrorsNameTheKernelAndTheBuffers) {
  cl::Context& ctx = test::device_context();
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("clpt-device-errors-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "tiny.cl") << "__kernel void tiny_kernel(__global int* x) { x[0] = 1; }\n";
  cl::KernelSources sources;
  sources.disk_dir = dir;
  const cl::Program program(ctx, "tiny.cl", "", sources);
  cl::Kernel kernel(program, "tiny_kernel");
  cl::Buffer alpha(ctx, 3u << 20, CL_MEM_READ_WRITE, nullptr, "alpha buffer");
  cl::Buffer beta(ctx, 1u << 20, CL_MEM_READ_WRITE, nullptr, "beta buffer");
  {
    cl::Buffer gone(ctx, 5u << 20, CL_MEM_READ_WRITE, nullptr, "gone buffer");
  }
  kernel.arg(0, alpha);
  kernel.launch(ctx, 1);
  ctx.finish();
  for (const cl_int code : {CL_OUT_OF_RESOURCES, CL_MEM_OBJECT_ALLOCATION_FAILURE}) {
    try {
      ctx.check(code, "clFinish");
      ADD_FAILURE() << "no error thrown";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_EQ(e.code(), ExitCode::Device);
      for (const char* part : {"clFinish", "tiny_kernel", "alpha buffer 3 MiB", "beta buffer 1 MiB",
                               "device buffers: 4 MiB in"})
        EXPECT_NE(m.find(part), std::string::npos) << part << " not in: " << m;
      EXPECT_EQ(m.find("gone buffer"), std::string::npos) << m;  // released buffers are forgotten
    }
  }
  EXPECT_NO_THROW(ctx.check(CL_SUCCESS, "nothing"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace clpt::gpu_runtime_test
