// KHR_materials_iridescence's thin film (kernels/bsdf/thin_film.cl, through
// tests/kernels/thin_film_test.cl) against a spectral reference written here: the exact Airy
// amplitude sum r = r12 + T121 r23 e^(i delta) / (1 - r21 r23 e^(i delta)) of the same
// interfaces (Schlick magnitudes, phase shifts 0 or pi), |r|^2 at every 0.5 nm from 360 to
// 830 nm, weighted by the CIE 1931 colour matching functions as fitted by Wyman, Sloan and
// Shirley 2013 (JCGT 2(2), "Simple analytic approximations to the CIE XYZ colour matching
// functions", the multi-lobe fit), converted to linear Rec. 709 and divided by the RGB of
// the equal-energy white (so that a flat reflectance is grey, as in an RGB renderer). The kernel follows Belcour and Barla 2017: the same sum in Fourier form,
// two terms, the CMFs' transforms fitted by Gaussians. So the two differ by the kernel's
// truncation and by two independent CMF fits; a wrong optical path (a missing factor 2 or
// eta2), a wrong phase convention or a wrong angle inside the film each move colours by far
// more (the mutations noted in the commit that added this test).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <iostream>
#include <vector>

#include <glm/glm.hpp>

#include "support/thin_film.h"

namespace clpt::thin_film_test {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Point {
  double cos1, eta2, d, f0;
};

double schlick(double f0, double c) { return f0 + (1.0 - f0) * std::pow(1.0 - c, 5.0); }

// Wyman et al. 2013, piecewise Gaussians g(x; mu, s1, s2).
double lobe(double x, double mu, double s1, double s2) {
  const double t = (x - mu) / (x < mu ? s1 : s2);
  return std::exp(-0.5 * t * t);
}
glm::dvec3 cmf(double l) {
  return {1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7) -
              0.065 * lobe(l, 501.1, 20.4, 26.2),
          0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1),
          1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8)};
}

glm::dvec3 xyz_to_rec709(glm::dvec3 c) {
  return {3.2404542 * c.x - 1.5371385 * c.y - 0.4985314 * c.z,
          -0.9692660 * c.x + 1.8760108 * c.y + 0.0415560 * c.z,
          0.0556434 * c.x - 0.2040259 * c.y + 1.0572252 * c.z};
}

// The film's spectral reflectance at wavelength l (nm).
double airy(const Point& p, double l) {
  const double sin2 = (1.0 - p.cos1 * p.cos1) / (p.eta2 * p.eta2);
  const double cos2 = std::sqrt(1.0 - sin2);
  const double r0 = (p.eta2 - 1.0) / (p.eta2 + 1.0);
  const double R12 = schlick(r0 * r0, p.cos1);
  const double s = std::sqrt(std::min(p.f0, 0.9999));
  const double eta3 = (1.0 + s) / (1.0 - s);
  const double r1 = (eta3 - p.eta2) / (eta3 + p.eta2);
  const double R23 = schlick(r1 * r1, cos2);
  const double phi12 = p.eta2 < 1.0 ? kPi : 0.0, phi21 = kPi - phi12;
  const double phi23 = eta3 < p.eta2 ? kPi : 0.0;
  using C = std::complex<double>;
  const C r12 = std::polar(std::sqrt(R12), phi12), r21 = std::polar(std::sqrt(R12), phi21);
  const C r23 = std::polar(std::sqrt(R23), phi23);
  const C e = std::polar(1.0, 2.0 * kPi * (2.0 * p.eta2 * p.d * cos2) / l);
  return std::norm(r12 + (1.0 - R12) * r23 * e / (1.0 - r21 * r23 * e));
}

glm::dvec3 reference(const Point& p) {
  glm::dvec3 xyz(0.0), white(0.0);
  for (double l = 360.0; l <= 830.0; l += 0.5) {
    const glm::dvec3 w = cmf(l);
    xyz += airy(p, l) * w;
    white += w;
  }
  return xyz_to_rec709(xyz) / xyz_to_rec709(white);
}

