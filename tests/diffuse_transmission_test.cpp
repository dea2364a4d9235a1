// KHR_materials_diffuse_transmission end to end (glTF file -> material -> BSDF -> integrator):
// a single-sheet plane whose diffuse layer (KHR_materials_specular 0: no coat) reflects
// (1 - t) rho and transmits t c, under a constant environment L = 1 on both sides, shows
// L ((1 - t) rho + t c) in every pixel, per channel: the reflected lobe integrates the front
// hemisphere's radiance, the transmitted one the back's. The BSDF's sampling, energy and
// reciprocity are in tests/bsdf_test.cpp (DiffuseTransmission* and translucent_*).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>

#include <nlohmann/json.hpp>

#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "stats/image_stats.h"
#include "support/device.h"
#include "support/gltf_plane.h"
#include "support/scenes.h"

namespace clpt::diffuse_transmission_test {
namespace {

namespace fs = std::filesystem;

TEST(DiffuseTransmission, SheetUnderAConstantSkyShowsItsClosedForm) {
  constexpr double kRho = 0.8, kT = 0.4;
  const glm::dvec3 color(1.0, 0.5, 0.0);
  const nlohmann::json material = {
      {"pbrMetallicRoughness", {{"baseColorFactor", {kRho, kRho, kRho, 1.0}}, {"metallicFactor", 0.0}}},
      {"extensions",
       {{"KHR_materials_diffuse_transmission",
         {{"diffuseTransmissionFactor", kT}, {"diffuseTransmissionColorFactor", {color.x, color.y, color.z}}}},
        {"KHR_materials_specular", {{"specularFactor", 0.0}}}}}};
  const fs::path file = test::write_tilted_plane(
      "diffuse-transmission", material, {"KHR_materials_diffuse_transmission", "KHR_materials_specular"});
  Scene s = test::load_tilted_plane(file);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_FLOAT_EQ(s.materials[0].diffuse_transmission, float(kT));
  EXPECT_FLOAT_EQ(s.materials[0].diffuse_transmission_color.y, 0.5f);
  constexpr uint32_t kSize = 12;
  const FilmResult f = test::render_plane_under_sky(s, 0.5f, kSize, 512, 9);
  ASSERT_EQ(f.dropped_samples, 0u);
  const glm::dvec3 want = (1.0 - kT) * glm::dvec3(kRho) + kT * color;
  const Image v = variance_of_mean(f.variance, f.samples_per_pixel);
  for (int c = 0; c < 3; ++c) {
    double m = 0.0, var = 0.0;
    for (size_t p = 0; p < size_t(kSize) * kSize; ++p) m += f.mean.rgb[p * 3 + c], var += v.rgb[p * 3 + c];
    const double n = double(kSize) * kSize, sigma = std::sqrt(var) / n;
    m /= n;
    std::cout << "[ dtrans   ] channel " << c << ": image mean " << m << " expected " << want[c] << " sigma "
              << sigma << "\n";
    EXPECT_NEAR(m, want[c], 4.0 * sigma + 1e-4) << "channel " << c;
  }
}

}  // namespace
}  // namespace clpt::diffuse_transmission_test
