// Photon mapping (--integrator pm and sppm) on the PoCL device:
//   SphereFurnaceSppm   the furnace's closed form. Its irradiance is the same everywhere, and
//                       on a surface that is a plane or a sphere the photons within R of a
//                       point cover an area of exactly pi R^2, so each pass's estimate is
//                       unbiased given its radius; SPPM's statistics sum those estimates
//                       (tau / R^2 gains Phi_i / R_i^2 each pass), so the image mean over
//                       independent renders must match the closed form (z-test), and the
//                       per-pixel error must fall as passes are added (4N against N).
//   CrossIntegrator     sppm against a high-spp pt reference on the Cornell box: relMSE falls
//                       from 16 to 64 to 256 passes, and the image mean ends within 1 %;
//                       pm within stated bias bounds (image and block means), and pm's
//                       bias falls as its maps grow;
//   ThroughRoughGlass   pm and sppm on a large rough glass sphere (issue 14): the camera side
//                       path traces through glossy vertices instead of estimating density at
//                       them (density estimation at the glass put pm 13 % off).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

#include "render/renderer.h"
#include "stats/image_stats.h"
#include "support/device.h"
#include "support/mesh.h"
#include "support/reference_match.h"
#include "support/reference_render.h"
#include "support/render.h"
#include "support/scenes.h"

