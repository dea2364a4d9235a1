// The warps of kernels/core/warp.cl, run on the device through tests/kernels/warp_test.cl:
//   WarpChi2    ~1M samples of each warp against its own pdf function (Pearson chi-square,
//               Sidak alpha 0.01 over the suite), the pdf evaluated on the device;
//   WarpPdf     each pdf integrates to 1 over its support, is 0 off it and positive on it;
//   WarpInvert  sample -> invert returns u, invert -> sample returns the point (1e-3).
// And the chi-square harness itself (tests/support/chi2.*), on the host:
//   Chi2Harness calibrated under the null, and with the power to reject wrong pdfs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "support/chi2.h"
#include "kernels/warp_ids.h"
#include "support/device.h"

namespace clpt::warp_test {
namespace {

using test::Chi2Grid;
using test::Chi2Options;
using test::Chi2Result;
using test::PlaneDomain;
using test::SphereBins;

constexpr double kPi = 3.14159265358979323846;
constexpr uint32_t kSamples = 1u << 20;

// Significance per test: alpha 0.01 for the whole suite the running test belongs to.
double suite_alpha() {
  const ::testing::TestSuite* suite = ::testing::UnitTest::GetInstance()->current_test_suite();
  return test::sidak_alpha(0.01, suite ? suite->total_test_count() : 1);
}

void print_result(const Chi2Result& r) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::cout << "[ chi2     ] " << (info ? info->name() : "") << ": " << r.summary() << "\n";
}

// ---------------------------------------------------------------------------------------
// Device side

// The ids of tests/kernels/warp_test.cl, from the header both sides include.
enum class Warp : cl_int {
  UniformHemisphere = WARP_UNIFORM_HEMISPHERE,
  CosineHemisphere = WARP_COSINE_HEMISPHERE,
  UniformSphere = WARP_UNIFORM_SPHERE,
  UniformCone = WARP_UNIFORM_CONE,
  ConcentricDisk = WARP_CONCENTRIC_DISK,
  UniformDisk = WARP_UNIFORM_DISK,
  UniformTriangle = WARP_UNIFORM_TRIANGLE,
};

struct WarpCase {
  Warp warp;
  float param = 0.0f;  // cos_theta_max of the cone
};

bool is_direction(Warp w) {
  return w == Warp::UniformHemisphere || w == Warp::CosineHemisphere || w == Warp::UniformSphere ||
         w == Warp::UniformCone;
}

// u.y is an azimuth: 0 and 1 are the same point.
bool periodic_v(Warp w) {
  return w == Warp::UniformHemisphere || w == Warp::UniformSphere || w == Warp::UniformCone ||
         w == Warp::UniformDisk;
}

// The support's band of cos(theta) for directions.
double support_z_min(const WarpCase& c) {
  switch (c.warp) {
    case Warp::UniformSphere: return -1.0;
    case Warp::UniformCone: return double(c.param);
    default: return 0.0;
  }
}

Chi2Grid support_grid(const WarpCase& c, int a_bins = 32, int b_bins = 64, int subdivisions = 1) {
  if (is_direction(c.warp)) {
    SphereBins bins;
    bins.z_bins = a_bins;
    bins.phi_bins = b_bins;
    bins.z_min = support_z_min(c);
    bins.subdivisions = subdivisions;
    return Chi2Grid::sphere(bins);
  }
  return Chi2Grid::plane(
      c.warp == Warp::UniformTriangle ? PlaneDomain::Triangle : PlaneDomain::Disk, a_bins, b_bins,
      subdivisions);
}

const cl::Program& warp_program() {
  return test::test_program("kernels/warp_test.cl");
}

std::vector<glm::vec4> sample_random(const WarpCase& c, uint32_t seed, uint32_t n) {
  cl::Context& ctx = test::device_context();
  cl::Buffer out(ctx, n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "warp samples");
  cl::Kernel kernel(warp_program(), "warp_sample_random");
  kernel.args(0, cl_int(c.warp), c.param, cl_uint(seed), out, cl_uint(n));
  kernel.launch(ctx, n);
  return out.read_vector<glm::vec4>(n);
}

std::vector<glm::vec4> sample_at(const WarpCase& c, const std::vector<glm::vec2>& u) {
  cl::Context& ctx = test::device_context();
  const cl_uint n = cl_uint(u.size());
  cl::Buffer in = cl::Buffer::from_vector(ctx, u);
  cl::Buffer out(ctx, n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "warp samples");
  cl::Kernel kernel(warp_program(), "warp_sample_at");
  kernel.args(0, cl_int(c.warp), c.param, in, out, n);
  kernel.launch(ctx, n);
  return out.read_vector<glm::vec4>(n);
}

std::vector<double> pdf_at(const WarpCase& c, const std::vector<glm::dvec3>& points) {
  cl::Context& ctx = test::device_context();
  const cl_uint n = cl_uint(points.size());
  std::vector<glm::vec4> p(n);
  for (size_t i = 0; i < n; ++i) p[i] = glm::vec4(glm::vec3(points[i]), 0.0f);
  cl::Buffer in = cl::Buffer::from_vector(ctx, p);
  cl::Buffer out(ctx, n * sizeof(float), CL_MEM_WRITE_ONLY, nullptr, "pdf values");
  cl::Kernel kernel(warp_program(), "warp_pdf_at");
  kernel.args(0, cl_int(c.warp), c.param, in, out, n);
  kernel.launch(ctx, n);
  const std::vector<float> values = out.read_vector<float>(n);
  return std::vector<double>(values.begin(), values.end());
}

std::vector<glm::vec2> invert_at(const WarpCase& c, const std::vector<glm::vec4>& points) {
  cl::Context& ctx = test::device_context();
  const cl_uint n = cl_uint(points.size());
  cl::Buffer in = cl::Buffer::from_vector(ctx, points);
  cl::Buffer out(ctx, n * sizeof(glm::vec2), CL_MEM_WRITE_ONLY, nullptr, "inverted samples");
  cl::Kernel kernel(warp_program(), "warp_invert_at");
  kernel.args(0, cl_int(c.warp), c.param, in, out, n);
  kernel.launch(ctx, n);
  return out.read_vector<glm::vec2>(n);
}

// ---------------------------------------------------------------------------------------
// WarpChi2

void expect_chi2(const WarpCase& c, uint32_t seed, const Chi2Grid& grid,
                 uint32_t samples = kSamples) {
  Chi2Options options;
  options.alpha = suite_alpha();
  const Chi2Result r =
      test::chi2_test(grid, sample_random(c, seed, samples), pdf_at(c, grid.nodes()), options);
  print_result(r);
  EXPECT_TRUE(r.passed) << r.report;
}

void expect_chi2(const WarpCase& c, uint32_t seed) { expect_chi2(c, seed, support_grid(c)); }

TEST(WarpChi2, UniformHemisphere) { expect_chi2({Warp::UniformHemisphere}, 1); }
TEST(WarpChi2, CosineHemisphere) { expect_chi2({Warp::CosineHemisphere}, 2); }
TEST(WarpChi2, UniformSphere) { expect_chi2({Warp::UniformSphere}, 3); }
TEST(WarpChi2, UniformConeNarrow) { expect_chi2({Warp::UniformCone, 0.999f}, 4); }
TEST(WarpChi2, UniformConeHalf) { expect_chi2({Warp::UniformCone, 0.5f}, 5); }
TEST(WarpChi2, UniformConeWide) { expect_chi2({Warp::UniformCone, -0.3f}, 6); }
TEST(WarpChi2, ConcentricDisk) { expect_chi2({Warp::ConcentricDisk}, 7); }
TEST(WarpChi2, UniformDisk) { expect_chi2({Warp::UniformDisk}, 8); }
TEST(WarpChi2, UniformTriangle) { expect_chi2({Warp::UniformTriangle}, 9); }

// Grazing directions of the cosine hemisphere, cos(theta) < 0.1, where the density goes to
// 0: 1% of the samples, so 4M of them, binned finely in that band; the rest of the
// hemisphere is one more cell.
TEST(WarpChi2, CosineHemisphereGrazing) {
  SphereBins bins;
  bins.z_bins = 16;
  bins.phi_bins = 32;
  bins.z_min = 0.0;
  bins.z_max = 0.1;
  expect_chi2({Warp::CosineHemisphere}, 10, Chi2Grid::sphere(bins), 4 * kSamples);
}

// ---------------------------------------------------------------------------------------
// WarpPdf

// A point of the support, uniformly by area or solid angle, computed independently of the
// warps (rejection for the triangle).
glm::vec4 support_point(const WarpCase& c, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const double phi = 2.0 * kPi * U(rng);
  if (is_direction(c.warp)) {
    const double z0 = support_z_min(c);
    const double z = z0 + (1.0 - z0) * U(rng);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return glm::vec4(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z), 0.0f);
  }
  if (c.warp == Warp::UniformTriangle) {
    for (;;) {
      const double b1 = U(rng), b2 = U(rng);
      if (b1 + b2 <= 1.0) return glm::vec4(float(b1), float(b2), 0.0f, 0.0f);
    }
  }
  const double r = std::sqrt(U(rng));
  return glm::vec4(float(r * std::cos(phi)), float(r * std::sin(phi)), 0.0f, 0.0f);
}

