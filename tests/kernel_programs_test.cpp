// The list of kernel programs (host/cl/programs.h) and `clpt --dump-kernels`, which the
// vendor compile checks (scripts/kernel_compile_check.py, ctest label portability) read:
//   KernelPrograms.EveryKernelFileIsAProgram   every file under kernels/ that defines a
//       __kernel is some program's entry file, and every entry file exists: a new program
//       left out of the list would escape the vendors' compilers
//   KernelPrograms.EveryProgramBuilds    each program of the list builds on the test device (PoCL) with
//       its options, and each of its __kernel functions can be created
//   KernelPrograms.IntelOptionsGoToIntelGpusOnly   the megakernels' Intel register-file option
//       reaches Intel's GPUs alone
//   KernelPrograms.TriangleLanesGoToCpuDevicesOnly  the float4 triangle test's define reaches
//       CPU devices alone
//   KernelPrograms.DumpIsWhatADeviceIsGiven     the dump's files are the resolved sources and
//       programs.tsv the build options (and Intel GPUs' extra ones), byte for byte; it refuses a file or a folder of
//       other things, and rewrites an earlier dump
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <unistd.h>

#include "cl/device.h"
#include "cl/programs.h"
#include "support/device.h"
#include "util/error.h"

namespace clpt::kernel_programs_test {
namespace {
namespace fs = std::filesystem;

std::string read_file(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// Names of the __kernel functions defined in `source` (a line starting with __kernel void).
std::vector<std::string> kernel_names(const std::string& source) {
  static const std::regex def(R"(^\s*__kernel\s+void\s+([A-Za-z_][A-Za-z0-9_]*)\s*\()");
  std::vector<std::string> names;
  std::istringstream in(source);
  std::string line;
  std::smatch m;
  while (std::getline(in, line))
    if (std::regex_search(line, m, def)) names.push_back(m[1]);
  return names;
}

TEST(KernelPrograms, EveryKernelFileIsAProgram) {
  const fs::path kernels = fs::path(CLPT_SOURCE_DIR) / "kernels";
  std::set<std::string> entries, names;
  for (const cl::ProgramSpec& spec : programs::all()) {
    EXPECT_TRUE(names.insert(spec.name).second) << "two programs named " << spec.name;
    EXPECT_TRUE(fs::is_regular_file(kernels / spec.entry_file)) << spec.entry_file;
    entries.insert(spec.entry_file);
  }
  size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(kernels)) {
    if (e.path().extension() != ".cl" || kernel_names(read_file(e.path())).empty()) continue;
    ++files;
    const std::string rel = fs::relative(e.path(), kernels).generic_string();
    EXPECT_TRUE(entries.count(rel)) << rel << " defines a __kernel but is no program of "
                                    << "host/cl/programs.h";
  }
  EXPECT_GE(files, 11u);  // the scan found the integrators (a wrong root finds none)
}

TEST(KernelPrograms, EveryProgramBuilds) {
  for (const cl::ProgramSpec& spec : programs::all()) {
    SCOPED_TRACE(spec.name);
    const cl::Program program(test::device_context(), spec);
    // PoCL is no Intel GPU: the spec's own options (those of the dump's third column) and a
    // CPU device's.
    const std::string options = cl::build_options(spec.options);
    EXPECT_EQ(program.build_info().options,
              options + cl::device_kind_options(test::device_context().device(), options));
    const std::vector<std::string> kernels =
        kernel_names(cl::resolve_kernel_source(spec.entry_file, cl::KernelSources::core()));
    EXPECT_FALSE(kernels.empty());
    for (const std::string& k : kernels) EXPECT_NO_THROW(cl::Kernel(program, k.c_str())) << k;
  }
}

// Which devices get ProgramSpec::intel_gpu_options: GPUs of Intel's own platform, whose
// vendor string is "Intel(R) Corporation"; not its CPU runtime, not another platform's GPU.
TEST(KernelPrograms, IntelOptionsGoToIntelGpusOnly) {
  cl::DeviceInfo d;
  d.type = CL_DEVICE_TYPE_GPU;
  d.platform_vendor = "Intel(R) Corporation";
  EXPECT_TRUE(d.is_intel_gpu());
  d.type = CL_DEVICE_TYPE_CPU;
  EXPECT_FALSE(d.is_intel_gpu());
  d.type = CL_DEVICE_TYPE_GPU;
  for (const char* vendor : {"NVIDIA Corporation", "Advanced Micro Devices, Inc.", "The pocl project", "Mesa/X.org"}) {
    d.platform_vendor = vendor;
    EXPECT_FALSE(d.is_intel_gpu()) << vendor;
  }
  EXPECT_FALSE(test::device_context().device().is_intel_gpu());
  // The megakernels ask for Intel's large register file; the small programs do not.
  for (const cl::ProgramSpec& spec : programs::all()) {
    const std::string name = spec.name;
    const bool small = name == "ao" || name == "aov" || name == "raybench";
    EXPECT_EQ(std::string(spec.intel_gpu_options), small ? "" : "-cl-intel-256-GRF-per-thread") << name;
  }
}

// CPU devices test a leaf's triangles in float4 lanes, GPUs one at a time (kernels/bvh/
// intersect.cl says why); options that name the macro already are left to decide.
TEST(KernelPrograms, TriangleLanesGoToCpuDevicesOnly) {
  cl::DeviceInfo d;
  d.type = CL_DEVICE_TYPE_CPU;
  EXPECT_EQ(cl::device_kind_options(d, "-cl-std=CL1.2"), " -DCLPT_TRIANGLE_LANES=4");
  EXPECT_EQ(cl::device_kind_options(d, "-cl-std=CL1.2 -DCLPT_TRIANGLE_LANES=1"), "");
  for (const cl_device_type type : {cl_device_type(CL_DEVICE_TYPE_GPU), cl_device_type(CL_DEVICE_TYPE_ACCELERATOR)}) {
    d.type = type;
    EXPECT_EQ(cl::device_kind_options(d, "-cl-std=CL1.2"), "") << type;
  }
  // PoCL, the test device, is a CPU device: its programs are built with the lanes, and with
  // the prefetch hints, which only PoCL's devices get (Oclgrind's interpreter has no prefetch).
  const cl::Program p(test::device_context(), programs::kRaybench);
  EXPECT_NE(p.build_info().options.find("-DCLPT_TRIANGLE_LANES=4"), std::string::npos)
      << p.build_info().options;
  EXPECT_NE(p.build_info().options.find("-DCLPT_PREFETCH_HINTS=1"), std::string::npos)
      << p.build_info().options;
  d.type = CL_DEVICE_TYPE_CPU;
  d.platform_name = "Oclgrind";
  EXPECT_EQ(cl::device_kind_options(d, "-cl-std=CL1.2"), " -DCLPT_TRIANGLE_LANES=4");
  d.platform_name = "Portable Computing Language";
  EXPECT_EQ(cl::device_kind_options(d, "-cl-std=CL1.2"),
            " -DCLPT_TRIANGLE_LANES=4 -DCLPT_PREFETCH_HINTS=1");
}

// The scene's lanes buffer (render/scene_buffers) goes where the programs read it: CPU
// devices, or whichever CLPT_BUILD_OPTIONS builds with the lanes; GPUs get a placeholder.
TEST(KernelPrograms, TriangleLanesBufferFollowsTheBuild) {
  const char* saved = std::getenv("CLPT_BUILD_OPTIONS");
  const std::string before = saved ? saved : "";
  cl::DeviceInfo cpu, gpu;
  cpu.type = CL_DEVICE_TYPE_CPU;
  gpu.type = CL_DEVICE_TYPE_GPU;
  ::unsetenv("CLPT_BUILD_OPTIONS");
  EXPECT_TRUE(cl::triangle_lanes(cpu));
  EXPECT_FALSE(cl::triangle_lanes(gpu));
  ::setenv("CLPT_BUILD_OPTIONS", "-DCLPT_TRIANGLE_LANES=4", 1);
  EXPECT_TRUE(cl::triangle_lanes(gpu));
  ::setenv("CLPT_BUILD_OPTIONS", "-DCLPT_TRIANGLE_LANES=1", 1);
  EXPECT_FALSE(cl::triangle_lanes(cpu));
  if (saved)
    ::setenv("CLPT_BUILD_OPTIONS", before.c_str(), 1);
  else
    ::unsetenv("CLPT_BUILD_OPTIONS");
}

class KernelDump : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("clpt-dump-test-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(KernelDump, DumpIsWhatADeviceIsGiven) {
  const fs::path out = dir_ / "dump";
  ASSERT_EQ(programs::dump(out), programs::all().size());
  std::string expected_table = "# name\tentry file\tbuild options\tIntel GPU options\n";
  for (const cl::ProgramSpec& spec : programs::all()) {
    EXPECT_EQ(read_file(out / (std::string(spec.name) + ".cl")),
              cl::resolve_kernel_source(spec.entry_file, cl::KernelSources::core()))
        << spec.name;
    expected_table += std::string(spec.name) + '\t' + spec.entry_file + '\t' +
                      cl::build_options(spec.options) + '\t' + spec.intel_gpu_options + '\n';
  }
  EXPECT_EQ(read_file(out / "programs.tsv"), expected_table);
  EXPECT_NE(expected_table.find("mmlt\tintegrators/mlt.cl\t-cl-std=CL1.2 -DCLPT_MLT_MULTIPLEXED=1\t"
                                 "-cl-intel-256-GRF-per-thread\n"),
            std::string::npos);
  EXPECT_NE(expected_table.find("ao\tintegrators/ao.cl\t-cl-std=CL1.2\t\n"), std::string::npos);

  // An earlier dump is rewritten; an empty folder is used.
  std::ofstream(out / "pt.cl", std::ios::trunc) << "stale";
  EXPECT_EQ(programs::dump(out), programs::all().size());
  EXPECT_NE(read_file(out / "pt.cl"), "stale");
  fs::create_directories(dir_ / "empty");
  EXPECT_EQ(programs::dump(dir_ / "empty"), programs::all().size());
}

TEST_F(KernelDump, RefusesAFileAndAFolderOfOtherThings) {
  fs::create_directories(dir_ / "other");
  std::ofstream(dir_ / "other" / "notes.txt") << "mine";
  std::ofstream(dir_ / "file") << "mine";
  for (const fs::path& p : {dir_ / "other", dir_ / "file"}) {
    try {
      programs::dump(p);
      ADD_FAILURE() << "dumped into " << p;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ExitCode::Usage);
      EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(read_file(dir_ / "other" / "notes.txt"), "mine");
  EXPECT_EQ(read_file(dir_ / "file"), "mine");
  EXPECT_FALSE(fs::exists(dir_ / "other" / "pt.cl"));
}

}  // namespace
}  // namespace clpt::kernel_programs_test