namespace clpt::photon_mapping_test {
namespace {

using test::render;
using test::render_settings;

// Root mean square over pixel-channels of (image - value).
double rms_error(const Image& image, double value) {
  double sum = 0.0;
  for (float v : image.rgb) sum += (double(v) - value) * (double(v) - value);
  return std::sqrt(sum / double(image.rgb.size()));
}

using test::FurnaceCase;

class SphereFurnaceSppm : public ::testing::TestWithParam<FurnaceCase> {};

TEST_P(SphereFurnaceSppm, ConvergesToClosedForm) {
  const FurnaceCase c = GetParam();
  const Scene scene = test::furnace_scene(c.rho, 1.0f);
  const double expected = test::furnace_radiance(c.rho, 1.0, c.max_depth);
  RenderSettings s = render_settings("sppm", 16, 16);
  s.max_depth = c.max_depth;
  s.sppm.photons = 20000;  // per pass

  // Unbiased at any pass count: the image mean over independent renders.
  const BatchMean bm = batch_mean(test::render_batches(scene, s, 16, 5000));
  const double z = (bm.mean - expected) / bm.sigma;
  EXPECT_LT(std::fabs(z), 4.0) << "mean " << bm.mean << " expected " << expected << " sigma " << bm.sigma;
  EXPECT_LT(4.0 * bm.sigma, 0.01 * expected) << "too few samples for a meaningful test";

  // Consistent: the per-pixel error after 4N passes is below that after N.
  const double e16 = rms_error(render(scene, s, 77).mean, expected);
  s.spp = 64;
  const double e64 = rms_error(render(scene, s, 77).mean, expected);
  EXPECT_LT(e64, e16);
  std::cout << "[ figures  ] sppm furnace rho " << c.rho << " depth " << c.max_depth << ": mean "
            << bm.mean << " expected " << expected << " sigma " << bm.sigma << " z " << z
            << "; pixel rms error 16 passes " << e16 << ", 64 passes " << e64 << "\n";
}

INSTANTIATE_TEST_SUITE_P(Cases, SphereFurnaceSppm,
                         ::testing::Values(FurnaceCase{0.5f, 1}, FurnaceCase{0.5f, 3},
                                           FurnaceCase{0.8f, 8}),
                         [](const auto& info) { return test::furnace_case_name(info.param); });

TEST(CrossIntegrator, SppmConvergesToPtOnCornellBox) {
  const Scene scene = test::cornell_box();
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBox, 32, 8192, 4242);
  // A radius of about a third of a pixel's footprint (the box is 2 units wide, 32 pixels):
  // the default of two footprints darkens the edges of the walls by some percent at 256
  // passes (a disc that reaches past a wall's edge finds no photons there).
  RenderSettings s = render_settings("sppm", 16, 32);
  s.sppm.radius = 0.02f;
  s.sppm.photons = 20000;
  double previous = 0.0;
  Image last;
  for (uint64_t passes : {16u, 64u, 256u}) {
    s.spp = passes;
    last = render(scene, s, 11).mean;
    const double rel_mse = compare_images(last, ref.mean).rel_mse;
    std::cout << "[ figures  ] sppm cornell " << passes << " passes: relMSE " << rel_mse << "\n";
    if (previous > 0.0) {
      EXPECT_LT(rel_mse, previous) << passes << " passes";
    }
    previous = rel_mse;
  }
  // The image mean within 3 %: at 256 samples per pixel the camera's own sampling moves the
  // image mean by about 1 % (pt at 256 spp, seeds 11 to 13: 0.1191, 0.1197, 0.1216 against
  // 0.1210 at 8192), and the edges of the walls are still about 1 % dark at this radius
  // (four seeds averaged 0.9 % below).
  const double mean = image_mean(last), ref_mean = image_mean(ref.mean);
  EXPECT_NEAR(mean, ref_mean, 0.03 * ref_mean);
}

// Relative deviation of the mean of each block x block tile of `image` from the reference's.
std::vector<double> block_deviations(const Image& image, const Image& ref, uint32_t block) {
  std::vector<double> out;
  for (uint32_t by = 0; by + block <= image.height; by += block)
    for (uint32_t bx = 0; bx + block <= image.width; bx += block) {
      double a = 0.0, b = 0.0;
      for (uint32_t y = by; y < by + block; ++y)
        for (uint32_t x = bx; x < bx + block; ++x)
          for (int c = 0; c < 3; ++c) {
            a += image.pixel(x, y)[c];
            b += ref.pixel(x, y)[c];
          }
      out.push_back(b > 0.0 ? a / b - 1.0 : 0.0);
    }
  return out;
}

// pm is biased (each estimate averages the light over a disc of k photons); its bounds here
// are its measured bias plus the camera's own sampling noise at 256 samples per pixel, which
// moves 8 x 8 blocks that hold an edge of the light by up to 4 % (pt itself at seed 11: the
// block with the light's edge 3.9 % below the 8192-spp reference, and pm with the same
// camera samples 3.8 %). Measured with the default maps (200 000 global paths, k = 50):
// the blocks' deviations from the same-seed pt render within 1.3 % but one (4.7 %, where
// that pt render has a firefly), the image mean 0.2 % below it.
void expect_pm_within_bounds(const Scene& scene, const FilmResult& ref, RenderSettings s,
                             const std::string& label) {
  const Image pm = render(scene, s, 11).mean;
  const double mean = image_mean(pm), ref_mean = image_mean(ref.mean);
  EXPECT_NEAR(mean, ref_mean, 0.03 * ref_mean) << label;
  double worst = 0.0;
  for (double d : block_deviations(pm, ref.mean, 8)) worst = std::max(worst, std::fabs(d));
  EXPECT_LT(worst, 0.08) << label;
  std::cout << "[ figures  ] " << label << ": image mean " << mean << " (pt " << ref_mean
            << "), worst 8x8 block " << worst << ", relMSE " << compare_images(pm, ref.mean).rel_mse
            << "\n";
}

TEST(CrossIntegrator, PmWithinBiasBoundsOnCornellBox) {
  const Scene scene = test::cornell_box();
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBox, 32, 8192, 4242);
  expect_pm_within_bounds(scene, ref, render_settings("pm", 256, 32), "pm cornell, final gather 8");
  RenderSettings s = render_settings("pm", 256, 32);
  s.pm.final_gather = 0;
  expect_pm_within_bounds(scene, ref, s, "pm cornell, global map at the first hit");
}

