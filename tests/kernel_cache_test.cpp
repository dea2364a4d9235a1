// KernelCache and BuildFailure: the on-disk program cache hits, misses when the key
// changes, survives corrupt entries, leaves PoCL to its own cache; optional options are kept where they build and dropped
// where they do not; a broken kernel reports its build log;
// and a context hands a program it has to the next Program with the same key.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "cl/device.h"
#include "cl/program.h"
#include "support/device.h"
#include "util/error.h"

namespace clpt::kernel_cache_test {
namespace {
namespace fs = std::filesystem;

class KernelCache : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("clpt-cache-test-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "src");
    ::setenv("CLPT_CACHE_DIR", (dir_ / "cache").c_str(), 1);
    // The test device is PoCL, which clpt's cache leaves to PoCL's own: these tests ask for
    // clpt's (the cache that serves GPU drivers) to test it.
    ::setenv("CLPT_CACHE_POCL", "1", 1);
    write_source("__kernel void k(__global int* x) { x[0] = 1; }\n");
  }
  void TearDown() override {
    ::unsetenv("CLPT_CACHE_DIR");
    ::unsetenv("CLPT_CACHE_POCL");
    ::unsetenv("CLPT_BUILD_OPTIONS");
    fs::remove_all(dir_);
  }
  void write_source(const std::string& text) {
    std::ofstream(dir_ / "src" / "probe.cl", std::ios::trunc) << text;
  }
  cl::KernelSources sources() const {
    cl::KernelSources s;  // disk only: the test controls the source text
    s.disk_dir = dir_ / "src";
    return s;
  }
  // A context of its own per build: the disk cache is under test, not the context's reuse.
  // What every program on the test device is built with: -cl-std=CL1.2 and the device kind's
  // own (PoCL, a CPU: the triangle lanes).
  static std::string base_options() {
    return "-cl-std=CL1.2" + cl::device_kind_options(test::device_context().device(), "");
  }
  cl::BuildInfo build(const std::string& options = "", const std::string& optional = "") {
    const cl::Context ctx(test::device_context().device());
    cl::Program p(ctx, "probe.cl", options, sources(), optional);
    EXPECT_FALSE(p.build_info().from_memory);
    cl::Kernel k(p, "k");  // the program is usable either way
    return p.build_info();
  }
  size_t entries() const {
    size_t n = 0;
    if (fs::exists(dir_ / "cache"))
      for (const auto& e : fs::directory_iterator(dir_ / "cache")) n += e.path().extension() == ".clbin";
    return n;
  }
  fs::path dir_;
};

TEST_F(KernelCache, SecondBuildHits) {
  EXPECT_FALSE(build().from_cache);
  EXPECT_EQ(entries(), 1u);
  EXPECT_TRUE(build().from_cache);
  EXPECT_EQ(entries(), 1u);
}

TEST_F(KernelCache, ChangedSourceMisses) {
  EXPECT_FALSE(build().from_cache);
  write_source("__kernel void k(__global int* x) { x[0] = 2; }\n");
  EXPECT_FALSE(build().from_cache);
  EXPECT_EQ(entries(), 2u);
  EXPECT_TRUE(build().from_cache);
}

TEST_F(KernelCache, ChangedIncludedFileMisses) {
  // The key covers the resolved source, so an edit inside an included file counts.
  std::ofstream(dir_ / "src" / "inc.h") << "#define VALUE 1\n";
  write_source("#include \"inc.h\"\n__kernel void k(__global int* x) { x[0] = VALUE; }\n");
  EXPECT_FALSE(build().from_cache);
  EXPECT_TRUE(build().from_cache);
  std::ofstream(dir_ / "src" / "inc.h", std::ios::trunc) << "#define VALUE 2\n";
  EXPECT_FALSE(build().from_cache);
}

TEST_F(KernelCache, ChangedOptionsMiss) {
  EXPECT_FALSE(build().from_cache);
  EXPECT_FALSE(build("-DCLPT_PROBE=1").from_cache);
  EXPECT_TRUE(build("-DCLPT_PROBE=1").from_cache);
}

// CLPT_BUILD_OPTIONS reaches the compiler (a macro it defines decides whether the source
// builds) and the cache key (the same source with other options is another entry).
TEST_F(KernelCache, EnvironmentOptionsReachTheBuildAndTheKey) {
  write_source("#ifndef CLPT_PROBE_ENV\n#error CLPT_PROBE_ENV is not defined\n#endif\n"
               "__kernel void k(__global int* x) { x[0] = CLPT_PROBE_ENV; }\n");
  EXPECT_THROW(build(), Error);
  ::setenv("CLPT_BUILD_OPTIONS", "-DCLPT_PROBE_ENV=3", 1);
  EXPECT_EQ(cl::build_options("-DA=1"), "-cl-std=CL1.2 -DA=1 -DCLPT_PROBE_ENV=3");
  EXPECT_FALSE(build().from_cache);
  EXPECT_TRUE(build().from_cache);
  ::setenv("CLPT_BUILD_OPTIONS", "-DCLPT_PROBE_ENV=4", 1);
  EXPECT_FALSE(build().from_cache);
  EXPECT_EQ(entries(), 2u);
  ::unsetenv("CLPT_BUILD_OPTIONS");
  EXPECT_EQ(cl::build_options(""), "-cl-std=CL1.2");
}

// On PoCL clpt writes no binary (PoCL caches its programs itself, and asking it for a binary
// costs a code generation no launch uses); CLPT_CACHE_POCL=1 turns clpt's cache on there.
TEST_F(KernelCache, PoclLeavesCachingToPocl) {
  ASSERT_TRUE(test::device_context().device().is_pocl());
  ::unsetenv("CLPT_CACHE_POCL");
  EXPECT_FALSE(cl::binary_cache_serves(test::device_context().device()));
  EXPECT_FALSE(build().from_cache);
  EXPECT_FALSE(build().from_cache);
  EXPECT_EQ(entries(), 0u);
  ::setenv("CLPT_CACHE_POCL", "0", 1);
  EXPECT_FALSE(build().from_cache);
  EXPECT_EQ(entries(), 0u);
  ::setenv("CLPT_CACHE_POCL", "1", 1);
  EXPECT_FALSE(build().from_cache);
  EXPECT_EQ(entries(), 1u);
  EXPECT_TRUE(build().from_cache);
  cl::DeviceInfo gpu;  // any other driver: clpt's cache
  gpu.platform_name = "NVIDIA CUDA";
  gpu.platform_vendor = "NVIDIA Corporation";
  ::unsetenv("CLPT_CACHE_POCL");
  EXPECT_TRUE(cl::binary_cache_serves(gpu));
}

// Optional options (a vendor's own, e.g. Intel's -cl-intel-256-GRF-per-thread): where the
// build takes them, the program is theirs (a macro they define decides what the source
// builds) with a cache entry of its own; where the build fails with them, the program is
// built without them and says which it dropped.
TEST_F(KernelCache, OptionalOptionsAreKeptWhereTheyBuild) {
  write_source("#ifndef CLPT_PROBE_OPT\n#error CLPT_PROBE_OPT is not defined\n#endif\n"
               "__kernel void k(__global int* x) { x[0] = CLPT_PROBE_OPT; }\n");
  const cl::BuildInfo first = build("", "-DCLPT_PROBE_OPT=1");
  EXPECT_FALSE(first.from_cache);
  EXPECT_EQ(first.options, base_options() + " -DCLPT_PROBE_OPT=1");
  EXPECT_EQ(first.dropped_options, "");
  EXPECT_TRUE(build("", "-DCLPT_PROBE_OPT=1").from_cache);
  EXPECT_EQ(entries(), 1u);
}

TEST_F(KernelCache, OptionalOptionsTheBuildRefusesAreDropped) {
  // The source cannot build with the option's macro: the build with it fails, without it passes.
  write_source("#ifdef CLPT_PROBE_OPT\n#error refused\n#endif\n"
               "__kernel void k(__global int* x) { x[0] = 1; }\n");
  const cl::BuildInfo first = build("", "-DCLPT_PROBE_OPT=1");
  EXPECT_EQ(first.options, base_options());
  EXPECT_EQ(first.dropped_options, "-DCLPT_PROBE_OPT=1");
  EXPECT_EQ(entries(), 1u);  // the build without them only
  const cl::BuildInfo again = build("", "-DCLPT_PROBE_OPT=1");
  EXPECT_TRUE(again.from_cache);
  EXPECT_EQ(again.dropped_options, "-DCLPT_PROBE_OPT=1");
  // An option the compiler does not know at all is dropped the same way.
  const cl::BuildInfo unknown = build("", "-cl-clpt-no-such-option");
  EXPECT_EQ(unknown.dropped_options, "-cl-clpt-no-such-option");
  EXPECT_TRUE(unknown.from_cache);
  // A source that fails without them too still fails, with its own log.
  write_source("__kernel void k(__global int* x) { x[0] = undefined_name; }\n");
  try {
    build("", "-DCLPT_PROBE_OPT=1");
    ADD_FAILURE() << "a broken source built";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::Device);
    EXPECT_NE(std::string(e.what()).find("undefined_name"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("with options '" + base_options() + "'"), std::string::npos) << e.what();
  }
}

TEST_F(KernelCache, CorruptEntryIsRebuilt) {
  EXPECT_FALSE(build().from_cache);
  ASSERT_EQ(entries(), 1u);
  for (const auto& e : fs::directory_iterator(dir_ / "cache")) {
    const auto size = fs::file_size(e.path());
    std::fstream f(e.path(), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size / 2));
    f.write("garbage!", 8);
  }
  EXPECT_FALSE(build().from_cache);  // rejected, rebuilt, rewritten
  EXPECT_TRUE(build().from_cache);
  // A truncated entry too.
  for (const auto& e : fs::directory_iterator(dir_ / "cache")) fs::resize_file(e.path(), 20);
  EXPECT_FALSE(build().from_cache);
  EXPECT_TRUE(build().from_cache);
}

