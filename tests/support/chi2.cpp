#include "support/chi2.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>

#include <boost/math/special_functions/gamma.hpp>

namespace clpt::test {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;
constexpr double kUnitTolerance = 1e-4;  // |length - 1| of a direction
constexpr double kPlaneSlack = 1e-6;     // float rounding at a planar domain's edge

// 4-point Gauss-Legendre rule on [-1, 1]: exact for polynomials of degree 7, and its nodes
// lie strictly inside the interval.
constexpr double kGaussX[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                               0.8611363115940526};
constexpr double kGaussW[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                               0.3478548451374538};

std::string format(const char* fmt, double a, double b, double c, double d) {
  char buf[160];
  std::snprintf(buf, sizeof(buf), fmt, a, b, c, d);
  return buf;
}

int clamp_bin(double x, int bins) {
  const int i = int(std::floor(x * bins));
  return std::min(std::max(i, 0), bins - 1);
}

double wrap_phi(double y, double x) {
  double phi = std::atan2(y, x);
  if (phi < 0.0) phi += kTwoPi;
  return phi >= kTwoPi ? 0.0 : phi;
}

}  // namespace

double sidak_alpha(double alpha, int m) {
  if (m < 1) throw std::invalid_argument("sidak_alpha: m must be at least 1");
  return -std::expm1(std::log1p(-alpha) / m);
}

double chi2_p_value(double statistic, int dof) {
  if (dof < 1 || !std::isfinite(statistic)) return 0.0;
  if (statistic <= 0.0) return 1.0;
  return boost::math::gamma_q(0.5 * dof, 0.5 * statistic);
}

// ---------------------------------------------------------------------------------------
// Grid

Chi2Grid Chi2Grid::sphere(const SphereBins& bins) {
  if (bins.z_bins < 1 || bins.phi_bins < 1 || bins.subdivisions < 1 || !(bins.z_min >= -1.0) ||
      !(bins.z_max <= 1.0) || !(bins.z_min < bins.z_max))
    throw std::invalid_argument("Chi2Grid::sphere: bad bins");
  Chi2Grid g;
  g.sphere_ = true;
  g.bins_ = bins;
  g.a_bins_ = bins.z_bins;
  g.b_bins_ = bins.phi_bins;
  const double dz = (bins.z_max - bins.z_min) / bins.z_bins;
  const double dphi = kTwoPi / bins.phi_bins;
  for (int i = 0; i < bins.z_bins; ++i) {
    const double z0 = bins.z_min + i * dz, z1 = (i + 1 == bins.z_bins) ? bins.z_max : z0 + dz;
    for (int j = 0; j < bins.phi_bins; ++j) {
      const double p0 = j * dphi, p1 = (j + 1) * dphi;
      g.add_cell(format("cos(theta) [%.5f, %.5f) phi [%.1f, %.1f) deg", z0, z1, p0 * 180 / kPi,
                        p1 * 180 / kPi),
                 z0, z1, p0, p1, bins.subdivisions, bins.subdivisions);
    }
  }
  // The rest of the sphere, one cell on each side, integrated finely so that a pdf leaking
  // outside the band shows in the integral.
  if (bins.z_min > -1.0)
    g.add_cell(format("cos(theta) < %.5f (outside the band)", bins.z_min, 0, 0, 0), -1.0,
               bins.z_min, 0.0, kTwoPi, 16 * bins.subdivisions, bins.phi_bins);
  if (bins.z_max < 1.0)
    g.add_cell(format("cos(theta) > %.5f (outside the band)", bins.z_max, 0, 0, 0), bins.z_max, 1.0,
               0.0, kTwoPi, 16 * bins.subdivisions, bins.phi_bins);
  return g;
}

