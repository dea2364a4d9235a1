// Pixel reconstruction filters (camera/pixel_filter.cl, --filter; issue 24).
//
// PixelFilter.*: the default box of half a pixel hands the sampler's u through unchanged
// (images without --filter are bit for bit what they were), and every filter's map from u
// to the film offset is monotone (so a stratified sampler stays stratified).
// PixelFilterChi2.*: each filter's film offsets, drawn on the device from uniform u, follow
// the filter's density: Pearson's chi-square over 64 bins on [-r, r] against the filter's CDF
// computed here in double (box, tent and Blackman-Harris in closed form, the truncated
// Gaussian through std::erf), so an error in the kernel's inversion (Giles' erfinv, the
// Newton solve) shows.
// PixelFilterEdge.*: a measured edge. An emitting half-plane whose edge falls on a pixel
// boundary, rendered with --max-depth 0: a pixel whose centre lies d pixels inside the lit
// side must read CDF(d) (the share of its filter on the light), each column averaged over
// rows and samples, within a Sidak-corrected binomial bound; pixels farther than the radius
// from the edge read exactly 0 or 1, and the image's mean stays the box filter's.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "cl/buffer.h"
#include "cl/program.h"
#include "shared/render_types.h"
#include "support/chi2.h"
#include "support/device.h"
#include "support/render.h"
#include "support/scenes.h"

