// Vertex connection and merging (--integrator vcm, kernels/integrators/vcm.cl) on the PoCL
// device:
//   SphereFurnaceVcm     the furnace's closed form, z-test over independent batches (inside a
//                        sphere a merge's disc of radius r has exactly the area of the cap
//                        it gathers from, pi r^2: no merging bias to allow for), also with
//                        per-pixel radii, with merging at every vertex (--vcm-merge all;
//                        the others merge at the first, the default) and with three light
//                        subpaths per pixel (--vcm-light-paths 3);
//   VcmModes             --vcm-mode bpt renders bdpt's image (the same strategies and
//                        weights: equal to float rounding in the splats' order); ppm and pt
//                        modes agree with pt's reference mean;
//   CrossIntegrator      vcm against the 8 192-spp pt reference of the Cornell box (block
//                        means, per-pixel z, image mean), also in tiles of ~100 light paths
//                        (eta = pi r^2 paths of the tile), with light vertex caching; with a
//                        background, directional, point and spot lights; on the
//                        glossy-and-glass box; merging at every non-delta camera vertex
//                        (--vcm-merge all) on both boxes; several light subpaths per pixel
//                        (--vcm-light-paths), in tiles, with per-pixel radii and with caching;
//                        the error falling with passes (defaults and the pass rule); auto's
//                        K (passes of 1, 2 and 4, then its choice);
//   VcmOptions, VcmCli   usage errors; --stats figures (merges, light vertices, the radius
//                        shrinking pass by pass); the --vcm-merged layer.
// The MIS weights of both techniques are checked path by path against explicit whole-path
// densities, and shown to sum to 1, in tests/bdpt_mis_test.cpp (the *_vcm cases).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "integrators/vcm.h"
#include "shared/bdpt_types.h"
#include "io/image_io.h"
#include "render/renderer.h"
#include "stats/image_stats.h"
#include "support/parse_options.h"
#include "support/reference_match.h"
#include "support/reference_render.h"
#include "support/render.h"
#include "support/run.h"
#include "support/device.h"
#include "support/scenes.h"
#include "util/error.h"

