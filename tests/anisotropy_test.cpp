// KHR_materials_anisotropy end to end (host/scene/gltf/materials.cpp, the tangents the loader
// generates, kernels/material/material.cl's direction, kernels/bsdf/bsdf.cl's frame and the
// anisotropic GGX of kernels/bsdf/microfacet.cl):
//   Anisotropy   a brushed-metal square written as a glTF file (no TANGENT: generated from its
//                UVs) under a point light, seen from straight above. Its highlight is
//                stretched along the anisotropy direction: A = sum of I (x^2 - y^2) over the
//                image is > 0 for the tangent (x), < 0 when anisotropyRotation turns it by
//                90 degrees, the two mirror images of each other (A0 = -A90 by a z-test), 0
//                for strength 0; at 45 degrees B = sum of I x y > 0 (counter-clockwise, towards
//                the bitangent) and A = 0; and a texture whose RG say (0, 1) turns it as the rotation
//                does; the shared assets read the extension's values.
// Sampling (chi-square), reciprocity and energy of the lobes are in tests/bsdf_test.cpp
// (Anisotropic* and anisotropic_* configurations; GgxVndf for the stretched warp).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "stats/image_stats.h"
#include "support/device.h"
#include "support/gltf_square.h"
#include "support/scenes.h"
#include "util/log.h"

namespace clpt::anisotropy_test {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

// square.gltf (tests/support/gltf_square.h) with a white metal of roughness 0.3 and
// `anisotropy` as its KHR_materials_anisotropy object; with `texture_rgb`, aniso.png (one
// texel of that colour) for the anisotropy object to name as texture 0.
fs::path write_square(const std::string& tag, const nlohmann::json& anisotropy,
                      const std::vector<unsigned char>& texture_rgb = {}) {
  const nlohmann::json material = {
      {"pbrMetallicRoughness", {{"baseColorFactor", {1.0, 1.0, 1.0, 1.0}}, {"metallicFactor", 1.0}, {"roughnessFactor", 0.3}}},
      {"extensions", {{"KHR_materials_anisotropy", anisotropy}}}};
  test::SquareImages images;
  if (!texture_rgb.empty()) images.push_back({"aniso.png", {texture_rgb[0], texture_rgb[1], texture_rgb[2]}});
  return test::write_square("aniso-" + tag, material, {"KHR_materials_anisotropy"}, images);
}

// The stretch of the highlight: A = sum over pixels of I (x^2 - y^2) (x, y the pixel centre
// in [-1, 1], image x along world x; the channel mean of I), and its standard error.
struct Stretch {
  double a = 0.0, sigma = 0.0;
  double b = 0.0, sigma_b = 0.0;  // B = sum of I x y (world x, y): a stretch along x = y
};

constexpr uint32_t kSize = 32;

Stretch render_stretch(const nlohmann::json& anisotropy, uint32_t seed,
                       const std::vector<unsigned char>& texture_rgb = {}) {
  const fs::path file = write_square("s" + std::to_string(seed), anisotropy, texture_rgb);
  log::set_level(log::Level::Quiet);
  Scene scene = load_gltf(file);
  fs::remove_all(file.parent_path());
  if (anisotropy.value("anisotropyStrength", 0.0) > 0.0) {
    EXPECT_FALSE(scene.tangents.empty()) << "the loader generates tangents for an anisotropic material";
  }
  test::add_camera_on_z(scene, 2.0f, 1.0f);  // sees x, y in [-1.09, 1.09]: the square fills it
  RenderSettings rs;
  rs.width = rs.height = kSize;
  rs.spp = 64;
  rs.seed = seed;
  Renderer r(test::device_context(), scene, rs);
  const FilmResult f = r.render().film;
  EXPECT_EQ(f.dropped_samples, 0u);
  const Image v = variance_of_mean(f.variance, f.samples_per_pixel);
  Stretch s;
  double var = 0.0, var_b = 0.0;
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x) {
      const double px = 2.0 * (x + 0.5) / kSize - 1.0, py = 2.0 * (y + 0.5) / kSize - 1.0;
      const double w = px * px - py * py;
      const size_t p = size_t(y) * kSize + x;
      double i = 0.0, vi = 0.0;
      // The channels of a white metal under a white light are one estimate, so the variance
      // of their mean is their (equal) variance, not a third of it.
      for (int c = 0; c < 3; ++c) i += f.mean.rgb[p * 3 + c] / 3.0, vi += v.rgb[p * 3 + c] / 3.0;
      s.a += w * i;
      var += w * w * vi;
      const double wb = px * -py;  // image rows run down, world y up
      s.b += wb * i;
      var_b += wb * wb * vi;
    }
  s.sigma = std::sqrt(var);
  s.sigma_b = std::sqrt(var_b);
  return s;
}