// Points (directions, or planar points) strictly off the support, where the pdf must be 0.
std::vector<glm::dvec3> off_support(const WarpCase& c, size_t n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<glm::dvec3> p;
  while (p.size() < n) {
    if (is_direction(c.warp)) {
      const double z_max = support_z_min(c) - 1e-4;  // below the support, with a margin
      if (z_max <= -1.0) return p;                   // the whole sphere is the support
      const double z = -1.0 + (z_max + 1.0) * U(rng), phi = 2.0 * kPi * U(rng);
      const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
      p.push_back({r * std::cos(phi), r * std::sin(phi), z});
    } else {
      const glm::dvec3 q(-2.0 + 4.0 * U(rng), -2.0 + 4.0 * U(rng), 0.0);
      const bool outside = c.warp == Warp::UniformTriangle
                               ? (q.x < -1e-4 || q.y < -1e-4 || q.x + q.y > 1.0 + 1e-4)
                               : q.x * q.x + q.y * q.y > 1.0 + 1e-4;
      if (outside) p.push_back(q);
    }
  }
  return p;
}

void expect_pdf_normalised(const WarpCase& c) {
  // Over the whole domain (for directions the sphere: the support band and the rest), on a
  // finer quadrature than the chi-square tests use: 64 x 64 cells of 2 x 2 x 16 nodes.
  const Chi2Grid grid = support_grid(c, 64, 64, 2);
  const double integral = grid.integral(pdf_at(c, grid.nodes()));
  std::cout << "[ pdf      ] integral " << std::setprecision(9) << integral << "\n";
  EXPECT_NEAR(integral, 1.0, 1e-3);

  std::mt19937_64 rng(17);
  std::vector<glm::dvec3> on(10000);
  for (glm::dvec3& p : on) p = glm::dvec3(support_point(c, rng));
  const std::vector<double> on_values = pdf_at(c, on);
  EXPECT_EQ(std::count_if(on_values.begin(), on_values.end(), [](double v) { return !(v > 0.0); }),
            0)
      << "the pdf is not positive everywhere on its support";

  const std::vector<glm::dvec3> off = off_support(c, 10000, rng);
  const std::vector<double> outside = pdf_at(c, off);
  size_t nonzero = 0;
  for (size_t i = 0; i < outside.size(); ++i) {
    if (outside[i] != 0.0 && nonzero++ == 0)
      ADD_FAILURE() << "pdf " << outside[i] << " off the support at (" << off[i].x << ", "
                    << off[i].y << ", " << off[i].z << ")";
  }
  EXPECT_EQ(nonzero, 0u) << "of " << outside.size() << " points off the support";
}