// One context: the second Program with the same key is the first one's cl_program, whatever
// the disk cache holds (here: nothing that could be read); another key or another context
// does not share it, and the program outlives the Program objects that asked for it.
TEST_F(KernelCache, ContextReusesItsPrograms) {
  ::setenv("CLPT_CACHE_DIR", "/proc/clpt-cannot-write-here", 1);
  const cl::Context ctx(test::device_context().device());
  cl_program first_handle = nullptr;
  {
    cl::Program first(ctx, "probe.cl", "", sources());
    EXPECT_FALSE(first.build_info().from_cache);
    EXPECT_FALSE(first.build_info().from_memory);
    first_handle = first.get();
  }
  cl::Program again(ctx, "probe.cl", "", sources());
  EXPECT_TRUE(again.build_info().from_memory);
  EXPECT_FALSE(again.build_info().from_cache);
  EXPECT_EQ(again.get(), first_handle);
  cl::Kernel k(again, "k");  // usable after the first Program let go of it

  cl::Program other_options(ctx, "probe.cl", "-DCLPT_PROBE=1", sources());
  EXPECT_FALSE(other_options.build_info().from_memory);
  EXPECT_NE(other_options.get(), first_handle);
  write_source("__kernel void k(__global int* x) { x[0] = 5; }\n");
  cl::Program other_source(ctx, "probe.cl", "", sources());
  EXPECT_FALSE(other_source.build_info().from_memory);

  const cl::Context other_ctx(test::device_context().device());
  cl::Program elsewhere(other_ctx, "probe.cl", "", sources());
  EXPECT_FALSE(elsewhere.build_info().from_memory);
}