namespace clpt::vcm_test {
namespace {

using test::FurnaceCase;
using test::parse_error;

constexpr uint32_t kSize = 32;
// A merge radius well under the Cornell box's features (it is 0.55 wide; 2 pixel footprints
// at 32 x 32 would be 0.06): merging's bias stays below what these tests can see.
constexpr float kRadius = 0.01f;

// The pass rule (--vcm-shrink pass, its alpha) unless the test asks for per-pixel radii.
RenderSettings vcm_settings(uint32_t mode, uint64_t spp, uint32_t size = kSize) {
  RenderSettings s = test::render_settings("vcm", spp, size);
  s.vcm.mode = mode;
  s.vcm.radius = kRadius;
  s.vcm.pixel_radius = false;
  s.vcm.alpha = 0.75f;
  return s;
}

class SphereFurnaceVcm : public ::testing::TestWithParam<FurnaceCase> {};

// vcm, and ppm mode (merges alone, weight 1: the test of the merge's normalisation, which
// vcm's MIS gives little weight here: light vertices are sparse over the two spheres' 327 m^2).
TEST_P(SphereFurnaceVcm, MatchesClosedForm) {
  const FurnaceCase c = GetParam();
  const Scene scene = test::furnace_scene(c.rho, 1.0f);
  const double expected = test::furnace_radiance(c.rho, 1.0, c.max_depth);
  for (const int variant : {0, 1, 2, 3, 4}) {
    const uint32_t mode = variant == 1 ? dev::VCM_MODE_PPM : dev::VCM_MODE_VCM;
    const char* name = variant == 0   ? "vcm"
                       : variant == 1 ? "ppm"
                       : variant == 2 ? "vcm, per-pixel radii"
                       : variant == 3 ? "vcm, merging at every vertex"
                                      : "vcm, 3 light paths per pixel";
    RenderSettings s = vcm_settings(mode, 32, 16);
    s.vcm.pixel_radius = variant == 2;
    // The default merges at the first camera vertex alone, its weights counting that merge
    // only; merges take about half the weight here (eta times the light vertices' density,
    // 1 / 327 m^2, is about 0.6), so weights that counted merges the estimator does not make
    // (or missed ones it makes) would show. --vcm-merge all: at every vertex (Georgiev 2012).
    s.vcm.merge_first = variant != 3;
    // Per pixel, radii far from the pass's (r^2 falls as i^-0.96 where vertices arrive, the
    // pass's as i^-0.49), so that every weight must take the pixel's eta, light tracing's too.
    if (variant == 2) s.vcm.alpha = 0.51f;
    // Three light subpaths per pixel: merges over three times the light vertices (eta three
    // times as large) and light tracing's splats a third each.
    if (variant == 4) s.vcm.light_per_pixel = 3;
    s.max_depth = c.max_depth;
    s.vcm.radius = 0.5f;  // the inner sphere's radius is 1, the outer one's 5
    const BatchMean bm = batch_mean(test::render_batches(scene, s, 30, 5000));
    const double z = (bm.mean - expected) / bm.sigma;
    EXPECT_LT(std::fabs(z), 4.0) << name << ": mean " << bm.mean << " expected " << expected
                                 << " sigma " << bm.sigma;
    EXPECT_LT(4.0 * bm.sigma, 0.03 * expected) << name << ": too few samples for a meaningful test";
    std::cout << "[ figures  ] " << name << " furnace rho " << c.rho << " depth " << c.max_depth
              << ": mean " << bm.mean << " expected " << expected << " sigma " << bm.sigma << " z "
              << z << "\n";
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, SphereFurnaceVcm,
                         ::testing::Values(FurnaceCase{0.5f, 1}, FurnaceCase{0.8f, 8}),
                         [](const auto& info) { return test::furnace_case_name(info.param); });

// The relative difference of two images' means and their largest pixel-channel difference
// relative to b's mean (stats/image_stats.h).
struct ImageDifference {
  double mean_rel = 0.0, max_rel = 0.0;
};
ImageDifference difference(const Image& a, const Image& b) {
  const double mean = image_mean(b);
  return {std::fabs(image_mean(a) - mean) / mean, compare_images(a, b).max_abs_diff / mean};
}

// Merging off, vcm is bdpt: the same subpaths from the same sampler dimensions, the same
// strategies and weights (StrategyMis' vm = 0). Only the order of the splats' float atomics
// differs between two renders, so the images agree to float rounding, not bit for bit.
TEST(VcmModes, BptModeRendersBdpt) {
  const Scene scene = test::cornell_box();
  const Image bdpt = test::render(scene, test::render_settings("bdpt", 16, kSize), 31).mean;
  const Image bpt = test::render(scene, vcm_settings(dev::VCM_MODE_BPT, 16), 31).mean;
  const ImageDifference d = difference(bpt, bdpt);
  std::cout << "[ figures  ] vcm --vcm-mode bpt against bdpt, one seed: image mean rel diff "
            << d.mean_rel << ", largest pixel diff / image mean " << d.max_rel << "\n";
  EXPECT_LT(d.mean_rel, 1e-5);
  EXPECT_LT(d.max_rel, 1e-3);
  // And a different seed is a different image (the comparison can fail).
  const Image other = test::render(scene, vcm_settings(dev::VCM_MODE_BPT, 16), 32).mean;
  EXPECT_GT(difference(other, bdpt).max_rel, 1e-2);
}

// The other modes converge to the same image: photon mapping alone (merging at the first
// non-delta vertex, emitters through delta paths only), path tracing alone (NEE against
// emitter hits), and full vcm, each against pt's reference.
TEST(VcmModes, EveryModeMatchesPtOnCornellBox) {
  const Scene scene = test::cornell_box();
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBox, kSize, 8192, 4242);
  test::expect_matches_reference(test::render_batches(scene, vcm_settings(dev::VCM_MODE_PT, 64), 16, 900),
                                 ref, "vcm mode pt");
  // Photon mapping alone is biased by the radius where radiance bends within r of a pixel's
  // point (a few pixels at the box's edges: 8 of 3 072 pixel-channels at |z| up to 12 when
  // this test was written, against the 8 the per-pixel test allows at 0.9975); the block
  // and image-mean tests keep their strictness.
  test::expect_matches_reference(test::render_batches(scene, vcm_settings(dev::VCM_MODE_PPM, 64), 16, 1900),
                                 ref, "vcm mode ppm", 4, 0.995);
  test::expect_matches_reference(test::render_batches(scene, vcm_settings(dev::VCM_MODE_LT, 64), 16, 2900),
                                 ref, "vcm mode lt");
}

TEST(CrossIntegrator, VcmMatchesPtOnCornellBox) {
  const Scene scene = test::cornell_box();
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBox, kSize, 8192, 4242);
  RenderSettings s = vcm_settings(dev::VCM_MODE_VCM, 32);
  test::expect_matches_reference(test::render_batches(scene, s, 16, 700), ref, "vcm cornell");
  // Tiles of about 100 light paths: each camera path merges with its tile's light vertices
  // only, over eta = pi r^2 (paths of the tile).
  s.bdpt.memory_bytes = 8 * (sizeof(dev::PathVertex) + sizeof(dev::GridPoint) + 24) * 100;
  test::expect_matches_reference(test::render_batches(scene, s, 16, 1700), ref, "vcm tiles");
}

// --vcm-shrink pixel: each pixel merges with its own radius, and every weight of its paths
// (the light vertices' too, moved along their EtaSlopes, and the light tracer's, with the eta
// of the pixel it lands in) uses that pixel's eta. In tiles a light path splats into pixels of
// other tiles, whose radii must be the pass's, not the next's.
TEST(CrossIntegrator, VcmWithPixelRadiiMatchesPt) {
  const Scene scene = test::cornell_box();
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBox, kSize, 8192, 4242);
  RenderSettings s = vcm_settings(dev::VCM_MODE_VCM, 32);
  s.vcm.pixel_radius = true;
  s.vcm.alpha = 0.6f;
  s.vcm.radius = 2.0f * kRadius;  // radii that stay large where few light vertices arrive
  test::expect_matches_reference(test::render_batches(scene, s, 16, 3700), ref, "vcm pixel radii");
  s.bdpt.memory_bytes = 8 * (sizeof(dev::PathVertex) + sizeof(dev::GridPoint) + 32) * 100;
  test::expect_matches_reference(test::render_batches(scene, s, 16, 4700), ref,
                                 "vcm pixel radii, tiles");
}