std::vector<glm::vec4> kernel(const std::vector<Point>& pts) {
  std::vector<glm::vec4> in;
  for (const Point& p : pts) in.emplace_back(float(p.cos1), float(p.eta2), float(p.d), float(p.f0));
  return test::thin_film_reflectance(in);
}

// Bounds on the largest channel difference over all points and on its mean (set from the
// kernel as committed: 0.066 and 0.0094, mostly the two CMF fits' difference at long optical
// paths; a path without its factor 2, 10 % too long, cos1 for cos2 or the phases swapped give
// largest 0.78-0.88 and mean 0.11-0.21).
constexpr double kMaxError = 0.1, kMeanError = 0.03;

// Films on dielectric and metallic bases, at normal to grazing incidence, thin to thick.
TEST(ThinFilm, MatchesTheSpectralAirySum) {
  std::vector<Point> pts;
  for (double cos1 : {1.0, 0.7, 0.4, 0.15})
    for (double eta2 : {1.3, 1.8})
      for (double d : {80.0, 200.0, 350.0, 500.0, 800.0, 1200.0})
        for (double f0 : {0.04, 0.5, 0.9}) pts.push_back({cos1, eta2, d, f0});
  const std::vector<glm::vec4> got = kernel(pts);
  double worst = 0.0, spread = 0.0, sum = 0.0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const Point& p = pts[i];
    const glm::dvec3 want = reference(p);
    const glm::dvec3 have = glm::dvec3(glm::vec3(got[i]));
    const glm::dvec3 diff = glm::abs(have - want);
    const double e = std::max({diff.x, diff.y, diff.z});
    worst = std::max(worst, e);
    sum += e;
    // How coloured the reference is: the test means something only where films are.
    spread = std::max(spread, std::max({want.x, want.y, want.z}) - std::min({want.x, want.y, want.z}));
    EXPECT_LT(e, kMaxError) << "cos " << p.cos1 << " eta2 " << p.eta2 << " d " << p.d << " f0 " << p.f0
                       << ": kernel (" << have.x << ", " << have.y << ", " << have.z << ") reference ("
                       << want.x << ", " << want.y << ", " << want.z << ")";
  }
  const double mean = sum / double(pts.size());
  std::cout << "[ thin film ] " << pts.size() << " points: |kernel - spectral Airy| largest " << worst
            << ", mean " << mean << "; largest channel spread of the reference " << spread << "\n";
  EXPECT_LT(mean, kMeanError);
  EXPECT_GT(spread, 0.3) << "the points should include strongly coloured films";
}

// The kernel's own sum, term by term in double precision: R12 + Rs + 2 sum_m C_m S(m opd,
// m phi) for m = 1 .. 4 with S the Gaussian fit of the CMFs' transform (Belcour and Barla
// 2017, the constants as the extension quotes them), each order's cos and exp evaluated
// directly. The kernel makes the orders by recurrences (thin_film_fringes); this says
// they are the same sum, up to float rounding (mutations: the cosine recurrence without its
// factor 2, or exp(-b)^(m^2) stepped by exp(-b)^2, fail it by 0.37 and 0.034).
glm::dvec3 fourier_sum(const Point& p) {
  const double c1 = std::clamp(p.cos1, 0.0, 1.0);
  const double sin2 = (1.0 - c1 * c1) / (p.eta2 * p.eta2);
  const double cos2 = std::sqrt(1.0 - sin2);
  const double r0 = (p.eta2 - 1.0) / (p.eta2 + 1.0);
  const double R12 = schlick(r0 * r0, c1), T121 = 1.0 - R12;
  const double phi21 = p.eta2 < 1.0 ? 0.0 : kPi;
  const double s = std::sqrt(std::clamp(p.f0, 0.0, 0.9999)), eta3 = (1.0 + s) / (1.0 - s);
  const double r1 = (eta3 - p.eta2) / (eta3 + p.eta2);
  const double R23 = schlick(r1 * r1, cos2);
  const double phi = phi21 + (eta3 < p.eta2 ? kPi : 0.0);
  const double opd = 2.0 * p.eta2 * p.d * cos2;
  const double R123 = std::clamp(R12 * R23, 1e-5, 0.9999), r123 = std::sqrt(R123);
  const double Rs = T121 * T121 * R23 / (1.0 - R123);
  const glm::dvec3 val(5.4856e-13, 4.4201e-13, 5.2481e-13), pos(1.6810e6, 1.7953e6, 2.2084e6),
      var(4.3278e9, 9.3046e9, 6.6121e9);
  const glm::dvec3 white(1.2053688, 0.9483195, 0.9100097);
  const double norm = 1.0 / 1.0685e-7;
  glm::dvec3 I(R12 + Rs);
  double Cm = Rs - T121;
  for (int m = 1; m <= 4; ++m) {
    Cm *= r123;
    const double phase = 2.0 * kPi * 1e-9 * m * opd, shift = m * phi;
    glm::dvec3 xyz;
    for (int c = 0; c < 3; ++c)
      xyz[c] = val[c] * norm * std::sqrt(2.0 * kPi * var[c]) * std::cos(pos[c] * phase + shift) *
               std::exp(-phase * phase * var[c]);
    xyz.x += 9.7470e-14 * norm * std::sqrt(2.0 * kPi * 4.5282e9) *
             std::cos(2.2399e6 * phase + shift) * std::exp(-4.5282e9 * phase * phase);
    I += 2.0 * Cm * xyz_to_rec709(xyz) / white;
  }
  return glm::clamp(I, 0.0, 1.0);
}