TEST(WarpPdf, UniformHemisphere) { expect_pdf_normalised({Warp::UniformHemisphere}); }
TEST(WarpPdf, CosineHemisphere) { expect_pdf_normalised({Warp::CosineHemisphere}); }
TEST(WarpPdf, UniformSphere) { expect_pdf_normalised({Warp::UniformSphere}); }
TEST(WarpPdf, UniformConeNarrow) { expect_pdf_normalised({Warp::UniformCone, 0.999f}); }
TEST(WarpPdf, UniformConeHalf) { expect_pdf_normalised({Warp::UniformCone, 0.5f}); }
TEST(WarpPdf, UniformConeWide) { expect_pdf_normalised({Warp::UniformCone, -0.3f}); }
TEST(WarpPdf, ConcentricDisk) { expect_pdf_normalised({Warp::ConcentricDisk}); }
TEST(WarpPdf, UniformDisk) { expect_pdf_normalised({Warp::UniformDisk}); }
TEST(WarpPdf, UniformTriangle) { expect_pdf_normalised({Warp::UniformTriangle}); }

// ---------------------------------------------------------------------------------------
// WarpInvert

void expect_invert_round_trips(const WarpCase& c) {
  constexpr size_t kPoints = 10000;
  constexpr double kTolerance = 1e-3;
  std::mt19937_64 rng(23);
  // Open interval, as the warps' own test samples: u = 0 may be a pole or rim where the
  // inverse is not unique.
  std::uniform_real_distribution<float> U(1e-6f, 1.0f - 1e-6f);

  // sample -> invert gives u back.
  std::vector<glm::vec2> u(kPoints);
  for (glm::vec2& v : u) v = glm::vec2(U(rng), U(rng));
  const std::vector<glm::vec2> back = invert_at(c, sample_at(c, u));
  double worst = 0.0;
  size_t worst_i = 0;
  for (size_t i = 0; i < kPoints; ++i) {
    double dx = std::fabs(double(back[i].x) - u[i].x), dy = std::fabs(double(back[i].y) - u[i].y);
    if (periodic_v(c.warp)) dy = std::min(dy, 1.0 - dy);
    const double e = std::isfinite(dx + dy) ? std::max(dx, dy) : HUGE_VAL;
    if (e > worst) {
      worst = e;
      worst_i = i;
    }
  }
  std::cout << "[ invert   ] u -> p -> u: max error " << worst << "\n";
  EXPECT_LE(worst, kTolerance) << "u (" << u[worst_i].x << ", " << u[worst_i].y
                               << ") came back as (" << back[worst_i].x << ", " << back[worst_i].y
                               << ")";

  // invert -> sample gives the point back.
  std::vector<glm::vec4> p(kPoints);
  for (glm::vec4& q : p) q = support_point(c, rng);
  const std::vector<glm::vec2> up = invert_at(c, p);
  const std::vector<glm::vec4> again = sample_at(c, up);
  worst = 0.0;
  worst_i = 0;
  size_t off_square = 0;
  for (size_t i = 0; i < kPoints; ++i) {
    const glm::vec3 d = glm::abs(glm::vec3(again[i]) - glm::vec3(p[i]));
    const double e = std::isfinite(d.x + d.y + d.z) ? double(std::max({d.x, d.y, d.z})) : HUGE_VAL;
    if (!(up[i].x >= 0.0f && up[i].x <= 1.0f && up[i].y >= 0.0f && up[i].y <= 1.0f) &&
        off_square++ == 0)
      ADD_FAILURE() << "invert left the unit square: (" << up[i].x << ", " << up[i].y << ")";
    if (e > worst) {
      worst = e;
      worst_i = i;
    }
  }
  std::cout << "[ invert   ] p -> u -> p: max error " << worst << "\n";
  EXPECT_EQ(off_square, 0u) << "inverted points outside [0,1]^2";
  EXPECT_LE(worst, kTolerance) << "(" << p[worst_i].x << ", " << p[worst_i].y << ", "
                               << p[worst_i].z << ") came back as (" << again[worst_i].x << ", "
                               << again[worst_i].y << ", " << again[worst_i].z << ")";
}

