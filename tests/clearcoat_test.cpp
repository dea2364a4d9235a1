// KHR_materials_clearcoat end to end (glTF file -> material -> BSDF -> integrator): a plane
// under a constant environment sees only the environment, so each pixel shows L times the
// BSDF's directional albedo at its view direction, which for a smooth coat of weight c over
// a Lambertian base of albedo rho is closed form (kernels/bsdf/gltf_bsdf.cl):
//   a(mu_o) = c Fc(mu_o) + (1 - c Fc(mu_o)) rho (1 - c Fbar),
//   Fc(mu) = 0.04 + 0.96 (1 - mu)^5,  Fbar = 2 int_0^1 Fc(mu) mu dmu = 0.04 + 0.96 / 21.
// ClearcoatNormal: the coat's own normal (clearcoatNormalTexture) moves the coat's highlight
// and the base's normal map does not (tests/support/gltf_square.h).
// The BSDF's own lobes are checked by tests/bsdf_test.cpp (chi-square, energy, reciprocity;
// Tilted* for a coat with its own normal); the conformance matrix compares every estimator
// on a rough coat (StageMaterial::Clearcoat).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>

#include <nlohmann/json.hpp>

#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/device.h"
#include "support/gltf_plane.h"
#include "support/gltf_square.h"
#include "support/reference_match.h"
#include "stats/image_stats.h"
#include "support/scenes.h"
#include "util/log.h"

namespace clpt::clearcoat_test {
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

// A tangent-space normal tilted by `deg` degrees towards the tangent (+x on the square),
// as a normal map's 8-bit texel.
std::array<unsigned char, 3> tilted_texel(double deg) {
  const double t = deg * 3.14159265358979323846 / 180.0;
  auto byte = [](double v) { return static_cast<unsigned char>(std::lround((v * 0.5 + 0.5) * 255.0)); };
  return {byte(std::sin(t)), byte(0.0), byte(std::cos(t))};
}

// Where the highlight sits along x: M = sum over pixels of I x (x in [-1, 1] across the
// image, along world x), and its standard error.
struct Moment {
  double m = 0.0, sigma = 0.0;
};

constexpr uint32_t kSquareSize = 32;

// The square under its point light, seen from 2 m above: a black base with no specular
// lobe of its own (KHR_materials_specular 0), so that only the clearcoat (factor 1,
// roughness 0.3) reflects; `coat_extra` and `base_normal` add the coat's and the base's
// normal maps.
Scene coat_square(const std::string& tag, const nlohmann::json& coat_extra, const nlohmann::json& base_normal,
                  const test::SquareImages& images) {
  nlohmann::json coat = {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.3}};
  coat.update(coat_extra);
  nlohmann::json material = {
      {"pbrMetallicRoughness", {{"baseColorFactor", {0.0, 0.0, 0.0, 1.0}}, {"metallicFactor", 0.0}}},
      {"extensions", {{"KHR_materials_clearcoat", coat}, {"KHR_materials_specular", {{"specularFactor", 0.0}}}}}};
  if (!base_normal.is_null()) material["normalTexture"] = base_normal;
  const fs::path file =
      test::write_square("coatnormal-" + tag, material, {"KHR_materials_clearcoat", "KHR_materials_specular"}, images);
  log::set_level(log::Level::Quiet);
  Scene scene = load_gltf(file);
  fs::remove_all(file.parent_path());
  test::add_camera_on_z(scene, 2.0f, 1.0f);  // sees x, y in [-1.09, 1.09]: the square fills it
  return scene;
}

RenderSettings square_settings(const char* integrator, uint64_t spp, uint32_t seed) {
  RenderSettings rs;
  rs.integrator = integrator;
  rs.width = rs.height = kSquareSize;
  rs.spp = spp;
  rs.seed = seed;
  return rs;
}

Moment coat_highlight(const std::string& tag, const nlohmann::json& coat_extra,
                      const nlohmann::json& base_normal, const test::SquareImages& images, uint32_t seed) {
  const Scene scene = coat_square(tag, coat_extra, base_normal, images);
  const FilmResult f = Renderer(test::device_context(), scene, square_settings("pt", 64, seed)).render().film;
  EXPECT_EQ(f.dropped_samples, 0u);
  const Image v = variance_of_mean(f.variance, f.samples_per_pixel);
  Moment r;
  double var = 0.0;
  for (uint32_t y = 0; y < kSquareSize; ++y)
    for (uint32_t x = 0; x < kSquareSize; ++x) {
      const double px = 2.0 * (x + 0.5) / kSquareSize - 1.0;
      const size_t p = size_t(y) * kSquareSize + x;
      double i = 0.0, vi = 0.0;
      // A white coat under a white light: the channels are one estimate (no third of it).
      for (int c = 0; c < 3; ++c) i += f.mean.rgb[p * 3 + c] / 3.0, vi += v.rgb[p * 3 + c] / 3.0;
      r.m += px * i;
      var += px * px * vi;
    }
  r.sigma = std::sqrt(var);
  return r;
}