namespace clpt::pixel_filter_test {
namespace {

struct FilterCase {
  const char* name;
  uint32_t filter;
  float radius;
};

void PrintTo(const FilterCase& c, std::ostream* os) { *os << c.name << " r " << c.radius; }

const FilterCase kCases[] = {
    {"box", dev::FILTER_BOX, 0.5f},       {"box_wide", dev::FILTER_BOX, 1.5f},
    {"tent", dev::FILTER_TENT, 1.0f},     {"tent_wide", dev::FILTER_TENT, 2.5f},
    {"gaussian", dev::FILTER_GAUSSIAN, 1.5f}, {"gaussian_narrow", dev::FILTER_GAUSSIAN, 0.6f},
    {"blackman_harris", dev::FILTER_BLACKMAN_HARRIS, 2.0f},
    {"blackman_harris_wide", dev::FILTER_BLACKMAN_HARRIS, 3.0f},
};

// P(offset < x) for the filter of radius r, in double, written from the definitions.
double filter_cdf(uint32_t filter, double r, double x) {
  if (x <= -r) return 0.0;
  if (x >= r) return 1.0;
  switch (filter) {
    case dev::FILTER_TENT:
      return x < 0.0 ? (x + r) * (x + r) / (2.0 * r * r) : 1.0 - (r - x) * (r - x) / (2.0 * r * r);
    case dev::FILTER_GAUSSIAN: {
      const double sigma = r / 3.0, e = std::erf(r / (sigma * std::sqrt(2.0)));
      return 0.5 * (1.0 + std::erf(x / (sigma * std::sqrt(2.0))) / e);
    }
    case dev::FILTER_BLACKMAN_HARRIS: {
      const double a0 = 0.35875, a1 = 0.48829, a2 = 0.14128, a3 = 0.01168, tau = 2.0 * M_PI;
      const double t = (x + r) / (2.0 * r);
      return (a0 * t - a1 * std::sin(tau * t) / tau + a2 * std::sin(2 * tau * t) / (2 * tau) -
              a3 * std::sin(3 * tau * t) / (3 * tau)) /
             a0;
    }
    default:
      return (x + r) / (2.0 * r);
  }
}

std::vector<glm::vec2> jitters(const FilterCase& c, const std::vector<glm::vec2>& u) {
  cl::Context& ctx = test::device_context();
  const cl_uint n = cl_uint(u.size());
  cl::Buffer in = cl::Buffer::from_vector(ctx, u);
  cl::Buffer out(ctx, n * sizeof(glm::vec2), CL_MEM_WRITE_ONLY, nullptr, "filter jitter");
  cl::Kernel kernel(test::test_program("kernels/pixel_filter_test.cl"), "filter_jitter");
  kernel.args(0, cl_uint(c.filter), c.radius, in, out, n);
  kernel.launch(ctx, n);
  return out.read_vector<glm::vec2>(n);
}

TEST(PixelFilter, BoxOfHalfAPixelIsTheJitterItself) {
  std::vector<glm::vec2> u;
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  for (int i = 0; i < 4096; ++i) u.push_back({uni(rng), uni(rng)});
  u.push_back({0.0f, 0.99999994f});
  const std::vector<glm::vec2> j = jitters(kCases[0], u);
  for (size_t i = 0; i < u.size(); ++i) {
    ASSERT_EQ(j[i].x, u[i].x) << i;
    ASSERT_EQ(j[i].y, u[i].y) << i;
  }
}

TEST(PixelFilter, EveryFilterIsMonotoneAndInsideItsRadius) {
  std::vector<glm::vec2> u;
  for (int i = 0; i <= 20000; ++i) {
    const float v = std::min(float(i) / 20000.0f, 0.99999994f);
    u.push_back({v, 1.0f - v});
  }
  for (const FilterCase& c : kCases) {
    SCOPED_TRACE(c.name);
    const std::vector<glm::vec2> j = jitters(c, u);
    for (size_t i = 0; i < j.size(); ++i) {
      ASSERT_TRUE(std::isfinite(j[i].x) && std::isfinite(j[i].y)) << i;
      ASSERT_GE(j[i].x, 0.5f - c.radius - 1e-5f) << i;
      ASSERT_LE(j[i].x, 0.5f + c.radius + 1e-5f) << i;
      if (i) {
        ASSERT_GE(j[i].x, j[i - 1].x - 1e-5f) << "u " << u[i].x;  // x rises with u.x (float: 1e-5 px)
        ASSERT_LE(j[i].y, j[i - 1].y + 1e-5f) << "u " << u[i].y;  // y falls as u.y falls
      }
    }
  }
}

class PixelFilterChi2 : public ::testing::TestWithParam<FilterCase> {};

TEST_P(PixelFilterChi2, OffsetsFollowTheFilter) {
  const FilterCase c = GetParam();
  constexpr int kBins = 64;
  constexpr uint32_t kSamples = 200000;
  std::vector<glm::vec2> u(kSamples);
  std::mt19937 rng(7 + c.filter);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  for (glm::vec2& v : u) v = {uni(rng), uni(rng)};
  const std::vector<glm::vec2> j = jitters(c, u);
  const double r = c.radius;
  for (int axis = 0; axis < 2; ++axis) {
    SCOPED_TRACE(axis ? "y" : "x");
    std::vector<double> observed(kBins, 0.0), expected(kBins, 0.0);
    for (const glm::vec2& v : j) {
      const double x = double(axis ? v.y : v.x) - 0.5;
      const int b = std::clamp(int(std::floor((x + r) / (2.0 * r) * kBins)), 0, kBins - 1);
      observed[size_t(b)] += 1.0;
    }
    for (int b = 0; b < kBins; ++b) {
      const double lo = -r + 2.0 * r * b / kBins, hi = -r + 2.0 * r * (b + 1) / kBins;
      expected[size_t(b)] = kSamples * (filter_cdf(c.filter, r, hi) - filter_cdf(c.filter, r, lo));
    }
    // Bins expecting fewer than 5 samples (Blackman-Harris' ends) are pooled into one.
    double stat = 0.0, pooled_o = 0.0, pooled_e = 0.0;
    int cells = 0;
    for (int b = 0; b < kBins; ++b) {
      if (expected[size_t(b)] < 5.0) {
        pooled_o += observed[size_t(b)];
        pooled_e += expected[size_t(b)];
        continue;
      }
      const double d = observed[size_t(b)] - expected[size_t(b)];
      stat += d * d / expected[size_t(b)];
      ++cells;
    }
    if (pooled_e > 0.0) {
      stat += (pooled_o - pooled_e) * (pooled_o - pooled_e) / pooled_e;
      ++cells;
    }
    const double p = test::chi2_p_value(stat, cells - 1);
    // 8 cases x 2 axes.
    EXPECT_GE(p, test::sidak_alpha(0.01, 16)) << c.name << ": chi2 " << stat << " over " << cells << " cells";
  }
}

INSTANTIATE_TEST_SUITE_P(Filters, PixelFilterChi2, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<FilterCase>& i) { return std::string(i.param.name); });

// An emitting half-plane x < 0 at z = 0 (radiance 1; a 1.5 x 3 rectangle, beyond the view),
// a square camera on the z axis: the edge
// is the film's vertical centre line, a pixel boundary for an even width.
Scene half_plane_scene() {
  Scene scene;
  test::Mesh quad;
  // Just past the view (half a width of 4 tan(0.25) = 1.02 at z = 0): light tracing's
  // points on it then mostly land on the film.
  quad.positions = {{-1.5f, -1.5f, 0.0f}, {0.0f, -1.5f, 0.0f}, {0.0f, 1.5f, 0.0f}, {-1.5f, 1.5f, 0.0f}};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  Material light;
  light.base_color = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  light.metallic = 0.0f;
  light.emission = glm::vec3(1.0f);
  test::add_mesh(scene, quad, light);
  test::add_camera_on_z(scene, 4.0f, 0.5f);
  return scene;
}

constexpr uint32_t kEdgeSize = 32;

class PixelFilterEdge : public ::testing::TestWithParam<FilterCase> {};

TEST_P(PixelFilterEdge, EdgeProfileIsTheFiltersCdf) {
  const FilterCase c = GetParam();
  constexpr uint32_t kSize = kEdgeSize, kSpp = 256;
  RenderSettings s = test::render_settings("pt", kSpp, kSize);
  s.max_depth = 0;
  s.filter = c.filter;
  s.filter_radius = c.radius;
  const FilmResult film = test::render(half_plane_scene(), s, 3);

  // Per column: the mean over rows and channels, and the samples behind it.
  const double n = double(kSize) * kSpp;
  const double z = 4.5;  // two-sided 1e-5 per column: Sidak over the 8 cases' ~60 graded columns
  double mean_all = 0.0;
  for (uint32_t x = 0; x < kSize; ++x) {
    double sum = 0.0;
    for (uint32_t y = 0; y < kSize; ++y)
      for (int ch = 0; ch < 3; ++ch) sum += film.mean.rgb[(size_t(y) * kSize + x) * 3 + size_t(ch)];
    const double value = sum / (3.0 * kSize);
    mean_all += value / kSize;
    const double d = kSize / 2.0 - (x + 0.5);  // pixel centre's distance into the lit side
    const double expected = filter_cdf(c.filter, c.radius, d);
    if (expected == 0.0 || expected == 1.0) {
      EXPECT_EQ(value, expected) << c.name << " column " << x << " lies beyond the filter's reach";
      continue;
    }
    const double sigma = std::sqrt(expected * (1.0 - expected) / n);
    EXPECT_NEAR(value, expected, z * sigma + 1e-6) << c.name << " column " << x << " (d = " << d << ")";
  }
  // Every filter here is symmetric: the image's mean (half the columns lit) is one half.
  EXPECT_NEAR(mean_all, 0.5, z * std::sqrt(0.25 / (n * kSize / 4)) + 1e-6) << c.name;
}

INSTANTIATE_TEST_SUITE_P(Filters, PixelFilterEdge, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<FilterCase>& i) { return std::string(i.param.name); });

