// KHR_materials_clearcoat end to end (glTF file -> material -> BSDF -> integrator): a plane
// under a constant environment sees only the environment, so each pixel shows L times the
// BSDF's directional albedo at its view direction, which for a smooth coat of weight c over
// a Lambertian base of albedo rho is closed form (kernels/bsdf/gltf_bsdf.cl):
//   a(mu_o) = c Fc(mu_o) + (1 - c Fc(mu_o)) rho (1 - c Fbar),
//   Fc(mu) = 0.04 + 0.96 (1 - mu)^5,  Fbar = 2 int_0^1 Fc(mu) mu dmu = 0.04 + 0.96 / 21.
// The BSDF's own lobes are checked by tests/bsdf_test.cpp (chi-square, energy, reciprocity);
// the conformance matrix compares every estimator on a rough coat (StageMaterial::Clearcoat).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/device.h"
#include "support/gltf_plane.h"
#include "stats/image_stats.h"
#include "support/scenes.h"
#include "util/log.h"

namespace clpt {
namespace {

namespace fs = std::filesystem;

double schlick_coat(double mu) { return 0.04 + 0.96 * std::pow(1.0 - mu, 5.0); }

// The tilted plane (support/gltf_plane.h) with the material's KHR_materials_clearcoat: what
// a user's file holds.
fs::path write_plane(double clearcoat, double rho) {
  const nlohmann::json material = {
      {"pbrMetallicRoughness", {{"baseColorFactor", {rho, rho, rho, 1.0}}, {"metallicFactor", 0.0}}},
      {"extensions",
       {{"KHR_materials_clearcoat", {{"clearcoatFactor", clearcoat}, {"clearcoatRoughnessFactor", 0.0}}},
        {"KHR_materials_specular", {{"specularFactor", 0.0}}}}}};
  return test::write_tilted_plane("clearcoat", material, {"KHR_materials_clearcoat", "KHR_materials_specular"});
}

TEST(Clearcoat, SmoothCoatOverLambertShowsItsClosedForm) {
  constexpr double kCoat = 0.8, kRho = 0.5;
  const fs::path file = write_plane(kCoat, kRho);
  Scene s = test::load_tilted_plane(file);
  ASSERT_EQ(s.materials.size(), 1u);
  ASSERT_FLOAT_EQ(s.materials[0].clearcoat, float(kCoat));
  const float yfov = 0.5f;
  constexpr uint32_t kSize = 16;
  const FilmResult f = test::render_plane_under_sky(s, yfov, kSize, 1024, 5);
  ASSERT_EQ(f.dropped_samples, 0u);

  const glm::dvec3 n = test::tilted_plane_normal();  // towards the camera
  const double fbar = 0.04 + 0.96 / 21.0;
  Image ref(kSize, kSize), ref_var(kSize, kSize);
  double lo = 1.0, hi = 0.0;
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x) {
      const double mu = -glm::dot(glm::dvec3(test::pixel_centre_direction(x, y, kSize, yfov)), n);
      ASSERT_GT(mu, 0.0);
      const double fc = kCoat * schlick_coat(mu);
      const double a = fc + (1.0 - fc) * kRho * (1.0 - kCoat * fbar);
      lo = std::min(lo, a), hi = std::max(hi, a);
      for (int c = 0; c < 3; ++c) ref.rgb[(size_t(y) * kSize + x) * 3 + c] = float(a);
    }
  std::cout << "[ coat     ] expected albedo " << lo << " to " << hi << " across the image\n";
  const Image v = variance_of_mean(f.variance, f.samples_per_pixel);
  const ZTestResult z = z_test(f.mean, &v, ref, &ref_var);
  EXPECT_GE(z.pass_fraction(), 0.99) << z.failed() << " of " << z.tested << " fail, max |z| " << z.max_abs_z;
  double m = 0.0, mref = 0.0, var = 0.0;
  for (size_t i = 0; i < ref.rgb.size(); ++i) m += f.mean.rgb[i], mref += ref.rgb[i], var += v.rgb[i];
  const double n_values = double(ref.rgb.size());
  const double sigma = std::sqrt(var) / n_values;
  std::cout << "[ coat     ] image mean " << m / n_values << " expected " << mref / n_values << " sigma " << sigma
            << "\n";
  EXPECT_NEAR(m / n_values, mref / n_values, 4.0 * sigma + 1e-4);
}

// The same plane without the extension's effect (clearcoatFactor 0) is the Lambertian base:
// the coat's absence is exact, so a file with a zero coat renders as one without it.
TEST(Clearcoat, ZeroCoatIsTheBase) {
  const fs::path file = write_plane(0.0, 0.5);
  const FilmResult f = test::render_plane_under_sky(test::load_tilted_plane(file), 0.5f, 8, 256);
  double m = 0.0;
  for (float x : f.mean.rgb) m += x;
  m /= double(f.mean.rgb.size());
  EXPECT_NEAR(m, 0.5, 0.01);
}

// The Khronos ClearCoatTest asset: factors, roughness factors and both textures reach the
// materials as the file gives them.
TEST(GltfConformance, ClearCoatTestReadsTheExtension) {
  const fs::path file = fs::path(CLPT_SHARED_EXTENSIONS_DIR) / "ClearCoatTest/glTF-Binary/ClearCoatTest.glb";
  if (!fs::exists(file)) GTEST_SKIP() << file << " not found (../shared absent)";
  log::set_level(log::Level::Quiet);
  const Scene s = load_gltf(file);
  auto named = [&](const std::string& name) -> const Material& {
    for (const Material& m : s.materials)
      if (m.name == name) return m;
    ADD_FAILURE() << "no material " << name;
    return s.materials[0];
  };
  EXPECT_EQ(named("Simple_Base").clearcoat, 0.0f);
  EXPECT_EQ(named("Simple_Coated").clearcoat, 1.0f);
  EXPECT_FLOAT_EQ(named("Simple_Coated").clearcoat_roughness, 0.03f);
  EXPECT_TRUE(named("Partial_Coated").clearcoat_texture.used());
  EXPECT_FALSE(named("Partial_Coated").clearcoat_roughness_texture.used());
  EXPECT_EQ(named("RoughVariations_Coated").clearcoat_roughness, 1.0f);
  EXPECT_TRUE(named("RoughVariations_Coated").clearcoat_roughness_texture.used());
}

}  // namespace
}  // namespace clpt