TEST(WarpInvert, UniformHemisphere) { expect_invert_round_trips({Warp::UniformHemisphere}); }
TEST(WarpInvert, CosineHemisphere) { expect_invert_round_trips({Warp::CosineHemisphere}); }
TEST(WarpInvert, UniformSphere) { expect_invert_round_trips({Warp::UniformSphere}); }
TEST(WarpInvert, UniformConeNarrow) { expect_invert_round_trips({Warp::UniformCone, 0.999f}); }
TEST(WarpInvert, UniformConeHalf) { expect_invert_round_trips({Warp::UniformCone, 0.5f}); }
TEST(WarpInvert, UniformConeWide) { expect_invert_round_trips({Warp::UniformCone, -0.3f}); }
TEST(WarpInvert, ConcentricDisk) { expect_invert_round_trips({Warp::ConcentricDisk}); }
TEST(WarpInvert, UniformDisk) { expect_invert_round_trips({Warp::UniformDisk}); }
TEST(WarpInvert, UniformTriangle) { expect_invert_round_trips({Warp::UniformTriangle}); }

// ---------------------------------------------------------------------------------------
// WarpTrig: core/math.cl's cos_sin_turns, the warps' (cos, sin) of 2 pi t, against double
// precision: over four periods, at every quadrant's and octant's edges and their float
// neighbours, and densely near 0, where sin must keep its relative accuracy.

std::vector<glm::vec2> cos_sin_turns_at(const std::vector<float>& t) {
  cl::Context& ctx = test::device_context();
  const cl_uint n = cl_uint(t.size());
  cl::Buffer in = cl::Buffer::from_vector(ctx, t);
  cl::Buffer out(ctx, n * sizeof(glm::vec2), CL_MEM_WRITE_ONLY, nullptr, "cos and sin");
  cl::Kernel kernel(warp_program(), "cos_sin_turns_at");
  kernel.args(0, in, out, n);
  kernel.launch(ctx, n);
  return out.read_vector<glm::vec2>(n);
}