Chi2Grid Chi2Grid::plane(PlaneDomain domain, int a_bins, int b_bins, int subdivisions) {
  if (a_bins < 1 || b_bins < 1 || subdivisions < 1)
    throw std::invalid_argument("Chi2Grid::plane: bad bins");
  Chi2Grid g;
  g.sphere_ = false;
  g.plane_ = domain;
  g.a_bins_ = a_bins;
  g.b_bins_ = b_bins;
  const double b_range = domain == PlaneDomain::Disk ? kTwoPi : 1.0;
  const char* fmt = domain == PlaneDomain::Square ? "x [%.4f, %.4f) y [%.4f, %.4f)"
                    : domain == PlaneDomain::Disk
                        ? "r^2 [%.4f, %.4f) phi [%.4f, %.4f) rad"
                        : "(b1+b2)^2 [%.4f, %.4f) b2/(b1+b2) [%.4f, %.4f)";
  for (int i = 0; i < a_bins; ++i) {
    const double a0 = double(i) / a_bins, a1 = double(i + 1) / a_bins;
    for (int j = 0; j < b_bins; ++j) {
      const double b0 = b_range * j / b_bins, b1 = b_range * (j + 1) / b_bins;
      g.add_cell(format(fmt, a0, a1, b0, b1), a0, a1, b0, b1, subdivisions, subdivisions);
    }
  }
  return g;
}

// A cell [a0, a1) x [b0, b1) of the domain's parameters, integrated with sub_a x sub_b
// sub-cells of 4 x 4 Gauss-Legendre nodes. Parameters and their measure:
//   sphere   a = z, b = phi             point (r cos phi, r sin phi, z)   d(omega) = da db
//   square   a = x, b = y                                                 dA = da db
//   disk     a = r^2, b = phi           point sqrt(a) (cos b, sin b)      dA = da db / 2
//   triangle a = s^2, b = t             point s (1 - t, t)                dA = da db / 2
void Chi2Grid::add_cell(std::string name, double a0, double a1, double b0, double b1, int sub_a,
                        int sub_b) {
  const uint32_t cell = uint32_t(cell_names_.size());
  cell_names_.push_back(std::move(name));
  const double jacobian = (!sphere_ && plane_ != PlaneDomain::Square) ? 0.5 : 1.0;
  const double ha = (a1 - a0) / sub_a, hb = (b1 - b0) / sub_b;
  for (int sa = 0; sa < sub_a; ++sa) {
    for (int sb = 0; sb < sub_b; ++sb) {
      const double ca = a0 + (sa + 0.5) * ha, cb = b0 + (sb + 0.5) * hb;
      for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
          const double a = ca + 0.5 * ha * kGaussX[i], b = cb + 0.5 * hb * kGaussX[j];
          glm::dvec3 p;
          if (sphere_) {
            const double r = std::sqrt(std::max(0.0, (1.0 - a) * (1.0 + a)));
            p = {r * std::cos(b), r * std::sin(b), a};
          } else if (plane_ == PlaneDomain::Square) {
            p = {a, b, 0.0};
          } else if (plane_ == PlaneDomain::Disk) {
            const double r = std::sqrt(a);
            p = {r * std::cos(b), r * std::sin(b), 0.0};
          } else {
            const double s = std::sqrt(a);
            p = {s * (1.0 - b), s * b, 0.0};
          }
          nodes_.push_back(p);
          weights_.push_back(0.25 * ha * hb * kGaussW[i] * kGaussW[j] * jacobian);
          node_cell_.push_back(cell);
        }
      }
    }
  }
}

std::vector<double> Chi2Grid::cell_mass(const std::vector<double>& pdf_at_nodes) const {
  if (pdf_at_nodes.size() != nodes_.size())
    throw std::invalid_argument("Chi2Grid: one pdf value per node expected");
  std::vector<double> mass(num_cells(), 0.0);
  for (size_t k = 0; k < nodes_.size(); ++k) mass[node_cell_[k]] += weights_[k] * pdf_at_nodes[k];
  return mass;
}

double Chi2Grid::integral(const std::vector<double>& pdf_at_nodes) const {
  const std::vector<double> mass = cell_mass(pdf_at_nodes);
  return std::accumulate(mass.begin(), mass.end(), 0.0);
}

double Chi2Grid::integral(const std::function<double(const glm::dvec3&)>& pdf) const {
  std::vector<double> values(nodes_.size());
  for (size_t k = 0; k < nodes_.size(); ++k) values[k] = pdf(nodes_[k]);
  return integral(values);
}

