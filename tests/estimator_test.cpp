// Every estimator choice of the path tracer converges to the same answer: the sphere
// furnace's closed form, for a covering set of option combinations.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <ostream>

#include "render/renderer.h"
#include "support/device.h"
#include "support/scenes.h"

namespace clpt {
namespace {

struct Combo {
  const char* name;
  uint32_t direct, mis, light_samples, hemisphere, rr;
  float rr_absorb;
  uint32_t branching, sampler;
};

void PrintTo(const Combo& c, std::ostream* os) { *os << c.name; }

class EstimatorFurnace : public ::testing::TestWithParam<Combo> {};

TEST_P(EstimatorFurnace, MatchesClosedForm) {
  const Combo c = GetParam();
  constexpr float kRho = 0.8f;
  constexpr unsigned kDepth = 5;
  const Scene scene = test::furnace_scene(kRho, 1.0f);
  const double expected = test::furnace_radiance(kRho, 1.0, kDepth);
  constexpr int kBatches = 10;
  std::vector<double> means;
  for (int b = 0; b < kBatches; ++b) {
    RenderSettings s;
    s.width = s.height = 16;
    s.spp = 16;
    s.max_depth = kDepth;
    s.seed = 77 + b;
    s.direct = c.direct;
    s.mis = c.mis;
    s.light_samples = c.light_samples;
    s.hemisphere = c.hemisphere;
    s.rr = c.rr;
    s.rr_absorb = c.rr_absorb;
    s.branching = c.branching;
    s.sampler = c.sampler;
    Renderer r(test::device_context(), scene, s);
    const RenderOutput out = r.render();
    ASSERT_EQ(out.film.dropped_samples, 0u);
    double sum = 0.0;
    for (float v : out.film.mean.rgb) sum += v;
    means.push_back(sum / double(out.film.mean.rgb.size()));
  }
  const double mean = std::accumulate(means.begin(), means.end(), 0.0) / kBatches;
  double var = 0.0;
  for (double m : means) var += (m - mean) * (m - mean);
  const double sigma = std::sqrt(var / (kBatches - 1) / kBatches);
  ASSERT_GT(sigma, 0.0);
  const double z = (mean - expected) / sigma;
  EXPECT_LT(std::fabs(z), 4.0) << c.name << ": mean " << mean << " expected " << expected
                               << " sigma " << sigma;
  EXPECT_LT(4.0 * sigma, 0.03 * expected) << "too few samples for a meaningful test";
}

// d: direct, m: mis, n: light samples, h: hemisphere, rr, branching, sampler
INSTANTIATE_TEST_SUITE_P(
    Combos, EstimatorFurnace,
    ::testing::Values(
        Combo{"mis_power", dev::DIRECT_MIS, dev::MIS_POWER, 1, dev::HEMISPHERE_BSDF, dev::RR_THROUGHPUT, 0, 1, 0},
        Combo{"mis_balance", dev::DIRECT_MIS, dev::MIS_BALANCE, 1, dev::HEMISPHERE_BSDF, dev::RR_THROUGHPUT, 0, 1, 0},
        Combo{"light_only", dev::DIRECT_LIGHT, dev::MIS_POWER, 1, dev::HEMISPHERE_BSDF, dev::RR_THROUGHPUT, 0, 1, 0},
        Combo{"bsdf_only", dev::DIRECT_BSDF, dev::MIS_POWER, 1, dev::HEMISPHERE_BSDF, dev::RR_THROUGHPUT, 0, 1, 0},
        Combo{"mis_4_light_samples", dev::DIRECT_MIS, dev::MIS_POWER, 4, dev::HEMISPHERE_BSDF, dev::RR_THROUGHPUT, 0, 1, 0},
        Combo{"balance_3_light_samples", dev::DIRECT_MIS, dev::MIS_BALANCE, 3, dev::HEMISPHERE_BSDF, dev::RR_THROUGHPUT, 0, 1, 0},
        Combo{"uniform_hemisphere_mis", dev::DIRECT_MIS, dev::MIS_POWER, 1, dev::HEMISPHERE_UNIFORM, dev::RR_THROUGHPUT, 0, 1, 0},
        Combo{"uniform_hemisphere_bsdf_only", dev::DIRECT_BSDF, dev::MIS_POWER, 1, dev::HEMISPHERE_UNIFORM, dev::RR_THROUGHPUT, 0, 1, 0},
        Combo{"cosine_hemisphere_light_only", dev::DIRECT_LIGHT, dev::MIS_POWER, 2, dev::HEMISPHERE_COSINE, dev::RR_THROUGHPUT, 0, 1, 0},
        Combo{"rr_fixed_0_3", dev::DIRECT_MIS, dev::MIS_POWER, 1, dev::HEMISPHERE_BSDF, dev::RR_FIXED, 0.3f, 1, 0},
        Combo{"rr_fixed_0_7_uniform", dev::DIRECT_MIS, dev::MIS_BALANCE, 1, dev::HEMISPHERE_UNIFORM, dev::RR_FIXED, 0.7f, 1, 0},
        Combo{"branching_4", dev::DIRECT_MIS, dev::MIS_POWER, 1, dev::HEMISPHERE_BSDF, dev::RR_THROUGHPUT, 0, 4, 0},
        Combo{"branching_3_light_samples_2", dev::DIRECT_MIS, dev::MIS_BALANCE, 2, dev::HEMISPHERE_COSINE, dev::RR_FIXED, 0.5f, 3, 0},
        Combo{"sampler_stratified", dev::DIRECT_MIS, dev::MIS_POWER, 1, dev::HEMISPHERE_BSDF, dev::RR_THROUGHPUT, 0, 1, dev::SAMPLER_STRATIFIED},
        Combo{"sampler_lhs", dev::DIRECT_MIS, dev::MIS_POWER, 1, dev::HEMISPHERE_BSDF, dev::RR_THROUGHPUT, 0, 1, dev::SAMPLER_LHS},
        Combo{"sampler_sobol", dev::DIRECT_MIS, dev::MIS_POWER, 1, dev::HEMISPHERE_BSDF, dev::RR_THROUGHPUT, 0, 1, dev::SAMPLER_SOBOL}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace clpt

namespace clpt {
namespace {

// The planes are 2000 units wide on purpose: a ray leaving such a large triangle is where
// self-intersection shows (t's rounding error grows with the vertices' distance); before
// intersect_triangle rejected t below its error bound, this read 0.20 instead of 0.25.
// Ambient occlusion between two parallel planes h apart, seen from between them by an
// orthographic camera looking at the floor. A floor point's ray of polar angle theta meets
// the ceiling at h / cos(theta), so it is unoccluded within radius R exactly when
// cos(theta) < h / R: AO = (1/pi) * integral of cos over that cone = (h / R)^2.
TEST(AmbientOcclusion, SlabMatchesClosedForm) {
  constexpr float kH = 1.0f, kR = 2.0f, kSize = 1000.0f;
  Scene scene;
  Material m;
  test::Mesh floor, ceiling;
  floor.positions = {{-kSize, 0, -kSize}, {kSize, 0, -kSize}, {kSize, 0, kSize}, {-kSize, 0, kSize}};
  floor.triangles = {{0, 2, 1}, {0, 3, 2}};
  ceiling.positions = floor.positions;
  for (glm::vec3& p : ceiling.positions) p.y = kH;
  ceiling.triangles = {{0, 1, 2}, {0, 2, 3}};
  test::add_mesh(scene, floor, m);
  test::add_mesh(scene, ceiling, m);
  Camera cam;
  cam.type = Camera::Type::Orthographic;
  cam.xmag = cam.ymag = 1.0f;
  cam.camera_to_world = glm::mat4(glm::vec4(1, 0, 0, 0), glm::vec4(0, 0, -1, 0),
                                  glm::vec4(0, 1, 0, 0), glm::vec4(0, 0.5f * kH, 0, 1));
  scene.cameras.push_back(cam);

  constexpr int kBatches = 10;
  std::vector<double> means;
  for (int b = 0; b < kBatches; ++b) {
    RenderSettings s;
    s.width = s.height = 16;
    s.spp = 32;
    s.seed = 5 + b;
    s.integrator = "ao";
    s.ao_radius = kR;
    Renderer r(test::device_context(), scene, s);
    const RenderOutput out = r.render();
    double sum = 0.0;
    for (float v : out.film.mean.rgb) sum += v;
    means.push_back(sum / double(out.film.mean.rgb.size()));
  }
  const double expected = (kH / kR) * (kH / kR);
  const double mean = std::accumulate(means.begin(), means.end(), 0.0) / kBatches;
  double var = 0.0;
  for (double v : means) var += (v - mean) * (v - mean);
  const double sigma = std::sqrt(var / (kBatches - 1) / kBatches);
  EXPECT_LT(std::fabs(mean - expected), 4.0 * sigma) << "mean " << mean << " sigma " << sigma;
  EXPECT_LT(4.0 * sigma, 0.02) << "too few samples for a meaningful test";
}

}  // namespace
}  // namespace clpt