// Light vertex caching (--bdpt-lvc, as bdpt's): each camera vertex connects to 2 vertices
// drawn from all the tile's stored light vertices, scaled by their count / (2 paths).
TEST(CrossIntegrator, VcmWithLightVertexCachingMatchesPt) {
  const Scene scene = test::cornell_box();
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBox, kSize, 8192, 4242);
  RenderSettings s = vcm_settings(dev::VCM_MODE_VCM, 32);
  s.bdpt.lvc = 2;
  test::expect_matches_reference(test::render_batches(scene, s, 16, 2700), ref, "vcm lvc 2");
}

// The environment and delta lights take their own branches of the weights (no distance factor
// on an infinite light's first segment; dVC = 0 from delta lights) and light vertices from
// them merge like any other.
TEST(CrossIntegrator, VcmMatchesPtWithEnvironmentAndPunctualLights) {
  const Scene scene = test::cornell_box_all_lights();
  auto with_background = [](RenderSettings s) {
    s.background = glm::vec3(0.3f, 0.4f, 0.5f);
    return s;
  };
  const FilmResult ref = test::pt_reference("cornell_all_lights", test::cornell_box_all_lights,
                                            with_background(test::render_settings("pt", 8192, kSize)), 4545);
  test::expect_matches_reference(
      test::render_batches(scene, with_background(vcm_settings(dev::VCM_MODE_VCM, 32)), 16, 3900),
      ref, "vcm environment+punctual");
}

