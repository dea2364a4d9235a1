// LoadLimits (host/scene/load_limits.*): --limit NAME=VALUE parsing, and the limits in effect
// in the loader:
//   LoadLimits.ParsesNamesValuesAndSuffixes  k/M/G suffixes, every name, clear usage errors;
//   LoadLimits.RaisedLimitLetsALargeSceneLoad / LoweredLimitRefusesIt  a limit passed to
//       load_gltf is the one applied;
//   LoadLimits.MemoryBudgetRefusesATinyFileThatNeedsGigabytes  the 604-byte file of
//       docs/robustness.md (a 2^24-vertex accessor without bufferView, used by 4 nodes)
//       is refused with the memory estimate instead of being loaded.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <unistd.h>
#include <string>

#include "scene/gltf_loader.h"
#include "scene/load_limits.h"
#include "util/error.h"

namespace clpt::load_limits_test {
namespace {

namespace fs = std::filesystem;

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return std::to_string(int(e.code())) + ": " + e.what();
  }
  return "no error";
}

TEST(LoadLimits, ParsesNamesValuesAndSuffixes) {
  LoadLimits l;
  l.set("triangles=1k");
  EXPECT_EQ(l.triangles, 1024u);
  l.set("vertices=3M");
  EXPECT_EQ(l.vertices, 3u << 20);
  l.set("memory=64G");
  EXPECT_EQ(l.memory_bytes, uint64_t{64} << 30);
  l.set("json-depth=12");
  EXPECT_EQ(l.json_depth, 12u);
  EXPECT_EQ(l.memory_budget(), uint64_t{64} << 30);
  // Every name describe() lists is accepted by set().
  std::istringstream names(l.describe());
  for (std::string line; std::getline(names, line);) EXPECT_NO_THROW(l.set(line)) << line;

  for (const char* bad : {"triangles", "triangles=", "triangles=-1", "triangles=1.5", "triangles=1T",
                          "triangles=99999999999999999999", "triangles=20000000000000G", "bogus=1"}) {
    const std::string m = message_of([&] { LoadLimits x; x.set(bad); });
    EXPECT_EQ(m.rfind("1: ", 0), 0u) << bad << " -> " << m;  // ExitCode::Usage
    EXPECT_NE(m.find(bad), std::string::npos) << "the message must quote the argument: " << m;
  }
  EXPECT_NE(message_of([] { LoadLimits x; x.set("bogus=1"); }).find("triangles"), std::string::npos)
      << "an unknown name lists the known ones";
  LoadLimits d;
  EXPECT_GT(d.memory_budget(), uint64_t{1} << 28) << "default: 80 % of physical memory";
}

const fs::path kCornell = fs::path(CLPT_SOURCE_DIR) / "scenes/cornell_box.gltf";

TEST(LoadLimits, LoweredLimitRefusesAndRaisedLimitLoads) {
  LoadOptions o;
  o.limits.triangles = 10;
  const std::string m = message_of([&] { load_gltf(kCornell, o); });
  EXPECT_EQ(m.rfind("2: ", 0), 0u) << m;
  EXPECT_NE(m.find("--limit triangles"), std::string::npos) << m;
  o.limits.triangles = 1000;
  EXPECT_NO_THROW(load_gltf(kCornell, o));
}