int64_t Chi2Grid::locate(const glm::dvec3& p) const {
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return -1;
  if (sphere_) {
    const double len = glm::length(p);
    if (!(std::fabs(len - 1.0) <= kUnitTolerance)) return -1;
    const double z = std::min(1.0, std::max(-1.0, p.z / len));
    const int64_t band = int64_t(a_bins_) * b_bins_;
    if (z < bins_.z_min) return band;
    if (z > bins_.z_max) return band + (bins_.z_min > -1.0 ? 1 : 0);
    const int i = clamp_bin((z - bins_.z_min) / (bins_.z_max - bins_.z_min), a_bins_);
    const int j = clamp_bin(wrap_phi(p.y, p.x) / kTwoPi, b_bins_);
    return int64_t(i) * b_bins_ + j;
  }
  if (p.z != 0.0) return -1;
  double a = 0.0, b = 0.0;
  switch (plane_) {
    case PlaneDomain::Square:
      if (p.x < -kPlaneSlack || p.x > 1.0 + kPlaneSlack || p.y < -kPlaneSlack ||
          p.y > 1.0 + kPlaneSlack)
        return -1;
      a = p.x;
      b = p.y;
      break;
    case PlaneDomain::Disk:
      a = p.x * p.x + p.y * p.y;
      if (a > 1.0 + kPlaneSlack) return -1;
      b = wrap_phi(p.y, p.x) / kTwoPi;
      break;
    case PlaneDomain::Triangle: {
      const double s = p.x + p.y;
      if (p.x < -kPlaneSlack || p.y < -kPlaneSlack || s > 1.0 + kPlaneSlack) return -1;
      a = s * s;
      b = s > 0.0 ? p.y / s : 0.0;
      break;
    }
  }
  return int64_t(clamp_bin(a, a_bins_)) * b_bins_ + clamp_bin(b, b_bins_);
}

// ---------------------------------------------------------------------------------------
// Statistic

std::string Chi2Result::summary() const {
  char buf[256];
  std::snprintf(buf, sizeof(buf),
                "chi2 %.1f, dof %d, p %.3g (alpha %.3g); %zu samples in %zu cells (%zu pooled); "
                "pdf integral %.6f",
                statistic, dof, p_value, alpha, samples, cells, pooled_cells, pdf_integral);
  return buf;
}

Chi2Result chi2_counts(const std::vector<double>& observed, const std::vector<double>& expected,
                       const Chi2Options& options, const std::function<std::string(size_t)>& name) {
  if (observed.size() != expected.size())
    throw std::invalid_argument("chi2_counts: observed and expected differ in length");
  Chi2Result r;
  r.alpha = options.alpha;
  r.samples = size_t(std::accumulate(observed.begin(), observed.end(), 0.0));

  // Cells expecting too few samples go into one pooled cell; if even that expects too few,
  // it joins the smallest regular cell, so every sample still counts.
  struct Cell {
    double observed = 0.0, expected = 0.0;
    std::string name;
  };
  std::vector<Cell> cells;
  Cell pool;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] < options.min_expected) {
      pool.observed += observed[i];
      pool.expected += expected[i];
      ++r.pooled_cells;
    } else {
      cells.push_back({observed[i], expected[i], name(i)});
    }
  }
  if (r.pooled_cells > 0) {
    pool.name = "pooled (" + std::to_string(r.pooled_cells) + " cells expecting < " +
                format("%g", options.min_expected, 0, 0, 0) + ")";
    if (pool.expected >= options.min_expected || cells.empty()) {
      cells.push_back(pool);
    } else {
      auto smallest =
          std::min_element(cells.begin(), cells.end(),
                           [](const Cell& a, const Cell& b) { return a.expected < b.expected; });
      smallest->observed += pool.observed;
      smallest->expected += pool.expected;
      smallest->name += " + " + pool.name;
    }
  }
  r.cells = cells.size();
  r.dof = int(cells.size()) - 1;

  std::vector<double> contribution(cells.size());
  bool empty_expectation = false;
  for (size_t i = 0; i < cells.size(); ++i) {
    const double d = cells[i].observed - cells[i].expected;
    if (cells[i].expected > 0.0) {
      contribution[i] = d * d / cells[i].expected;
    } else {
      contribution[i] = cells[i].observed > 0.0 ? HUGE_VAL : 0.0;
      empty_expectation = empty_expectation || cells[i].observed > 0.0;
    }
    r.statistic += contribution[i];
  }
  r.p_value = chi2_p_value(r.statistic, r.dof);
  r.passed = r.dof >= 1 && !empty_expectation && r.p_value >= options.alpha;

  r.report = r.summary() + "\n";
  if (r.dof < 1) r.report += "too few cells for a test: use more samples or fewer bins\n";
  if (!r.passed && !cells.empty()) {
    std::vector<size_t> order(cells.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return contribution[a] > contribution[b]; });
    r.report += "worst cells (observed, expected, (O - E) / sqrt(E)):\n";
    const size_t shown = std::min(order.size(), size_t(std::max(0, options.worst_cells)));
    for (size_t k = 0; k < shown; ++k) {
      const Cell& c = cells[order[k]];
      char line[128];
      std::snprintf(
          line, sizeof(line), "  %10.0f %12.2f %+9.2f  ", c.observed, c.expected,
          c.expected > 0.0 ? (c.observed - c.expected) / std::sqrt(c.expected) : HUGE_VAL);
      r.report += line + c.name + "\n";
    }
  }
  return r;
}