TEST(CrossIntegrator, VcmMatchesPtWithGlossyAndGlass) {
  const Scene scene = test::cornell_box_glossy_glass();
  const FilmResult ref =
      test::pt_reference(test::ReferenceScene::CornellBoxGlossyGlass, kSize, 16384, 4343);
  test::expect_matches_reference(
      test::render_batches(scene, vcm_settings(dev::VCM_MODE_VCM, 32), 16, 800), ref,
      "vcm glossy glass");
  // Per-pixel radii that part from the pass's (alpha 0.51): the caustic under the glass is
  // light tracing's and merging's, so their weights must take the same (the pixel's) eta.
  RenderSettings s = vcm_settings(dev::VCM_MODE_VCM, 32);
  s.vcm.pixel_radius = true;
  s.vcm.alpha = 0.51f;
  test::expect_matches_reference(test::render_batches(scene, s, 16, 1800), ref,
                                 "vcm glossy glass, pixel radii");
}

// --vcm-merge all: merging at every non-delta camera vertex (Georgiev 2012) where the other
// tests take the default, the first alone (stages/vertex_mis.cl; tests/bdpt_mis_test.cpp checks
// both path by path). The glossy-and-glass box adds camera paths through the smooth glass, with
// per-pixel radii.
TEST(CrossIntegrator, VcmMergingAtEveryVertexMatchesPt) {
  RenderSettings s = vcm_settings(dev::VCM_MODE_VCM, 32);
  s.vcm.merge_first = false;
  const FilmResult cornell =
      test::pt_reference(test::ReferenceScene::CornellBox, kSize, 8192, 4242);
  test::expect_matches_reference(test::render_batches(test::cornell_box(), s, 16, 5700), cornell,
                                 "vcm merge all");
  const FilmResult glass =
      test::pt_reference(test::ReferenceScene::CornellBoxGlossyGlass, kSize, 16384, 4343);
  s.vcm.pixel_radius = true;
  s.vcm.alpha = 0.51f;
  test::expect_matches_reference(test::render_batches(test::cornell_box_glossy_glass(), s, 16, 5800),
                                 glass, "vcm glossy glass, merge all, pixel radii");
}

// --vcm-light-paths K: K light subpaths per pixel and pass; each camera path connects to the
// first of its pixel's and merges with all (eta = pi r^2 K pixels), light tracing splats all
// K, a K-th each, and weights them as K samples per pixel (stages/vertex_mis.cl). In tiles the
// budget divides among the K; with light vertex caching the cache holds all K's vertices.
TEST(CrossIntegrator, VcmWithSeveralLightPathsPerPixelMatchesPt) {
  const FilmResult cornell =
      test::pt_reference(test::ReferenceScene::CornellBox, kSize, 8192, 4242);
  RenderSettings s = vcm_settings(dev::VCM_MODE_VCM, 32);
  s.vcm.light_per_pixel = 3;
  test::expect_matches_reference(test::render_batches(test::cornell_box(), s, 16, 6700), cornell,
                                 "vcm 3 light paths");
  RenderSettings t = s;
  t.bdpt.memory_bytes = 3 * 8 * (sizeof(dev::PathVertex) + sizeof(dev::GridPoint) + 32) * 100;
  test::expect_matches_reference(test::render_batches(test::cornell_box(), t, 16, 6800), cornell,
                                 "vcm 3 light paths, tiles");
  RenderSettings c = s;
  c.bdpt.lvc = 2;
  test::expect_matches_reference(test::render_batches(test::cornell_box(), c, 16, 6900), cornell,
                                 "vcm 3 light paths, lvc 2");
  // Per-pixel radii (as VcmWithPixelRadiiMatchesPt's). Not on the glossy-and-glass box: its
  // pt reference's caustic pixels are heavy-tailed (fireflies it has not yet seen), so vcm sits
  // above it there, |z| > 4 in 1 to 4 pixel-channels at K = 1 and 5 to 10 at K = 2 (three
  // seeds each, all positive, in the same pixels), while the image means agree (z 0.2).
  s.vcm.light_per_pixel = 2;
  s.vcm.pixel_radius = true;
  s.vcm.alpha = 0.6f;
  s.vcm.radius = 2.0f * kRadius;
  test::expect_matches_reference(test::render_batches(test::cornell_box(), s, 16, 7000), cornell,
                                 "vcm 2 light paths, pixel radii");
}