TEST_F(KernelCache, UnwritableCacheIsNotFatal) {
  ::setenv("CLPT_CACHE_DIR", "/proc/clpt-cannot-write-here", 1);
  EXPECT_FALSE(build().from_cache);
  EXPECT_FALSE(build().from_cache);
}

TEST_F(KernelCache, BuildFailureCarriesTheLog) {
  write_source("__kernel void k(__global int* x) { x[0] = undefined_identifier_xyz; }\n");
  try {
    build();
    FAIL() << "a broken kernel must not build";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::Device);
    const std::string msg = e.what();
    EXPECT_NE(msg.find("probe.cl"), std::string::npos) << msg;
    EXPECT_NE(msg.find("undefined_identifier_xyz"), std::string::npos) << msg;
  }
  EXPECT_EQ(entries(), 0u);
}

TEST(KernelSource, IncludesResolvedWithLineMarkers) {
  const std::string src = cl::resolve_kernel_source("integrators/pt.cl", cl::KernelSources::core());
  EXPECT_NE(src.find("#line 1 \"integrators/pt.cl\""), std::string::npos);
  EXPECT_NE(src.find("#line 1 \"shared/scene_types.h\""), std::string::npos);
  EXPECT_EQ(src.find("#include \"shared/scene_types.h\""), std::string::npos);
  // Each file once, even when included from several places.
  const auto first = src.find("#line 1 \"shared/compat.h\"");
  ASSERT_NE(first, std::string::npos);
  EXPECT_EQ(src.find("#line 1 \"shared/compat.h\"", first + 1), std::string::npos);
}

TEST(KernelSource, MissingIncludeIsAClearError) {
  cl::KernelSources s;
  const fs::path dir = fs::temp_directory_path() / ("clpt-inc-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "a.cl") << "\n#include \"nope.h\"\n";
  s.disk_dir = dir;
  try {
    cl::resolve_kernel_source("a.cl", s);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a.cl:2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("nope.h"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace clpt::kernel_cache_test