TEST(WarpTrig, CosSinTurnsMatchesDoublePrecision) {
  std::vector<float> t;
  for (int i = -(1 << 20); i <= (1 << 20); ++i) t.push_back(float(i) * 0x1.0p-18f);  // [-4, 4]
  for (int k = -32; k <= 32; ++k) {  // eighths of a turn, and the floats beside them
    const float e = float(k) * 0.125f;
    t.push_back(e);
    t.push_back(std::nextafter(e, -10.0f));
    t.push_back(std::nextafter(e, 10.0f));
  }
  for (float x = 0x1.0p-40f; x < 0.1f; x *= 1.01f) {
    t.push_back(x);
    t.push_back(-x);
    t.push_back(0.5f - x);  // sin near its zero at half a turn
    t.push_back(0.25f - x);  // cos near its zero at a quarter turn
  }
  t.push_back(1000.3f);  // far from 0, where t itself is coarse
  const std::vector<glm::vec2> cs = cos_sin_turns_at(t);
  double worst_abs = 0.0, worst_ulp = 0.0;
  float worst_t = 0.0f;
  for (size_t i = 0; i < t.size(); ++i) {
    // The reference reduces as exactly in double (t - q/4 has no rounding error), so that
    // its own error near the zeros of sin and cos away from t = 0 stays far below a float's.
    const double q = std::nearbyint(4.0 * double(t[i])), r = double(t[i]) - 0.25 * q;
    const double cr = std::cos(2.0 * kPi * r), sr = std::sin(2.0 * kPi * r);
    const int quadrant = int(std::fmod(std::fmod(q, 4.0) + 4.0, 4.0));
    const double c = quadrant == 0 ? cr : quadrant == 1 ? -sr : quadrant == 2 ? -cr : sr;
    const double s = quadrant == 0 ? sr : quadrant == 1 ? cr : quadrant == 2 ? -sr : -cr;
    const double err = std::max(std::fabs(cs[i].x - c), std::fabs(cs[i].y - s));
    // In units of the float spacing at the exact value: both sin and cos relative where they
    // are small (the spacing of a value below 2^-126 is the subnormal one).
    auto ulps = [](double got, double want) {
      const float w = float(std::fabs(want));
      const double spacing = double(std::nextafter(w, 2.0f)) - double(w);
      return std::fabs(got - want) / spacing;
    };
    const double u = std::max(ulps(cs[i].x, c), ulps(cs[i].y, s));
    if (u > worst_ulp) worst_t = t[i];
    worst_abs = std::max(worst_abs, err);
    worst_ulp = std::max(worst_ulp, u);
  }
  std::cout << "[ trig     ] " << t.size() << " arguments: max error " << worst_abs << ", "
            << worst_ulp << " ulp (at t = " << worst_t << ")\n";
  EXPECT_LT(worst_abs, 1.2e-7);
  // OpenCL C 1.2 allows sin and cos 4 ulp; the polynomials measure within 2 (math.cl).
  EXPECT_LE(worst_ulp, 4.0);
}

// WarpLog: core/math.cl's ln_positive (the Metropolis small steps' Gaussian magnitude) against
// double precision: every float of [1/2, 2) at a stride, the edges of its reduction at
// sqrt(1/2) and sqrt(2) and their neighbours, and every power of two of the normal range with
// floats beside it.

std::vector<float> ln_positive_at(const std::vector<float>& x) {
  cl::Context& ctx = test::device_context();
  const cl_uint n = cl_uint(x.size());
  cl::Buffer in = cl::Buffer::from_vector(ctx, x);
  cl::Buffer out(ctx, n * sizeof(float), CL_MEM_WRITE_ONLY, nullptr, "ln");
  cl::Kernel kernel(warp_program(), "ln_positive_at");
  kernel.args(0, in, out, n);
  kernel.launch(ctx, n);
  return out.read_vector<float>(n);
}

TEST(WarpLog, LnPositiveMatchesDoublePrecision) {
  std::vector<float> x;
  for (float v = 0.5f; v < 2.0f; v = std::nextafter(v, 3.0f)) {  // every 61st float of [1/2, 2)
    x.push_back(v);
    for (int k = 0; k < 60; ++k) v = std::nextafter(v, 3.0f);
  }
  for (const float edge : {0.70710678f, 1.41421356f, 1.0f}) {
    float lo = edge, hi = edge;
    for (int k = 0; k < 64; ++k) {
      x.push_back(lo);
      x.push_back(hi);
      lo = std::nextafter(lo, 0.0f);
      hi = std::nextafter(hi, 3.0f);
    }
  }
  for (int e = -126; e <= 127; ++e) {
    const float p = std::ldexp(1.0f, e);
    x.push_back(p);
    x.push_back(std::nextafter(p, 0.0f) >= FLT_MIN ? std::nextafter(p, 0.0f) : p);
    x.push_back(p * 1.3f < FLT_MAX ? p * 1.3f : p);
  }
  const std::vector<float> got = ln_positive_at(x);
  double worst_abs = 0.0, worst_ulp = 0.0;
  float worst_x = 0.0f;
  for (size_t i = 0; i < x.size(); ++i) {
    const double want = std::log(double(x[i]));
    const double err = std::fabs(double(got[i]) - want);
    // In units of the float spacing at the exact value (near x = 1, where ln x is small, the
    // relative accuracy matters: the Gaussian's magnitude is sqrt(-2 ln u)).
    const float w = float(std::fabs(want));
    const double spacing = w > 0.0f ? double(std::nextafter(w, 2.0f * w)) - double(w) : 0x1.0p-149;
    const double u = err / spacing;
    if (u > worst_ulp) worst_x = x[i];
    worst_abs = std::max(worst_abs, err);
    worst_ulp = std::max(worst_ulp, u);
  }
  std::cout << "[ log      ] " << x.size() << " arguments: max error " << worst_abs << ", "
            << worst_ulp << " ulp (at x = " << worst_x << ")\n";
  // OpenCL C 1.2 allows log 3 ulp (native_log any); PoCL measures 0.83, and the bound leaves
  // room for a GPU's division (2.5 ulp), whose error reaches the result through s alone.
  EXPECT_LE(worst_ulp, 2.0);
}

