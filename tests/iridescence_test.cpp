// KHR_materials_iridescence end to end (glTF file -> material -> BSDF -> integrator): a
// smooth metal plane with a thin film under a constant environment L = 1 (support/
// gltf_plane.h) shows, in each pixel, the mirror's reflectance mix(F_schlick(base, mu),
// R_film(mu), k) over the pixel's footprint. R_film comes from the film kernel itself
// (tests/kernels/thin_film_test.cl), which tests/thin_film_test.cpp checks against a spectral
// Airy sum; this test checks that the file's factor, film index and thickness reach it, on
// the right lobe, with the right blend. The BSDF's sampling, energy and reciprocity with a
// film are in tests/bsdf_test.cpp (Iridescent* configurations).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/device.h"
#include "support/gltf_plane.h"
#include "support/scenes.h"
#include "support/thin_film.h"
#include "util/log.h"

namespace clpt::iridescence_test {
namespace {

namespace fs = std::filesystem;

TEST(Iridescence, FilmOnAMirrorShowsItsReflectance) {
  constexpr double kBase = 0.3, kFactor = 0.7, kIor = 1.8, kMin = 150.0, kMax = 550.0;
  const nlohmann::json material = {
      {"pbrMetallicRoughness",
       {{"baseColorFactor", {kBase, kBase, kBase, 1.0}}, {"metallicFactor", 1.0}, {"roughnessFactor", 0.0}}},
      {"extensions",
       {{"KHR_materials_iridescence",
         {{"iridescenceFactor", kFactor},
          {"iridescenceIor", kIor},
          {"iridescenceThicknessMinimum", kMin},
          {"iridescenceThicknessMaximum", kMax}}}}}};
  const fs::path file = test::write_tilted_plane("iridescence", material, {"KHR_materials_iridescence"});
  Scene s = test::load_tilted_plane(file);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_FLOAT_EQ(s.materials[0].iridescence, float(kFactor));
  EXPECT_FLOAT_EQ(s.materials[0].iridescence_ior, float(kIor));
  EXPECT_FLOAT_EQ(s.materials[0].iridescence_thickness_min, float(kMin));
  EXPECT_FLOAT_EQ(s.materials[0].iridescence_thickness_max, float(kMax));
  const float yfov = 0.5f;
  constexpr uint32_t kSize = 16;
  const FilmResult f = test::render_plane_under_sky(s, yfov, kSize, 64, 3);
  ASSERT_EQ(f.dropped_samples, 0u);

  // The reflectance at a 5 x 5 grid over each pixel's footprint (box filter: uniform jitter
  // over the pixel), for the file's thickness (no thickness texture: the maximum) and, to
  // show that the test can tell, for the extension's default maximum, 400 nm.
  const glm::dvec3 n = test::tilted_plane_normal();
  const double tan_half = std::tan(0.5 * yfov);
  constexpr int kGrid = 5;
  std::vector<double> mus;
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x)
      for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) {
          const double fx = 2.0 * (x + i / double(kGrid - 1)) / kSize - 1.0;
          const double fy = 1.0 - 2.0 * (y + j / double(kGrid - 1)) / kSize;
          const glm::dvec3 d = glm::normalize(glm::dvec3(fx * tan_half, fy * tan_half, -1.0));
          mus.push_back(-glm::dot(d, n));
        }
  std::vector<glm::vec4> in, in_default;
  for (double mu : mus) {
    in.emplace_back(float(mu), float(kIor), float(kMax), float(kBase));
    in_default.emplace_back(float(mu), float(kIor), 400.0f, float(kBase));
  }
  const std::vector<glm::vec4> R = test::thin_film_reflectance(in);
  const std::vector<glm::vec4> R_default = test::thin_film_reflectance(in_default);
  auto reflectance = [&](const std::vector<glm::vec4>& Rf, size_t k, int c) {
    const double mu = std::clamp(mus[k], 0.0, 1.0);
    const double schlick = kBase + (1.0 - kBase) * std::pow(1.0 - mu, 5.0);
    return (1.0 - kFactor) * schlick + kFactor * Rf[k][c];
  };
  int outside = 0, default_outside = 0;
  double spread = 0.0;
  for (uint32_t p = 0; p < kSize * kSize; ++p)
    for (int c = 0; c < 3; ++c) {
      double lo = 1e9, hi = -1e9, lo_d = 1e9, hi_d = -1e9;
      for (int g = 0; g < kGrid * kGrid; ++g) {
        const size_t k = size_t(p) * kGrid * kGrid + g;
        lo = std::min(lo, reflectance(R, k, c)), hi = std::max(hi, reflectance(R, k, c));
        lo_d = std::min(lo_d, reflectance(R_default, k, c)), hi_d = std::max(hi_d, reflectance(R_default, k, c));
      }
      const double v = f.mean.rgb[size_t(p) * 3 + c];
      // 1e-3: float rounding of the direction and of the film; the footprint's range is
      // sampled on a grid, and the reflectance is smooth within a pixel.
      if (v < lo - 1e-3 || v > hi + 1e-3) {
        ++outside;
        ADD_FAILURE() << "pixel " << p << " channel " << c << ": " << v << " outside [" << lo << ", " << hi << "]";
      }
      if (v < lo_d - 1e-3 || v > hi_d + 1e-3) ++default_outside;
    }
  for (uint32_t p = 0; p < kSize * kSize; ++p) {
    const float* v = &f.mean.rgb[size_t(p) * 3];
    spread = std::max(spread, double(std::max({v[0], v[1], v[2]}) - std::min({v[0], v[1], v[2]})));
  }
  std::cout << "[ iridesce ] " << outside << " of " << 3 * kSize * kSize
            << " pixel channels outside the film's range over their footprint; against a 400 nm film "
            << default_outside << "; largest channel spread " << spread << "\n";
  EXPECT_GT(spread, 0.1) << "the film should colour the mirror";
  EXPECT_GT(default_outside, int(kSize * kSize)) << "a 400 nm film should not pass for the file's 550 nm";
}