// The filter where integrators splat (film/splat_filter.cl): lt, bdpt, vcm and mlt must give
// the half-plane's edge the same profile, CDF(d), and a film filled by an emitter must stay
// 1 to its edges (each pixel's filter cut at the film's edge and renormalised; pt, by filter
// importance sampling, gives exactly 1 there). Splatted pixels have no per-pixel variance,
// so each column's mean is judged over 8 independent renders (Student-t, 7 degrees of
// freedom, Sidak-corrected over the columns and cases).
struct SplatCase {
  const char* integrator;
  FilterCase filter;
};

void PrintTo(const SplatCase& c, std::ostream* os) { *os << c.integrator << " " << c.filter.name; }

class PixelFilterSplat : public ::testing::TestWithParam<SplatCase> {};

// Column means (over rows and channels) of `batches` renders of `scene`.
std::vector<std::vector<double>> column_means(const Scene& scene, const SplatCase& c, uint64_t spp, int batches) {
  std::vector<std::vector<double>> out;
  for (int b = 0; b < batches; ++b) {
    RenderSettings s = test::render_settings(c.integrator, spp, kEdgeSize);
    s.max_depth = 0;
    s.filter = c.filter.filter;
    s.filter_radius = c.filter.radius;
    const FilmResult film = test::render(scene, s, 101 + uint32_t(b));
    std::vector<double> cols(kEdgeSize, 0.0);
    for (uint32_t y = 0; y < kEdgeSize; ++y)
      for (uint32_t x = 0; x < kEdgeSize; ++x)
        for (int ch = 0; ch < 3; ++ch) cols[x] += film.mean.rgb[(size_t(y) * kEdgeSize + x) * 3 + size_t(ch)];
    for (double& v : cols) v /= 3.0 * kEdgeSize;
    out.push_back(cols);
  }
  return out;
}