// ---------------------------------------------------------------------------------------
// Chi2Harness: host samples in double from std::mt19937_64, host pdfs.

using Pdf = std::function<double(const glm::dvec3&)>;

template <class F>
std::vector<glm::vec4> host_samples(size_t n, uint64_t seed, F&& warp) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<glm::vec4> s(n);
  for (glm::vec4& v : s) {
    const double a = U(rng), b = U(rng);
    v = glm::vec4(glm::vec3(warp(a, b)), 0.0f);
  }
  return s;
}

glm::dvec3 polar_direction(double z, double phi) {
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

std::vector<glm::vec4> uniform_hemisphere_samples(size_t n, uint64_t seed) {
  return host_samples(n, seed, [](double a, double b) { return polar_direction(a, 2 * kPi * b); });
}
std::vector<glm::vec4> cosine_hemisphere_samples(size_t n, uint64_t seed) {
  return host_samples(
      n, seed, [](double a, double b) { return polar_direction(std::sqrt(a), 2 * kPi * b); });
}
std::vector<glm::vec4> uniform_sphere_samples(size_t n, uint64_t seed) {
  return host_samples(n, seed,
                      [](double a, double b) { return polar_direction(1 - 2 * a, 2 * kPi * b); });
}

const Pdf kUniformSpherePdf = [](const glm::dvec3&) { return 1.0 / (4.0 * kPi); };
const Pdf kCosinePdf = [](const glm::dvec3& w) { return w.z > 0.0 ? w.z / kPi : 0.0; };
// cos^n(theta) normalised over the hemisphere.
Pdf cosine_power_pdf(double n) {
  return [n](const glm::dvec3& w) {
    return w.z > 0.0 ? (n + 1.0) / (2.0 * kPi) * std::pow(w.z, n) : 0.0;
  };
}

Chi2Grid hemisphere_grid() {
  SphereBins bins;
  bins.z_min = 0.0;
  return Chi2Grid::sphere(bins);
}

Chi2Options suite_options() {
  Chi2Options o;
  o.alpha = suite_alpha();
  return o;
}

TEST(Chi2Harness, PValuesAndSidak) {
  // Textbook critical values at 5 % and 0.1 %.
  EXPECT_NEAR(test::chi2_p_value(3.841459, 1), 0.05, 1e-6);
  EXPECT_NEAR(test::chi2_p_value(18.307038, 10), 0.05, 1e-6);
  EXPECT_NEAR(test::chi2_p_value(29.588298, 10), 0.001, 1e-7);
  EXPECT_NEAR(test::sidak_alpha(0.01, 1), 0.01, 1e-15);
  EXPECT_NEAR(test::sidak_alpha(0.01, 10), 1.0 - std::pow(0.99, 0.1), 1e-15);
  EXPECT_LT(test::sidak_alpha(0.01, 10), 0.01 / 10 * 1.01);
}

TEST(Chi2Harness, PoolsCellsExpectingFewerThanFive) {
  // Cells 1 and 2 expect 4 together: too few for a pooled cell, so they join the smallest
  // regular cell (expecting 6), which then observes 10 against 10.
  Chi2Options o;
  const Chi2Result r = test::chi2_counts({10, 0, 1, 9}, {10, 2, 2, 6}, o,
                                         [](size_t i) { return std::to_string(i); });
  EXPECT_EQ(r.cells, 2u);
  EXPECT_EQ(r.pooled_cells, 2u);
  EXPECT_EQ(r.dof, 1);
  EXPECT_DOUBLE_EQ(r.statistic, 0.0);
  // Enough for a pooled cell of its own: 3 cells, (5 - 6)^2 / 6 from the pool.
  const Chi2Result s = test::chi2_counts({10, 0, 5, 9, 20}, {10, 3, 3, 8, 20}, o,
                                         [](size_t i) { return std::to_string(i); });
  EXPECT_EQ(s.cells, 4u);
  EXPECT_EQ(s.dof, 3);
  EXPECT_NEAR(s.statistic, 1.0 / 6.0 + 1.0 / 8.0, 1e-12);
}

// Under the null the statistic is chi-square with the stated dof: its mean over 200
// independent tests is dof within 4 sigma, and p < 0.1 happens about 20 times in 200.
TEST(Chi2Harness, NullIsCalibrated) {
  SphereBins bins;
  bins.z_bins = 8;
  bins.phi_bins = 16;
  const Chi2Grid grid = Chi2Grid::sphere(bins);
  constexpr int kRuns = 200;
  double sum = 0.0;
  int small_p = 0, dof = 0;
  for (int run = 0; run < kRuns; ++run) {
    const Chi2Result r =
        test::chi2_test(grid, uniform_sphere_samples(10000, 1000 + run), kUniformSpherePdf);
    sum += r.statistic;
    small_p += r.p_value < 0.1;
    dof = r.dof;
  }
  ASSERT_EQ(dof, 127);
  const double mean = sum / kRuns, sigma = std::sqrt(2.0 * dof / kRuns);
  std::cout << "[ chi2     ] null: mean statistic " << mean << " (dof " << dof << "), p < 0.1 in "
            << small_p << " of " << kRuns << "\n";
  EXPECT_NEAR(mean, dof, 4.0 * sigma);
  // Binomial(200, 0.1): mean 20, sd 4.2.
  EXPECT_GE(small_p, 4);
  EXPECT_LE(small_p, 37);
}

TEST(Chi2Harness, AcceptsTheTruePdf) {
  const Chi2Result r = test::chi2_test(hemisphere_grid(), cosine_hemisphere_samples(kSamples, 1),
                                       kCosinePdf, suite_options());
  print_result(r);
  EXPECT_TRUE(r.passed) << r.report;
}

TEST(Chi2Harness, RejectsUniformSamplesClaimedCosine) {
  const Chi2Result r = test::chi2_test(hemisphere_grid(), uniform_hemisphere_samples(kSamples, 2),
                                       kCosinePdf, suite_options());
  print_result(r);
  EXPECT_FALSE(r.passed);
  EXPECT_LT(r.p_value, 1e-6) << r.report;
  EXPECT_NEAR(r.pdf_integral, 1.0, 1e-6);  // the chi-square, not the normalisation, rejects it
}

// Cosine samples against cos^1.1 normalised: a density at most ~10 % off. The expected
// statistic is about dof + 2500 at 1M samples (cos^1.05: dof + 620), well past any alpha.
TEST(Chi2Harness, RejectsSlightlyWrongPdf) {
  const std::vector<glm::vec4> samples = cosine_hemisphere_samples(kSamples, 3);
  const Chi2Grid grid = hemisphere_grid();
  const Chi2Result r = test::chi2_test(grid, samples, cosine_power_pdf(1.1), suite_options());
  print_result(r);
  EXPECT_NEAR(r.pdf_integral, 1.0, 1e-6);
  EXPECT_FALSE(r.passed);
  EXPECT_LT(r.p_value, 1e-6) << r.report;
  const Chi2Result r105 = test::chi2_test(grid, samples, cosine_power_pdf(1.05), suite_options());
  print_result(r105);
  EXPECT_FALSE(r105.passed) << r105.report;
}

TEST(Chi2Harness, RejectsUnnormalisedPdf) {
  // 0.5 % too much density: too little for the chi-square at 10^4 samples, caught by the
  // integral.
  const Pdf pdf = [](const glm::dvec3&) { return 1.005 / (4.0 * kPi); };
  const Chi2Result r =
      test::chi2_test(Chi2Grid::sphere(), uniform_sphere_samples(10000, 4), pdf, suite_options());
  EXPECT_FALSE(r.passed);
  EXPECT_NEAR(r.pdf_integral, 1.005, 1e-9);
  EXPECT_NE(r.report.find("integrates to"), std::string::npos) << r.report;
}

TEST(Chi2Harness, RejectsSamplesWherePdfIsZero) {
  // Samples over the whole sphere, a pdf on the upper hemisphere only: the lower half
  // lands where the pdf is 0.
  const Chi2Result r = test::chi2_test(hemisphere_grid(), uniform_sphere_samples(100000, 5),
                                       kCosinePdf, suite_options());
  EXPECT_FALSE(r.passed);
  EXPECT_GT(r.zero_pdf_samples, 45000u);
  EXPECT_LT(r.zero_pdf_samples, 55000u);
  EXPECT_NE(r.report.find("pdf is 0"), std::string::npos) << r.report;
}

// A pdf that is 0 only on the cap cos(theta) > 0.999 (and normalised without it): about
// 50 of 10^5 uniform samples fall there, far too few for the chi-square to notice; the
// check of the pdf at every sample must.
TEST(Chi2Harness, RejectsAFewSamplesWherePdfIsZero) {
  const Pdf capless = [](const glm::dvec3& w) {
    return w.z > 0.999 ? 0.0 : 1.0 / (4.0 * kPi * (1.0 - 0.0005));
  };
  const Chi2Result r = test::chi2_test(Chi2Grid::sphere(), uniform_sphere_samples(100000, 9),
                                       capless, suite_options());
  EXPECT_GE(r.p_value, r.alpha) << "the chi-square alone should not see this: " << r.report;
  EXPECT_NEAR(r.pdf_integral, 1.0, 1e-3);
  EXPECT_GT(r.zero_pdf_samples, 20u);
  EXPECT_FALSE(r.passed) << r.report;
}

TEST(Chi2Harness, RejectsPointsOffTheDomain) {
  std::vector<glm::vec4> samples = uniform_sphere_samples(10000, 6);
  samples[123] *= 1.01f;  // not a unit direction
  Chi2Result r = test::chi2_test(Chi2Grid::sphere(), samples, kUniformSpherePdf, suite_options());
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.outside_samples, 1u);
  EXPECT_NE(r.report.find("#123"), std::string::npos) << r.report;

  std::vector<glm::vec4> disk(1000, glm::vec4(0.1f, 0.2f, 0.0f, 0.0f));
  disk[7] = glm::vec4(0.8f, 0.8f, 0.0f, 0.0f);  // |p| > 1
  const Pdf disk_pdf = [](const glm::dvec3& p) {
    return p.x * p.x + p.y * p.y <= 1.0 ? 1.0 / kPi : 0.0;
  };
  r = test::chi2_test(Chi2Grid::plane(PlaneDomain::Disk, 4, 8), disk, disk_pdf, suite_options());
  EXPECT_EQ(r.outside_samples, 1u);
  EXPECT_FALSE(r.passed);
}