// Consistent: the error against pt's reference falls as passes add up and radii shrink,
// with the defaults (per-pixel radii from two pixel footprints, alpha 2/3, auto's K) and with
// the pass rule at r = 0.01.
TEST(CrossIntegrator, VcmErrorFallsWithPasses) {
  const FilmResult ref = test::pt_reference(test::ReferenceScene::CornellBox, kSize, 8192, 4242);
  RenderSettings defaults = test::render_settings("vcm", 16, kSize);
  RenderSettings pass_rule = vcm_settings(dev::VCM_MODE_VCM, 16);
  for (RenderSettings* s : {&defaults, &pass_rule}) {
    double previous = 0.0;
    for (uint64_t passes : {16u, 64u, 256u}) {
      s->spp = passes;
      const double rel_mse =
          compare_images(test::render(test::cornell_box(), *s, 8100).mean, ref.mean).rel_mse;
      std::cout << "[ figures  ] vcm cornell, " << (s == &defaults ? "defaults" : "pass rule")
                << ", " << passes << " passes: relMSE " << rel_mse << "\n";
      if (previous > 0.0) {
        EXPECT_LT(rel_mse, previous) << passes << " passes";
      }
      previous = rel_mse;
    }
  }
}

// --vcm-light-paths auto (the default): 16 passes at K = 1, the pilot's passes at 1, 2 and 4
// in turn, then its choice; each pass stays unbiased whatever its K, and the light subpaths
// draw consecutive sample indices over passes of any K (VcmParams.light_sample).
TEST(CrossIntegrator, VcmAutoLightPathsMatchesPt) {
  const FilmResult cornell =
      test::pt_reference(test::ReferenceScene::CornellBox, kSize, 8192, 4242);
  RenderSettings s = vcm_settings(dev::VCM_MODE_VCM, 64);
  s.vcm.light_per_pixel = 0;
  s.vcm.pixel_radius = true;
  s.vcm.alpha = 0.6f;
  s.vcm.radius = 2.0f * kRadius;
  s.seed = 7300;
  const RenderOutput one = Renderer(test::device_context(), test::cornell_box(), s).render();
  ASSERT_EQ(one.stats.vcm.pilot.size(), 3u);  // the pilot ran (64 passes: 16 + 9 + 39)
  test::expect_matches_reference(test::render_batches(test::cornell_box(), s, 16, 7400), cornell,
                                 "vcm auto light paths");
}

TEST(VcmUnits, RadiusAndEta) {
  EXPECT_FLOAT_EQ(VertexConnectionMerging::radius(0.1f, 0.75f, 0), 0.1f);
  EXPECT_NEAR(VertexConnectionMerging::radius(0.1f, 0.75f, 15), 0.1 * std::pow(16.0, -0.125), 1e-7);
  EXPECT_FLOAT_EQ(VertexConnectionMerging::radius(0.1f, 1.0f, 99), 0.1f);  // alpha 1: fixed
  VcmConfig c;
  c.mode = dev::VCM_MODE_VCM;
  const dev::VcmParams v = VertexConnectionMerging::pass_params(c, dev::MIS_POWER, 0.1f, 1000, 1023);
  const double eta = 3.14159265358979 * 0.01 * 1000;
  EXPECT_NEAR(v.mis_vm, eta * eta, 1e-4 * eta * eta);
  EXPECT_NEAR(v.mis_vc, 1.0 / (eta * eta), 1e-4 / (eta * eta));
  EXPECT_NEAR(v.vm_normalization, 1.0 / eta, 1e-6 / eta);
  EXPECT_FLOAT_EQ(v.inv_cell, 5.0f);
  c.mode = dev::VCM_MODE_BPT;
  EXPECT_EQ(VertexConnectionMerging::pass_params(c, dev::MIS_POWER, 0.1f, 1000, 1023).mis_vm, 0.0f);
  c.mode = dev::VCM_MODE_PPM;
  EXPECT_EQ(VertexConnectionMerging::pass_params(c, dev::MIS_POWER, 0.1f, 1000, 1023).mis_vc, 0.0f);
}