// issue 23, class 5: json-depth and node-depth raised past what the stack holds crashed the
// loader (SIGSEGV at about 15 500 JSON levels and 12 500 node levels in 8 MiB). set() refuses
// a depth beyond max_recursion_depth(), and at that depth both a node chain and nested JSON
// load (the cap is safe, not only refused beyond).
TEST(LoadLimits, DepthsTheStackCannotServeAreRefusedAndTheCapLoads) {
  const uint64_t cap = LoadLimits::max_recursion_depth();
  ASSERT_GE(cap, 1024u) << "this test wants a stack of at least 2 MiB";
  for (const char* name : {"node-depth", "json-depth"}) {
    const std::string over = std::string(name) + "=" + std::to_string(cap + 1);
    const std::string m = message_of([&] { LoadLimits x; x.set(over); });
    EXPECT_EQ(m.rfind("1: ", 0), 0u) << m;
    EXPECT_NE(m.find("stack"), std::string::npos) << m;
    LoadLimits ok;
    EXPECT_NO_THROW(ok.set(std::string(name) + "=" + std::to_string(cap)));
  }
  // A chain of cap - 1 nodes under the root, and cap - 8 levels of nested JSON in "extras".
  const fs::path dir = fs::temp_directory_path() / ("clpt_depth_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string head =
      R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],)"
      R"("buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,)"
      R"(AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],)"
      R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
      R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",)"
      R"("min":[0,0,0],"max":[1,1,0]}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)";
  const size_t levels = size_t(cap) - 8;
  std::string nodes = head + "\"nodes\":[";
  for (size_t i = 0; i + 1 < levels; ++i) nodes += "{\"children\":[" + std::to_string(i + 1) + "]},";
  nodes += "{\"mesh\":0}]}";
  std::ofstream(dir / "chain.gltf") << nodes;
  std::ofstream(dir / "nested.gltf") << head << "\"nodes\":[{\"mesh\":0}],\"extras\":"
                                     << std::string(levels, '[') << std::string(levels, ']') << "}";
  LoadOptions o;
  o.limits.set("node-depth=" + std::to_string(cap));
  o.limits.set("json-depth=" + std::to_string(cap));
  EXPECT_EQ(load_gltf(dir / "chain.gltf", o).triangles.size(), 1u);
  EXPECT_EQ(load_gltf(dir / "nested.gltf", o).triangles.size(), 1u);
  fs::remove_all(dir);
}

TEST(LoadLimits, MemoryBudgetRefusesATinyFileThatNeedsGigabytes) {
  const fs::path dir = fs::temp_directory_path() / ("clpt-limits-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "zeros.gltf";
  std::ofstream(file) << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1,2,3]}],
    "nodes":[{"mesh":0},{"mesh":0},{"mesh":0},{"mesh":0}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
    "accessors":[{"componentType":5126,"count":16777216,"type":"VEC3","min":[0,0,0],"max":[0,0,0]}]})";
  LoadOptions o;
  o.limits.memory_bytes = uint64_t{1} << 30;  // 1 GiB: 4 x 2^24 vertices need about 10 GiB
  o.limits.zero_accessor_count = uint64_t{1} << 24;  // raised: the memory budget is tested here
  o.limits.memory_per_file_byte = uint64_t{1} << 40;  // the absolute budget binds, not this one
  const std::string m = message_of([&] { load_gltf(file, o); });
  EXPECT_EQ(m.rfind("2: ", 0), 0u) << m;
  EXPECT_NE(m.find("needs about"), std::string::npos) << m;
  EXPECT_NE(m.find("--limit memory=BYTES"), std::string::npos) << m;

  // With the default limits, the zeros alone are refused (issue 23, class 4), and with them
  // raised, the budget per byte of the file binds long before the machine's memory does.
  const std::string zeros = message_of([&] { load_gltf(file, LoadOptions{}); });
  EXPECT_NE(zeros.find("no bufferView (all zeros) and count 16777216"), std::string::npos) << zeros;
  EXPECT_NE(zeros.find("--limit zero-accessor-count=N"), std::string::npos) << zeros;
  LoadOptions raised;
  raised.limits.zero_accessor_count = uint64_t{1} << 24;
  const std::string per_byte = message_of([&] { load_gltf(file, raised); });
  EXPECT_NE(per_byte.find("needs about"), std::string::npos) << per_byte;
  EXPECT_NE(per_byte.find("more than the budget of 256.0 MiB"), std::string::npos) << per_byte;
  EXPECT_NE(per_byte.find("--limit memory-per-file-byte=N"), std::string::npos) << per_byte;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace clpt::load_limits_test