// The planar grids: each accepts points drawn uniformly by an independent method
// (rejection from a square), and rejects a warp that forgets a square root.
TEST(Chi2Harness, PlanarDomains) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto rejection = [&](PlaneDomain d) {
    std::vector<glm::vec4> s;
    while (s.size() < kSamples) {
      const double x = U(rng), y = U(rng);
      if (d == PlaneDomain::Square)
        s.emplace_back(x, y, 0, 0);
      else if (d == PlaneDomain::Triangle && x + y <= 1.0)
        s.emplace_back(x, y, 0, 0);
      else if (d == PlaneDomain::Disk) {
        const double px = 2 * x - 1, py = 2 * y - 1;
        if (px * px + py * py <= 1.0) s.emplace_back(px, py, 0, 0);
      }
    }
    return s;
  };
  const struct {
    PlaneDomain domain;
    double density;
  } domains[] = {
      {PlaneDomain::Square, 1.0}, {PlaneDomain::Disk, 1.0 / kPi}, {PlaneDomain::Triangle, 2.0}};
  for (const auto& d : domains) {
    const Pdf pdf = [&](const glm::dvec3&) { return d.density; };
    const Chi2Result r =
        test::chi2_test(Chi2Grid::plane(d.domain), rejection(d.domain), pdf, suite_options());
    print_result(r);
    EXPECT_TRUE(r.passed) << r.report;
  }
  // Disk points with r = u (no square root): too many near the centre.
  const std::vector<glm::vec4> bad_disk = host_samples(kSamples, 8, [](double a, double b) {
    return glm::dvec3(a * std::cos(2 * kPi * b), a * std::sin(2 * kPi * b), 0.0);
  });
  const Pdf disk_pdf = [](const glm::dvec3&) { return 1.0 / kPi; };
  const Chi2Result r = test::chi2_test(Chi2Grid::plane(PlaneDomain::Disk), bad_disk, disk_pdf);
  EXPECT_LT(r.p_value, 1e-6) << r.report;
  // Triangle points with s = u.x instead of sqrt(u.x).
  const std::vector<glm::vec4> bad_triangle = host_samples(
      kSamples, 9, [](double a, double b) { return glm::dvec3(a * (1 - b), a * b, 0.0); });
  const Pdf triangle_pdf = [](const glm::dvec3&) { return 2.0; };
  const Chi2Result t =
      test::chi2_test(Chi2Grid::plane(PlaneDomain::Triangle), bad_triangle, triangle_pdf);
  EXPECT_LT(t.p_value, 1e-6) << t.report;
}

}  // namespace
}  // namespace clpt::warp_test
