// Conformance: every glTF file in ../shared/scenes and ../shared/scenes-extensions either renders
// (tiny size) with no NaN/Inf sample, or fails with a clear clpt::Error naming the file. Each
// file renders with pt and ao, and with one of the other integrators, taken in turn over the
// files in name order, so that every integrator meets several real assets (textures, alpha,
// instancing, the material extensions) in every run at little cost.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "integrators/integrator.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/device.h"
#include "util/error.h"

namespace clpt::conformance_test {
namespace {
namespace fs = std::filesystem;

// The implemented integrators besides pt and ao (the integrator table's rows, so a new one
// joins the turn by itself): each file renders with one of them, in turn.
std::vector<std::string> rotated_integrators() {
  std::vector<std::string> names;
  for (const IntegratorInfo& row : integrator_table())
    if (row.implemented && row.name != std::string("pt") && row.name != std::string("ao"))
      names.push_back(row.name);
  return names;
}

// Settings small enough for a 16x12 image of 2 samples with any integrator.
RenderSettings tiny_settings(const std::string& integrator) {
  RenderSettings s;
  s.width = 16;
  s.height = 12;
  s.spp = 2;
  s.integrator = integrator;
  s.pm.photons = 3000;
  s.pm.caustic_photons = 3000;
  s.pm.final_gather = 2;
  s.mlt.bootstrap = 2000;
  s.ic.rays = 16;
  s.vcm.light_per_pixel = 1;
  return s;
}

// Renders every .gltf/.glb under root (or checks its clear refusal); returns the counts.
void render_or_refuse_all(const fs::path& root, size_t* rendered, size_t* refused) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string ext = entry.path().extension().string();
    if (ext == ".gltf" || ext == ".glb") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  const std::vector<std::string> others = rotated_integrators();
  size_t turn = 0;
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.string());
    Scene scene;
    try {
      scene = load_gltf(file);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ExitCode::BadInput);
      EXPECT_NE(std::string(e.what()).find(file.filename().string()), std::string::npos)
          << e.what();
      ++*refused;
      continue;
    }
    const auto check = [&](const RenderSettings& settings) {
      Renderer r(test::device_context(), scene, settings);
      const RenderOutput out = r.render();
      EXPECT_EQ(out.film.dropped_samples, 0u) << settings.integrator;
      size_t bad = 0;
      for (float v : out.film.mean.rgb) bad += !std::isfinite(v);
      EXPECT_EQ(bad, 0u) << settings.integrator;
    };
    check(tiny_settings("pt"));
    check(tiny_settings("ao"));
    // Most of these assets bring no light of their own (they are made for image-based
    // lighting): the rotated integrator gets a white sky, so that it has paths to follow.
    RenderSettings other = tiny_settings(others[turn++ % others.size()]);
    other.background = glm::vec3(1.0f);
    check(other);
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
