// libFuzzer target for clpt::load_gltf (.gltf and .glb). Built with -DCLPT_FUZZ=ON and clang;
// run through scripts/fuzz.sh. See docs/robustness.md.
//
// Each input is written to a private temporary folder and loaded from there, as clpt would
// load a user's file:
//   * The input may hold a second file after the separator kBinSeparator (below): the part
//     before it is the scene, the part after it is written beside it as `scene.bin`. Without
//     the separator the whole input is also written as `scene.bin`. Either way a buffer or image
//     URI `scene.bin` resolves, so external buffers are fuzzed too (scripts/fuzz.sh rewrites the
//     seeds' external URIs to `scene.bin` and appends their .bin after the separator).
//   * The scene is written as `scene.glb` when it starts with the GLB magic `glTF`, else as
//     `scene.gltf` (the loader itself decides by the first bytes, not the name).
//
// The loader's contract (host/scene/gltf_loader.h): on any input it returns a Scene or throws
// clpt::Error(ExitCode::BadInput). So only clpt::Error is caught here; any other exception,
// a crash, a hang (libFuzzer -timeout) or a sanitizer report is a finding. A returned Scene is
// also checked for the invariants the renderer relies on (indices in range, finite positions,
// matching attribute arrays, at least one material).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "scene/gltf_loader.h"
#include "fuzz/harness.h"
#include "util/error.h"
#include "util/log.h"

namespace {

namespace fs = std::filesystem;

constexpr char kBinSeparator[] = "\n#clpt-fuzz-bin#\n";

using clpt::fuzz::write_file;

[[noreturn]] void finding(const char* what) { clpt::fuzz::finding("gltf_fuzzer", what); }

void check_scene(const clpt::Scene& s) {
  const size_t n = s.positions.size();
  if (s.normals.size() != n || s.uvs.size() != n) finding("attribute arrays differ in length");
  if (s.triangle_materials.size() != s.triangles.size()) finding("one material per triangle broken");
  if (s.triangles.empty()) finding("a scene without triangles was returned");
  if (s.materials.empty()) finding("a scene without materials was returned");
  for (const auto& t : s.triangles)
    if (t.x >= n || t.y >= n || t.z >= n) finding("triangle index out of range");
  for (uint32_t m : s.triangle_materials)
    if (m >= s.materials.size()) finding("material index out of range");
  for (const auto& p : s.positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      finding("non-finite position in a returned scene");
  for (const auto& v : s.normals)
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      finding("non-finite normal in a returned scene");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  clpt::log::set_level(clpt::log::Level::Quiet);  // the loader's warnings would flood stderr
  clpt::fuzz::make_scratch_dir("gltf-fuzz");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const uint8_t* sep = nullptr;
  const size_t sep_len = sizeof(kBinSeparator) - 1;
  if (size >= sep_len)
    sep = static_cast<const uint8_t*>(::memmem(data, size, kBinSeparator, sep_len));
  const size_t scene_size = sep ? size_t(sep - data) : size;
  const uint8_t* bin = sep ? sep + sep_len : data;
  const size_t bin_size = sep ? size - scene_size - sep_len : size;

  const bool glb = scene_size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const fs::path scene = clpt::fuzz::scratch_dir() / (glb ? "scene.glb" : "scene.gltf");
  std::error_code ec;
  fs::remove(clpt::fuzz::scratch_dir() / (glb ? "scene.gltf" : "scene.glb"), ec);
  write_file(scene, data, scene_size);
  write_file(clpt::fuzz::scratch_dir() / "scene.bin", bin, bin_size);

  try {
    // The memory budget well under libFuzzer's -rss_limit_mb=2048 (ASan doubles allocations),
    // so an input that asks for too much is refused by the loader, as a user's would be.
    clpt::LoadOptions options;
    options.limits.memory_bytes = uint64_t{256} << 20;
    const clpt::Scene s = clpt::load_gltf(scene, options);
    check_scene(s);
  } catch (const clpt::Error& e) {
    if (e.code() != clpt::ExitCode::BadInput) finding("clpt::Error with an exit code other than BadInput");
    if (std::strchr(e.what(), '\n')) finding("an error message spans several lines");
    if (!std::strstr(e.what(), scene.c_str())) finding("an error message does not name the file");
  }
  return 0;
}