// The caustic under the glass block comes from the caustic map (L S+ D), the rest of the
// light through the glass from the camera path's delta bounces.
TEST(CrossIntegrator, PmWithinBiasBoundsWithGlossyAndGlass) {
  const Scene scene = test::cornell_box_glossy_glass();
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBoxGlossyGlass, 32, 16384, 4343);
  expect_pm_within_bounds(scene, ref, render_settings("pm", 256, 32), "pm glossy+glass");
}

// pm is consistent: with k fixed, more photons mean smaller discs, so the error of the
// global map read at the first hit (the most visible use of it) falls as the map grows.
// The same seed keeps the camera's samples, so only the map differs.
TEST(PhotonMapping, PmErrorFallsAsTheMapGrows) {
  const Scene scene = test::cornell_box();
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBox, 32, 8192, 4242);
  RenderSettings s = render_settings("pm", 64, 32);
  s.pm.final_gather = 0;
  double previous = 0.0;
  for (uint64_t photons : {10000u, 100000u, 1000000u}) {
    s.pm.photons = photons;
    const double rel_mse = compare_images(render(scene, s, 11).mean, ref.mean).rel_mse;
    std::cout << "[ figures  ] pm cornell, global map of " << photons << " paths at the first hit: relMSE "
              << rel_mse << "\n";
    if (previous > 0.0) {
      EXPECT_LT(rel_mse, previous) << photons << " paths";
    }
    previous = rel_mse;
  }
}

// A point light inside a closed, thin, double-sided sphere lights nothing outside it: pt
// renders black. The density estimates must not reach through the shell. They did: a
// photon inside, on a neighbouring facet and arriving at a grazing angle, passed the normal
// check (facets within 37 degrees) with its direction on the outer side of the visible
// point's tangent plane, so the outer surface reflected it (found on ../shared/scenes'
// ShadowsSpot, whose lamp shade encloses its spot light: sppm's image mean was 2.7x pt's).
// A disc radius of 0.2 on a sphere of radius 0.5 lets facets up to ~23 degrees apart share
// photons; the photons inside are dense (20 000 paths onto 0.8 of albedo).
TEST(PhotonMapping, NoLightThroughAClosedShell) {
  Scene scene;
  Material m;
  m.base_color = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
  m.metallic = 0.0f;
  m.specular = 0.0f;
  m.double_sided = true;
  test::add_mesh(scene, test::uv_sphere(glm::vec3(0.0f), 0.5f, 24, 12), m);
  PunctualLight point;
  point.type = PunctualLight::Type::Point;
  point.intensity = 10.0f;
  point.position = glm::vec3(0.0f, 0.1f, 0.05f);
  scene.lights.push_back(point);
  test::add_camera_on_z(scene, 2.0f, 0.6f);

  RenderSettings s = render_settings("sppm", 16, 16);
  s.sppm.radius = 0.2f;
  s.sppm.photons = 20000;
  const Image sppm = render(scene, s, 3).mean;
  s = render_settings("pm", 4, 16);
  s.pm.final_gather = 0;  // the global map read at the visible point
  s.pm.photons = 20000;
  s.pm.max_radius = 0.2f;
  const Image pm = render(scene, s, 3).mean;
  const float sppm_max = *std::max_element(sppm.rgb.begin(), sppm.rgb.end());
  const float pm_max = *std::max_element(pm.rgb.begin(), pm.rgb.end());
  std::cout << "[ figures  ] brightest pixel outside the shell: sppm " << sppm_max << ", pm "
            << pm_max << " (pt: 0)\n";
  EXPECT_EQ(sppm_max, 0.0f);
  EXPECT_EQ(pm_max, 0.0f);
}