Chi2Result chi2_test(const Chi2Grid& grid, const std::vector<glm::vec4>& samples,
                     const std::vector<double>& pdf_at_nodes, const Chi2Options& options) {
  const std::vector<double> mass = grid.cell_mass(pdf_at_nodes);
  std::vector<double> observed(grid.num_cells(), 0.0);
  size_t outside = 0, zero_pdf = 0;
  int64_t first_outside = -1, first_zero_pdf = -1;
  for (size_t i = 0; i < samples.size(); ++i) {
    const glm::vec4& s = samples[i];
    const int64_t cell = grid.locate(glm::dvec3(s.x, s.y, s.z));
    if (cell < 0) {
      if (outside++ == 0) first_outside = int64_t(i);
    } else {
      observed[size_t(cell)] += 1.0;
    }
    if (!(s.w > 0.0f) || !std::isfinite(s.w)) {
      if (zero_pdf++ == 0) first_zero_pdf = int64_t(i);
    }
  }
  const double n = double(samples.size());
  std::vector<double> expected(mass.size());
  for (size_t c = 0; c < mass.size(); ++c) expected[c] = n * mass[c];

  Chi2Result r =
      chi2_counts(observed, expected, options, [&](size_t c) { return grid.cell_name(c); });
  r.samples = samples.size();
  r.pdf_integral = std::accumulate(mass.begin(), mass.end(), 0.0);
  r.outside_samples = outside;
  r.zero_pdf_samples = zero_pdf;
  const bool normalised = std::fabs(r.pdf_integral - 1.0) <= options.integral_tolerance;
  const bool chi2_passed = r.passed;
  r.passed = chi2_passed && normalised && outside == 0 && zero_pdf == 0;

  std::string problems;
  if (!chi2_passed) problems += "chi-square rejects the pdf\n";
  if (!normalised)
    problems += format("pdf integrates to %.6f over the domain, not 1 (tolerance %g)\n",
                       r.pdf_integral, options.integral_tolerance, 0, 0);
  auto describe = [&](int64_t i) {
    const glm::vec4& s = samples[size_t(i)];
    return format("(%.7g, %.7g, %.7g", s.x, s.y, s.z, 0) + format(", pdf %.7g)", s.w, 0, 0, 0);
  };
  if (outside > 0)
    problems += std::to_string(outside) +
                (grid.is_sphere() ? " samples are not finite unit directions"
                                  : " samples lie outside the domain") +
                ", e.g. #" + std::to_string(first_outside) + " " + describe(first_outside) + "\n";
  if (zero_pdf > 0)
    problems += std::to_string(zero_pdf) + " samples where the pdf is 0 or not finite, e.g. #" +
                std::to_string(first_zero_pdf) + " " + describe(first_zero_pdf) + "\n";
  // The summary line first, then what failed, then the worst cells.
  const size_t eol = r.report.find('\n');
  r.report = r.summary() + "\n" + problems + r.report.substr(eol + 1);
  return r;
}

Chi2Result chi2_test(const Chi2Grid& grid, const std::vector<glm::vec4>& samples,
                     const std::function<double(const glm::dvec3&)>& pdf,
                     const Chi2Options& options) {
  std::vector<double> at_nodes(grid.nodes().size());
  for (size_t k = 0; k < at_nodes.size(); ++k) at_nodes[k] = pdf(grid.nodes()[k]);
  std::vector<glm::vec4> with_pdf(samples);
  for (glm::vec4& s : with_pdf) s.w = float(pdf(glm::dvec3(s.x, s.y, s.z)));
  return chi2_test(grid, with_pdf, at_nodes, options);
}

}  // namespace clpt::test
