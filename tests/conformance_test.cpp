// Conformance: every glTF file in ../shared/scenes and ../shared/scenes-extensions either renders (pt and ao, tiny size)
// with no NaN/Inf sample, or fails with a clear clpt::Error naming the file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/device.h"
#include "util/error.h"

namespace clpt::conformance_test {
namespace {
namespace fs = std::filesystem;

// Renders every .gltf/.glb under root (or checks its clear refusal); returns the counts.
void render_or_refuse_all(const fs::path& root, size_t* rendered, size_t* refused) {
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".gltf" && ext != ".glb") continue;
    SCOPED_TRACE(entry.path().string());
    Scene scene;
    try {
      scene = load_gltf(entry.path());
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ExitCode::BadInput);
      EXPECT_NE(std::string(e.what()).find(entry.path().filename().string()), std::string::npos)
          << e.what();
      ++*refused;
      continue;
    }
    for (const char* integrator : {"pt", "ao"}) {
      RenderSettings s;
      s.width = 16;
      s.height = 12;
      s.spp = 2;
      s.integrator = integrator;
      Renderer r(test::device_context(), scene, s);
      const RenderOutput out = r.render();
      EXPECT_EQ(out.film.dropped_samples, 0u) << integrator;
      size_t bad = 0;
      for (float v : out.film.mean.rgb) bad += !std::isfinite(v);
      EXPECT_EQ(bad, 0u) << integrator;
    }
    ++*rendered;
  }
}

TEST(Conformance, EverySharedSceneRendersOrFailsClearly) {
  const fs::path root = CLPT_SHARED_SCENES_DIR;
  if (!fs::exists(root)) GTEST_SKIP() << root << " not found (../shared/scenes absent)";
  size_t rendered = 0, refused = 0;
  render_or_refuse_all(root, &rendered, &refused);
  std::cout << rendered << " scenes rendered, " << refused << " refused with a clear error\n";
  EXPECT_GE(rendered, 25u);
}

// ../shared/scenes-extensions: compressed geometry, material extensions, WebP and KTX2
// textures (tests/compressed_geometry_test.cpp names the files that may be refused, and why).
TEST(Conformance, EveryExtensionSceneRendersOrFailsClearly) {
  const fs::path root = CLPT_SHARED_EXTENSIONS_DIR;
  if (!fs::exists(root)) GTEST_SKIP() << root << " not found (../shared/scenes-extensions absent)";
  size_t rendered = 0, refused = 0;
  render_or_refuse_all(root, &rendered, &refused);
  std::cout << rendered << " scenes rendered, " << refused << " refused with a clear error\n";
  EXPECT_GE(rendered, 20u);
}

}  // namespace
}  // namespace clpt::conformance_test