// A rough glass sphere (roughness 0.3, ior 1.5, radius 0.5) on a diffuse floor under a
// 0.5 m quad light, as issue 14 reported it; the camera on +z looks at it.
Scene rough_glass_scene() {
  Scene scene;
  Material floor;
  floor.base_color = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
  floor.metallic = 0.0f;
  floor.specular = 0.0f;
  test::Mesh quad;
  quad.positions = {{-3, 0, 3}, {3, 0, 3}, {3, 0, -3}, {-3, 0, -3}};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  test::add_mesh(scene, quad, floor);
  Material lamp = floor;
  lamp.base_color = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  lamp.emission = glm::vec3(10.0f);
  quad.positions = {{-0.25f, 2, -0.25f}, {0.25f, 2, -0.25f}, {0.25f, 2, 0.25f}, {-0.25f, 2, 0.25f}};
  test::add_mesh(scene, quad, lamp);
  test::add_mesh(scene, test::icosphere(glm::vec3(0.0f, 0.5f, 0.0f), 0.5f, 4),
                 test::glass_material(0.3f));
  Camera cam;
  cam.camera_to_world = glm::mat4(1.0f);
  cam.camera_to_world[3] = glm::vec4(0.0f, 0.5f, 3.0f, 1.0f);
  cam.yfov = 0.45f;
  cam.aspect = 1.0f;
  scene.cameras.push_back(cam);
  return scene;
}

TEST(PhotonMapping, ThroughRoughGlass) {
  constexpr uint32_t kSize = 32;
  const FilmResult ref = test::pt_reference("rough_glass_sphere v1", rough_glass_scene,
                                            render_settings("pt", 4096, kSize), 1);
  // The pixels whose centre ray meets the sphere (radius 0.5 at (0, 0.5, 0)).
  std::vector<bool> sphere(size_t(kSize) * kSize);
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x)
      sphere[size_t(y) * kSize + x] =
          test::ray_sphere(glm::vec3(0.0f, 0.5f, 3.0f), test::pixel_centre_direction(x, y, kSize, 0.45f),
                           glm::vec3(0.0f, 0.5f, 0.0f), 0.5f) > 0.0f;
  auto sphere_mean = [&](const Image& img) {
    double sum = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < sphere.size(); ++i)
      if (sphere[i]) sum += (double(img.rgb[3 * i]) + img.rgb[3 * i + 1] + img.rgb[3 * i + 2]) / 3.0, ++n;
    return sum / double(n);
  };
  const double reference = sphere_mean(ref.mean);
  for (const char* integrator : {"pm", "sppm"}) {
    RenderSettings s = render_settings(integrator, 64, kSize);
    if (std::string(integrator) == "sppm") s.sppm.photons = 16384;
    std::vector<double> m;
    for (const Image& b : test::render_batches(rough_glass_scene(), s, 4, 40)) m.push_back(sphere_mean(b));
    double mean = 0.0;
    for (double v : m) mean += v / double(m.size());
    // Stated bound: 4 % (density estimation at the floor behind and under the glass). With
    // density estimated at the glass itself this render gave sppm 1.177 and pm 1.030 (pm was
    // +12.7 % in a 48x48 view of the same kind of scene: docs/TESTING.md).
    EXPECT_NEAR(mean / reference, 1.0, 0.04) << integrator << ": sphere mean " << mean << ", pt " << reference;
    std::cout << "[ figures  ] " << integrator << " through rough glass: sphere mean / pt " << mean / reference << "\n";
  }
}

// The photon kernel appends photons in no fixed order; pm sorts them before building its
// maps, so two renders with one seed are identical bit for bit (which checkpoints rely on).
TEST(PhotonMapping, PmIsReproducible) {
  const Scene scene = test::cornell_box_glossy_glass();
  RenderSettings s = render_settings("pm", 2, 24);
  s.pm.photons = 30000;
  s.pm.caustic_photons = 30000;
  const Image a = render(scene, s, 5).mean, b = render(scene, s, 5).mean;
  EXPECT_EQ(a.rgb, b.rgb);
}

}  // namespace
}  // namespace clpt::photon_mapping_test