// |mean - expected| within the t-bound of the batches' spread (plus float slack).
void expect_columns(const std::vector<std::vector<double>>& batches, const std::function<double(uint32_t)>& expected,
                    const std::string& what) {
  const double t = 6.0;  // two-sided ~1e-4 at 7 dof: Sidak over ~20 cases x ~12 columns at 0.05 overall
  for (uint32_t x = 0; x < kEdgeSize; ++x) {
    double mean = 0.0, var = 0.0;
    for (const auto& b : batches) mean += b[x] / double(batches.size());
    for (const auto& b : batches) var += (b[x] - mean) * (b[x] - mean) / double(batches.size() - 1);
    const double se = std::sqrt(var / double(batches.size()));
    EXPECT_NEAR(mean, expected(x), t * se + 2e-3 * std::fabs(expected(x)) + 1e-6)
        << what << " column " << x << " (standard error " << se << ")";
  }
}

TEST_P(PixelFilterSplat, EdgeProfileIsTheFiltersCdf) {
  const SplatCase c = GetParam();
  const auto batches = column_means(half_plane_scene(), c, 32, 8);
  expect_columns(batches, [&](uint32_t x) {
    return filter_cdf(c.filter.filter, c.filter.radius, kEdgeSize / 2.0 - (x + 0.5));
  }, c.integrator);
}

TEST_P(PixelFilterSplat, AFilmFilledByLightStaysOneToItsEdges) {
  const SplatCase c = GetParam();
  Scene scene = half_plane_scene();
  for (glm::vec3& p : scene.positions) p.x = p.x < -1.0f ? p.x : 1.5f;  // the plane fills the view
  const auto batches = column_means(scene, c, 16, 8);
  expect_columns(batches, [](uint32_t) { return 1.0; }, c.integrator);
}

const SplatCase kSplatCases[] = {
    {"pt", kCases[4]},   {"pt", kCases[7]},   {"lt", kCases[4]},  {"lt", kCases[7]},
    {"bdpt", kCases[2]}, {"bdpt", kCases[4]}, {"vcm", kCases[6]}, {"mlt", kCases[4]},
};

INSTANTIATE_TEST_SUITE_P(Integrators, PixelFilterSplat, ::testing::ValuesIn(kSplatCases),
                         [](const ::testing::TestParamInfo<SplatCase>& i) {
                           return std::string(i.param.integrator) + "_" + i.param.filter.name;
                         });

}  // namespace
}  // namespace clpt::pixel_filter_test