TEST(VcmOptions, BadValuesAreUsageErrors) {
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm"}), ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-mode", "ppm", "--vcm-radius",
                         "0.01", "--vcm-alpha", "0.5", "--bdpt-memory", "64"}),
            ExitCode::Ok);
  for (const char* mode : {"vcm", "bpt", "ppm", "lt", "pt"})
    EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-mode", mode}), ExitCode::Ok) << mode;
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-mode", "sppm"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-radius", "0"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-radius", "-1"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-alpha", "0"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-alpha", "1.5"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-shrink", "pass"}), ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-shrink", "pixel"}), ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-shrink", "ray"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-merge", "first"}), ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-merge", "all"}), ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-merge", "last"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "bdpt", "--vcm-merge", "all"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-light-paths", "4"}), ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-light-paths", "auto"}), ExitCode::Ok);
  for (const char* k : {"0", "-1", "65", "1.5", "two", "Auto", ""})
    EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--vcm-light-paths", k}), ExitCode::Usage)
        << k;
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "bdpt", "--vcm-light-paths", "2"}), ExitCode::Usage);
  // Per-pixel radii need every splat in one pixel: another filter takes the pass rule, and
  // asking for both is an error.
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--filter", "tent"}), ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--filter", "tent", "--vcm-shrink",
                         "pixel"}),
            ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--filter-radius", "1", "--vcm-shrink",
                         "pixel"}),
            ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "pt", "--vcm-shrink", "pass"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--variance"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--checkpoint", "c.ckpt"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--vcm-mode", "bpt"}), ExitCode::Usage);  // not vcm
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "sppm", "--vcm-merged"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "bdpt", "--vcm-radius", "0.1"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--bdpt-lvc", "2"}), ExitCode::Ok);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "pt", "--bdpt-lvc", "2"}), ExitCode::Usage);
  EXPECT_EQ(parse_error({"s.gltf", "--integrator", "vcm", "--bdpt-strategy", "2,2"}), ExitCode::Usage);
}