// A coat normal tilted towards +x mirrors the light for points at x < 0 (camera and light
// are above the centre, so the bisector there leans towards +x): M < 0, and the opposite tilt
// gives -M. Without a map, with the map's scale 0, or with a normal map on the base alone
// (the specification: the base's map does not reach the coat) the highlight stays centred;
// the same texture named by both (ClearCoatTest's "shared normal map") moves it as the coat's
// alone does.
TEST(ClearcoatNormal, TheCoatsOwnNormalMovesItsHighlight) {
  const test::SquareImages images = {{"plus.png", tilted_texel(20.0)}, {"minus.png", tilted_texel(-20.0)}};
  const nlohmann::json none;
  const Moment flat = coat_highlight("flat", nlohmann::json::object(), none, images, 1);
  const Moment plus = coat_highlight("plus", {{"clearcoatNormalTexture", {{"index", 0}}}}, none, images, 2);
  const Moment minus = coat_highlight("minus", {{"clearcoatNormalTexture", {{"index", 1}}}}, none, images, 3);
  const Moment scale0 =
      coat_highlight("scale0", {{"clearcoatNormalTexture", {{"index", 0}, {"scale", 0.0}}}}, none, images, 4);
  const Moment base_only = coat_highlight("base", nlohmann::json::object(), {{"index", 0}}, images, 5);
  const Moment shared =
      coat_highlight("shared", {{"clearcoatNormalTexture", {{"index", 0}}}}, {{"index", 0}}, images, 6);
  std::cout << "[ coatnorm ] M (sigma): flat " << flat.m << " (" << flat.sigma << "), +20 deg " << plus.m << " ("
            << plus.sigma << "), -20 deg " << minus.m << " (" << minus.sigma << "), scale 0 " << scale0.m << " ("
            << scale0.sigma << "), base map only " << base_only.m << " (" << base_only.sigma << "), shared "
            << shared.m << " (" << shared.sigma << ")\n";
  EXPECT_LT(plus.m, -10.0 * plus.sigma) << "tilted towards +x: the highlight moves to x < 0";
  const double z = 4.0;  // 5 z-tests at 4 sigma: together < 4e-4 by chance
  EXPECT_NEAR(plus.m, -minus.m, z * std::hypot(plus.sigma, minus.sigma)) << "the opposite tilt mirrors it";
  EXPECT_NEAR(flat.m, 0.0, z * flat.sigma) << "no map: centred";
  EXPECT_NEAR(scale0.m, 0.0, z * scale0.sigma) << "scale 0 flattens the coat's map";
  EXPECT_NEAR(base_only.m, 0.0, z * base_only.sigma) << "the base's normal map does not tilt the coat";
  EXPECT_NEAR(shared.m, plus.m, z * std::hypot(shared.m, plus.sigma)) << "one map for both: as the coat's alone";
}

// Light paths see the coat's own normal through the adjoint of its shading normal
// (gltf_bsdf.cl): lt and bdpt batches agree with pt on the tilted coat's highlight, pixel by
// pixel and in blocks (support/reference_match.h). Importance taking the radiance form
// instead (measured) puts lt's image mean 7 sigma low and 36 of its 192 block-channels out.
// lt alone is a single strategy, heavy-tailed per pixel at 16 batches (as the conformance
// matrix says of it): 1 % of its pixel-channels may fail, the blocks and the mean may not.
TEST(ClearcoatNormal, LightPathsSeeTheSameCoat) {
  const Scene scene = coat_square("paths", {{"clearcoatNormalTexture", {{"index", 0}}}}, nullptr,
                                  {{"plus.png", tilted_texel(20.0)}});
  const FilmResult ref = Renderer(test::device_context(), scene, square_settings("pt", 2048, 7)).render().film;
  test::expect_matches_reference(test::render_batches(scene, square_settings("lt", 32, 0), 16, 100), ref, "lt", 4,
                                 0.99);
  test::expect_matches_reference(test::render_batches(scene, square_settings("bdpt", 16, 0), 8, 200), ref, "bdpt");
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
  EXPECT_FALSE(named("BaseNorm_Coated").clearcoat_normal_texture.used());
  EXPECT_TRUE(named("BaseNorm_Coated").normal_texture.used());
  EXPECT_TRUE(named("CoatNorm_Coated").clearcoat_normal_texture.used());
  EXPECT_EQ(named("CoatNorm_Coated").clearcoat_normal_scale, 1.0f);
  EXPECT_TRUE(named("SharedNorm_Coated").clearcoat_normal_texture.used());
  EXPECT_FALSE(s.tangents.empty());
}

}  // namespace
}  // namespace clpt::clearcoat_test