TEST(Anisotropy, HighlightStretchesAlongTheDirection) {
  const Stretch a0 = render_stretch({{"anisotropyStrength", 0.8}}, 1);
  const Stretch a90 = render_stretch({{"anisotropyStrength", 0.8}, {"anisotropyRotation", 0.5 * kPi}}, 2);
  const Stretch iso = render_stretch({{"anisotropyStrength", 0.0}}, 3);
  // The texture's RG (128, 255) is the direction (0.004, 1): the rotation by 90 degrees again.
  const Stretch tex = render_stretch({{"anisotropyStrength", 0.8}, {"anisotropyTexture", {{"index", 0}}}}, 4,
                                     {128, 255, 255});
  // Counter-clockwise from the tangent (x) towards the bitangent (y): 45 degrees is x = y.
  const Stretch a45 = render_stretch({{"anisotropyStrength", 0.8}, {"anisotropyRotation", 0.25 * kPi}}, 5);
  std::cout << "[ aniso    ] B (sigma): rotation 45 deg " << a45.b << " (" << a45.sigma_b << ")\n";
  std::cout << "[ aniso    ] A (sigma): rotation 0 " << a0.a << " (" << a0.sigma << "), 90 deg " << a90.a << " ("
            << a90.sigma << "), strength 0 " << iso.a << " (" << iso.sigma << "), texture (0, 1) " << tex.a << " ("
            << tex.sigma << ")\n";
  EXPECT_GT(a0.a, 10.0 * a0.sigma) << "stretched along the tangent (x)";
  EXPECT_LT(a90.a, -10.0 * a90.sigma) << "turned by the rotation to y";
  EXPECT_GT(a45.b, 10.0 * a45.sigma_b) << "turned counter-clockwise, to x = y";
  EXPECT_NEAR(a45.a, 0.0, 4.0 * a45.sigma) << "on the diagonal: no stretch along x or y";
  const double z = 4.0;  // z-tests: 4 sigma, so 4 of them together fail by chance < 3e-4
  EXPECT_NEAR(a0.a, -a90.a, z * std::hypot(a0.sigma, a90.sigma)) << "the two are mirror images";
  EXPECT_NEAR(iso.a, 0.0, z * iso.sigma) << "isotropic: no stretch";
  EXPECT_NEAR(tex.a, a90.a, z * std::hypot(tex.sigma, a90.sigma)) << "the texture turns it as the rotation does";
}

// The shared assets with the extension read its values as the files give them.
TEST(GltfConformance, AnisotropyAssetsReadTheExtension) {
  const fs::path root(CLPT_SHARED_EXTENSIONS_DIR);
  const fs::path strength = root / "AnisotropyStrengthTest/glTF-Binary/AnisotropyStrengthTest.glb";
  if (!fs::exists(strength)) GTEST_SKIP() << strength << " not found (../shared absent)";
  log::set_level(log::Level::Quiet);
  const Scene s = load_gltf(strength);
  std::vector<float> found;
  for (const Material& m : s.materials) found.push_back(m.anisotropy_strength);
  ASSERT_GE(found.size(), 6u);
  for (size_t i = 0; i < 6; ++i) EXPECT_NEAR(found[i], float(i) / 6.0f, 1e-6f) << "material " << i;
  EXPECT_FALSE(s.tangents.empty());
  const fs::path lamp = root / "AnisotropyBarnLamp/glTF-KTX2-Basisu/AnisotropyBarnLamp.gltf";
  if (!fs::exists(lamp)) return;
  LoadOptions lenient;  // its textures are KTX2 only: magenta stand-ins, the factors as written
  lenient.lenient = true;
  const Scene l = load_gltf(lamp, lenient);
  bool metal = false;
  for (const Material& m : l.materials) {
    if (m.name != "lamp metal") continue;
    metal = true;
    EXPECT_FLOAT_EQ(m.anisotropy_strength, 0.75f);
    EXPECT_NEAR(m.anisotropy_rotation, 0.785398f, 1e-6f);
    EXPECT_TRUE(m.anisotropy_texture.used());
  }
  EXPECT_TRUE(metal);
}

}  // namespace
}  // namespace clpt::anisotropy_test