TEST(VcmCli, StatsFigures) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("clpt_vcm_cli_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string scene = std::string(CLPT_SOURCE_DIR) + "/scenes/cornell_box.gltf";
  auto run = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args = {"--integrator", "vcm", "--resolution", "24x16", "--spp", "4"};
    args.insert(args.end(), extra.begin(), extra.end());
    return test::run_clpt_stats(dir, name, scene, args);
  };
  const nlohmann::json a = run("a", {"--vcm-radius", "0.05", "--vcm-alpha", "0.5"});
  ASSERT_FALSE(a.is_null());
  const nlohmann::json& v = a["vcm"];
  EXPECT_EQ(v["mode"].get<std::string>(), "vcm");
  EXPECT_EQ(v["passes"].get<uint32_t>(), 4u);
  EXPECT_EQ(v["tiles_per_pass"].get<uint32_t>(), 1u);
  EXPECT_FLOAT_EQ(v["first_radius"].get<float>(), 0.05f);
  EXPECT_NEAR(v["last_radius"].get<float>(), 0.05 * std::pow(4.0, -0.25), 1e-6);  // pass 4
  EXPECT_GT(v["light_vertices"].get<uint64_t>(), 4u * 24u * 16u);  // most paths store several
  EXPECT_GT(v["merges"].get<uint64_t>(), 0u);
  EXPECT_GT(v["connections"].get<uint64_t>(), 4u * 24u * 16u);
  EXPECT_EQ(v["grids"].get<uint64_t>(), 4u);
  // The default rule with the box filter: per-pixel radii, which only shrink, and some do
  // (the lit pixels find light vertices within 0.05 in 4 passes).
  EXPECT_EQ(v["shrink"].get<std::string>(), "pixel");
  EXPECT_EQ(v["merge"].get<std::string>(), "first");  // the default
  const nlohmann::json& pr = v["pixel_radius"];
  EXPECT_LE(pr["min"].get<float>(), pr["mean"].get<float>());
  EXPECT_LE(pr["mean"].get<float>(), pr["max"].get<float>());
  EXPECT_LE(pr["max"].get<float>(), 0.05f);
  EXPECT_LT(pr["min"].get<float>(), 0.05f);
  const nlohmann::json p = run("p", {"--vcm-radius", "0.05", "--vcm-shrink", "pass"});
  ASSERT_FALSE(p.is_null());
  EXPECT_EQ(p["vcm"]["shrink"].get<std::string>(), "pass");
  const nlohmann::json e = run("e", {"--vcm-merge", "all"});
  ASSERT_FALSE(e.is_null());
  EXPECT_EQ(e["vcm"]["merge"].get<std::string>(), "all");
  // Merging at every vertex makes more merges than at the first alone (same paths).
  EXPECT_GT(e["vcm"]["merges"].get<uint64_t>(), run("f", {})["vcm"]["merges"].get<uint64_t>());
  // Three light subpaths per pixel store about three times the light vertices (same seed).
  const nlohmann::json k = run("k", {"--vcm-light-paths", "3"});
  ASSERT_FALSE(k.is_null());
  EXPECT_EQ(k["vcm"]["light_paths_per_pixel"].get<uint32_t>(), 3u);
  EXPECT_TRUE(k["vcm"]["light_paths_auto"].is_null());  // K given
  // The default, auto, in a render of 4 passes: too short for the pilot, K = 1.
  EXPECT_EQ(e["vcm"]["light_paths_per_pixel"].get<uint32_t>(), 1u);
  EXPECT_TRUE(e["vcm"]["light_paths_auto"]["chosen"].is_null());
  EXPECT_EQ(e["vcm"]["light_paths_auto"]["candidates"].size(), 0u);
  const double stored_ratio = double(k["vcm"]["light_vertices"].get<uint64_t>()) /
                              double(e["vcm"]["light_vertices"].get<uint64_t>());
  EXPECT_GT(stored_ratio, 2.7);
  EXPECT_LT(stored_ratio, 3.3);
  EXPECT_FLOAT_EQ(p["vcm"]["alpha"].get<float>(), 0.75f);
  EXPECT_FALSE(p["vcm"].contains("pixel_radius"));
  // --vcm-merged: an EXR layer with the part of each pixel that merging gave, a share of the
  // pixel (merges are weighted by MIS, all terms positive): between 0 and the pixel, some of
  // the image, not all of it.
  run("m", {"--vcm-radius", "0.05", "--vcm-merged"});
  const ImageChannels ch = read_image_channels(dir / "m.exr");
  const Image* merged = ch.layer("merged");
  ASSERT_NE(merged, nullptr);
  double sum = 0.0, merged_sum = 0.0;
  size_t above = 0;
  for (size_t i = 0; i < ch.image.rgb.size(); ++i) {
    sum += ch.image.rgb[i];
    merged_sum += merged->rgb[i];
    above += merged->rgb[i] < 0.0f || merged->rgb[i] > ch.image.rgb[i] * 1.0001f + 1e-7f;
  }
  EXPECT_EQ(above, 0u);
  EXPECT_GT(merged_sum, 0.001 * sum);
  EXPECT_LT(merged_sum, 0.9 * sum);
  std::cout << "[ figures  ] vcm Cornell box 24x16, r = 0.05: merging gave " << merged_sum / sum
            << " of the image\n";
  EXPECT_EQ(read_image_channels(dir / "a.exr").layer("merged"), nullptr);  // only when asked
  // A radius that would merge everything, or put everything in one cell, is refused.
  for (const char* r : {"1", "1e-9"}) {
    const test::RunResult bad = test::run_clpt({scene, "--device", "pocl", "--integrator", "vcm",
                                                "--resolution", "8x8", "--spp", "1", "-q",
                                                "--vcm-radius", r, "-o",
                                                (dir / "bad.exr").string()});
    EXPECT_EQ(bad.exit_code, int(ExitCode::Usage)) << r << ": " << bad.err;
    EXPECT_NE(bad.err.find("--vcm-radius"), std::string::npos) << bad.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "bad.exr"));
  }
  // The default radius (a pixel footprint) is no usage error at a tiny resolution, where a
  // footprint is more than 10 % of the diagonal: it is held at the bound.
  const test::RunResult tiny = test::run_clpt({scene, "--device", "pocl", "--integrator", "vcm",
                                               "--resolution", "8x8", "--spp", "1", "-q", "-o",
                                               (dir / "tiny.exr").string(), "--stats",
                                               (dir / "tiny.json").string()});
  EXPECT_EQ(tiny.exit_code, 0) << tiny.err;
  std::ifstream tiny_stats(dir / "tiny.json");
  const nlohmann::json t = nlohmann::json::parse(tiny_stats, nullptr, false);
  ASSERT_FALSE(t.is_discarded());
  EXPECT_NEAR(t["vcm"]["first_radius"].get<float>(), 0.1f * 0.96074f, 1e-3f);  // Cornell diagonal
  // auto in a render long enough for its pilot: 16 passes at K = 1, 3 passes each at 1, 2
  // and 4, then the choice (its figures in --stats).
  const nlohmann::json au = test::run_clpt_stats(
      dir, "auto", scene, {"--integrator", "vcm", "--resolution", "24x16", "--spp", "60"});
  ASSERT_FALSE(au.is_null());
  const nlohmann::json& pilot = au["vcm"]["light_paths_auto"];
  ASSERT_EQ(pilot["candidates"].size(), 3u);
  const uint32_t chosen = pilot["chosen"].get<uint32_t>();
  EXPECT_TRUE(chosen == 1 || chosen == 2 || chosen == 4) << chosen;
  EXPECT_EQ(au["vcm"]["light_paths_per_pixel"].get<uint32_t>(), chosen);
  EXPECT_EQ(au["vcm"]["passes"].get<uint32_t>(), 60u);
  double least = 1e300;
  for (size_t i = 0; i < 3; ++i) {
    const nlohmann::json& c = pilot["candidates"][i];
    EXPECT_EQ(c["k"].get<uint32_t>(), i == 0 ? 1u : i == 1 ? 2u : 4u);
    EXPECT_EQ(c["passes"].get<uint32_t>(), 3u);
    EXPECT_GT(c["seconds_per_pass"].get<double>(), 0.0);
    EXPECT_GT(c["relative_variance"].get<double>(), 0.0);
    EXPECT_NEAR(c["relmse_seconds"].get<double>(),
                c["relative_variance"].get<double>() * c["seconds_per_pass"].get<double>(),
                1e-9 * c["relmse_seconds"].get<double>());
    least = std::min(least, c["relmse_seconds"].get<double>());
  }
  EXPECT_EQ(pilot["candidates"][chosen == 1 ? 0 : chosen == 2 ? 1 : 2]["relmse_seconds"].get<double>(),
            least);
  // Without merging nothing merges and no grid is built.
  const nlohmann::json b = run("b", {"--vcm-mode", "bpt"});
  ASSERT_FALSE(b.is_null());
  EXPECT_EQ(b["vcm"]["merges"].get<uint64_t>(), 0u);
  EXPECT_EQ(b["vcm"]["grids"].get<uint64_t>(), 0u);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace clpt::vcm_test