// The shared assets with the extension read its values as the files give them.
TEST(GltfConformance, IridescenceAssetsReadTheExtension) {
  const fs::path dir(CLPT_SHARED_EXTENSIONS_DIR);
  const fs::path suzanne = dir / "IridescenceSuzanne/glTF-Binary/IridescenceSuzanne.glb";
  const fs::path lamp = dir / "IridescenceLamp/glTF/IridescenceLamp.gltf";
  if (!fs::exists(suzanne) || !fs::exists(lamp)) GTEST_SKIP() << dir << ": iridescence assets not found (../shared absent)";
  log::set_level(log::Level::Quiet);
  const Scene s = load_gltf(suzanne);  // the extension is required there
  ASSERT_GE(s.materials.size(), 3u);
  EXPECT_EQ(s.materials[0].iridescence, 1.0f);
  EXPECT_FLOAT_EQ(s.materials[0].iridescence_ior, 1.33f);
  EXPECT_EQ(s.materials[0].iridescence_thickness_min, 100.0f);  // the default
  EXPECT_EQ(s.materials[0].iridescence_thickness_max, 400.0f);
  EXPECT_FALSE(s.materials[0].iridescence_thickness_texture.used());
  EXPECT_EQ(s.materials[2].iridescence_thickness_min, 200.0f);
  EXPECT_EQ(s.materials[2].iridescence_thickness_max, 600.0f);
  EXPECT_TRUE(s.materials[2].iridescence_thickness_texture.used());
  const Scene l = load_gltf(lamp);
  bool found = false;
  for (const Material& m : l.materials)
    if (m.name == "IridescenceLampIridescence") {
      found = true;
      EXPECT_FLOAT_EQ(m.iridescence_ior, 1.8f);
      EXPECT_EQ(m.iridescence_thickness_min, 485.0f);
      EXPECT_EQ(m.iridescence_thickness_max, 515.0f);
      EXPECT_TRUE(m.iridescence_thickness_texture.used());
      EXPECT_FALSE(m.iridescence_texture.used());
    }
  EXPECT_TRUE(found) << "no material IridescenceLampIridescence";
}

}  // namespace
}  // namespace clpt::iridescence_test
