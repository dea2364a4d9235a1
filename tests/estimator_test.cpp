// Every estimator choice of the path tracer converges to the same answer: the sphere
// furnace's closed form, for a covering set of option combinations.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <ostream>

#include "render/renderer.h"
#include "stats/image_stats.h"
#include "support/device.h"
#include "support/scenes.h"

namespace clpt::estimator_test {
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
  std::vector<Image> batches;
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
    batches.push_back(out.film.mean);
  }
  const BatchMean bm = batch_mean(batches);
  const double mean = bm.mean, sigma = bm.sigma;
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
}  // namespace clpt::estimator_test

namespace clpt::estimator_test {
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
  std::vector<Image> batches;
  for (int b = 0; b < kBatches; ++b) {
    RenderSettings s;
    s.width = s.height = 16;
    s.spp = 32;
    s.seed = 5 + b;
    s.integrator = "ao";
    s.ao.radius = kR;
    Renderer r(test::device_context(), scene, s);
    const RenderOutput out = r.render();
    batches.push_back(out.film.mean);
  }
  const double expected = (kH / kR) * (kH / kR);
  const BatchMean bm = batch_mean(batches);
  const double mean = bm.mean, sigma = bm.sigma;
  EXPECT_LT(std::fabs(mean - expected), 4.0 * sigma) << "mean " << mean << " sigma " << sigma;
  EXPECT_LT(4.0 * sigma, 0.02) << "too few samples for a meaningful test";
}

}  // namespace
}  // namespace clpt::estimator_test

namespace clpt::estimator_test {
namespace {

// A floor lit by two emitters that each defeat one strategy: a dim 20 x 20 m emitter 0.2 m
// above it (uniform area sampling wastes samples on far points and meets a cos^2/d^2 peak
// nearby; cosine sampling is nearly ideal) and a 2 cm emitter of radiance 2000 (only light
// sampling finds it). An orthographic camera between floor and lights sees the floor only;
// max depth 1 isolates direct light. Measured per-sample variance, pooled over 4 seeds of
// 32 x 32 x 64 samples: power MIS ~1.2, light only ~11, BSDF only ~100 (power MIS won by at
// least 3x in every single seed). The balance heuristic is not asserted: its guarantee is
// against other weightings, not the single strategies, and one seed had it 12 % worse than
// light sampling here.
Scene two_light_floor() {
  Scene scene;
  Material floor_m, big, small;
  floor_m.base_color = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
  big.base_color = small.base_color = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  big.emission = glm::vec3(0.2f);
  small.emission = glm::vec3(2000.0f);
  auto quad = [](glm::vec3 c, float h, bool facing_down) {
    test::Mesh m;
    m.positions = {{c.x - h, c.y, c.z - h}, {c.x + h, c.y, c.z - h}, {c.x + h, c.y, c.z + h},
                   {c.x - h, c.y, c.z + h}};
    m.triangles = facing_down ? std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}}
                              : std::vector<glm::uvec3>{{0, 2, 1}, {0, 3, 2}};
    return m;
  };
  test::add_mesh(scene, quad({0, 0, 0}, 10.0f, false), floor_m);
  test::add_mesh(scene, quad({0, 0.2f, 0}, 10.0f, true), big);
  test::add_mesh(scene, quad({0.3f, 0.15f, 0.2f}, 0.01f, true), small);
  Camera cam;
  cam.type = Camera::Type::Orthographic;
  cam.xmag = cam.ymag = 1.0f;
  cam.camera_to_world = glm::mat4(glm::vec4(1, 0, 0, 0), glm::vec4(0, 0, -1, 0),
                                  glm::vec4(0, 1, 0, 0), glm::vec4(0, 0.1f, 0, 1));
  scene.cameras.push_back(cam);
  return scene;
}

double pooled_variance(const Scene& scene, uint32_t direct) {
  double sum = 0.0;
  size_t n = 0;
  for (uint32_t seed = 1; seed <= 4; ++seed) {
    RenderSettings s;
    s.width = s.height = 32;
    s.spp = 64;
    s.max_depth = 1;
    s.direct = direct;
    s.seed = seed;
    Renderer r(test::device_context(), scene, s);
    const RenderOutput out = r.render();
    for (float v : out.film.variance.rgb) sum += v;
    n += out.film.variance.rgb.size();
  }
  return sum / double(n);
}

TEST(MisVariance, PowerHeuristicNotWorseThanBetterStrategy) {
  const Scene scene = two_light_floor();
  const double mis = pooled_variance(scene, dev::DIRECT_MIS);
  const double light = pooled_variance(scene, dev::DIRECT_LIGHT);
  const double bsdf = pooled_variance(scene, dev::DIRECT_BSDF);
  std::cout << "per-sample variance: MIS " << mis << ", light " << light << ", BSDF " << bsdf << "\n";
  EXPECT_LT(mis, std::min(light, bsdf));
}

}  // namespace
}  // namespace clpt::estimator_test

namespace clpt::estimator_test {
namespace {

// ConvergenceRate: an unbiased estimator with independent samples has MSE proportional to
// 1/N, so relMSE(4N) / relMSE(N) = 1/4. Measured on the furnace, whose exact answer is the
// reference, pooled over 8 seeds; ../shared/TESTING.md asks for a ratio in [0.2, 0.3].
double furnace_relmse(uint64_t spp, uint32_t seed) {
  constexpr float kRho = 0.7f;
  constexpr unsigned kDepth = 4;
  static const Scene scene = test::furnace_scene(kRho, 1.0f);
  const double r = test::furnace_radiance(kRho, 1.0, kDepth);
  RenderSettings s;
  s.width = s.height = 24;
  s.spp = spp;
  s.max_depth = kDepth;
  s.seed = seed;
  Renderer renderer(test::device_context(), scene, s);
  const RenderOutput out = renderer.render();
  double sum = 0.0;
  for (float v : out.film.mean.rgb) sum += (v - r) * (v - r) / ((r + 0.01) * (r + 0.01));
  return sum / double(out.film.mean.rgb.size());
}

TEST(ConvergenceRate, IndependentSamplingQuartersRelMseAtFourTimesTheSamples) {
  double low = 0.0, high = 0.0;
  for (uint32_t seed = 0; seed < 8; ++seed) {
    low += furnace_relmse(8, 100 + seed);
    high += furnace_relmse(32, 200 + seed);
  }
  const double ratio = high / low;
  std::cout << "relMSE(32 spp) / relMSE(8 spp) = " << ratio << "\n";
  EXPECT_GT(ratio, 0.2);
  EXPECT_LT(ratio, 0.3);
}

}  // namespace
}  // namespace clpt::estimator_test