TEST(ThinFilm, OrdersAreTheFourierSumTermByTerm) {
  std::vector<Point> pts;
  for (double cos1 : {1.0, 0.8, 0.5, 0.25, 0.05})
    for (double eta2 : {1.2, 1.5, 2.0})
      for (double d = 10.0; d <= 1500.0; d *= 1.35)
        for (double f0 : {0.02, 0.3, 0.95}) pts.push_back({cos1, eta2, d, f0});
  const std::vector<glm::vec4> got = kernel(pts);
  double worst = 0.0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const Point& p = pts[i];
    const glm::dvec3 want = fourier_sum(p);
    const glm::dvec3 diff = glm::abs(glm::dvec3(glm::vec3(got[i])) - want);
    const double e = std::max({diff.x, diff.y, diff.z});
    worst = std::max(worst, e);
    EXPECT_LT(e, 1e-5) << "cos " << p.cos1 << " eta2 " << p.eta2 << " d " << p.d << " f0 " << p.f0;
  }
  std::cout << "[ thin film ] " << pts.size()
            << " points: |kernel - Fourier sum in double| largest " << worst << "\n";
}

// Thick films average their fringes away: the incoherent sum R12 + Rs, grey. Zero thickness
// is no film at all: the base's Schlick reflectance.
TEST(ThinFilm, ThickFilmsAreIncoherentAndNoFilmIsTheBase) {
  const std::vector<Point> pts = {{0.8, 1.5, 50000.0, 0.04}, {0.3, 1.3, 50000.0, 0.9},
                                  {0.8, 1.5, 0.0, 0.04},     {0.3, 1.3, 0.0, 0.9}};
  const std::vector<glm::vec4> got = kernel(pts);
  for (size_t i = 0; i < pts.size(); ++i) {
    const Point& p = pts[i];
    double want = schlick(p.f0, p.cos1);
    if (p.d > 0.0) {
      const double cos2 = std::sqrt(1.0 - (1.0 - p.cos1 * p.cos1) / (p.eta2 * p.eta2));
      const double r0 = (p.eta2 - 1.0) / (p.eta2 + 1.0);
      const double R12 = schlick(r0 * r0, p.cos1);
      const double s = std::sqrt(p.f0), eta3 = (1.0 + s) / (1.0 - s);
      const double r1 = (eta3 - p.eta2) / (eta3 + p.eta2);
      const double R23 = schlick(r1 * r1, cos2);
      want = R12 + (1.0 - R12) * (1.0 - R12) * R23 / (1.0 - R12 * R23);
    }
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(got[i][c], want, 2e-3) << "point " << i << " channel " << c;
  }
}

}  // namespace
}  // namespace clpt::thin_film_test
