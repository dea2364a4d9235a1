// Pearson chi-square goodness of fit for sampling routines (warps now; BSDFs and lights
// later): do N samples follow the density their pdf function claims?
//
//   1. A Chi2Grid partitions the domain into cells: the sphere (or a band of cos(theta)) in
//      cells equal in solid angle, linear in cos(theta) and phi; or a planar domain (unit
//      square, unit disk, barycentric triangle) in cells equal in area, binned in the
//      domain's own polar-like parameterisation.
//   2. The pdf is integrated over every cell with Gauss-Legendre nodes strictly inside the
//      cell (so a pdf that jumps on a cell boundary, a cone's rim, is integrated exactly).
//      The pdf comes from a host lambda in double, or as values at grid.nodes evaluated
//      wherever the code under test runs (a device kernel).
//   3. Observed counts against N times each cell's integral; cells expecting fewer than 5
//      samples are pooled into one; Pearson's statistic; p = Q(dof/2, stat/2).
//
// A test passes when p >= alpha (alpha Sidak-corrected over the suite), the pdf integrates
// to 1 over the whole domain within 1e-3, every sample is a finite point of the domain
// (directions of unit length), and the pdf is positive at every sample.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace clpt::test {

// Per-test significance of m tests so that the chance of any false failure is alpha:
// 1 - (1 - alpha)^(1/m).
double sidak_alpha(double alpha, int m);

// Upper tail of the chi-square distribution: P(X >= statistic) with dof degrees of freedom.
double chi2_p_value(double statistic, int dof);

// Cells over a sphere band z = cos(theta) in [z_min, z_max] (z_bins x phi_bins, equal solid
// angle) plus, when the band is not the whole sphere, one cell for z < z_min and one for
// z > z_max (integrated on a finer grid), so every sample lands in some cell.
struct SphereBins {
  int z_bins = 32;
  int phi_bins = 64;
  double z_min = -1.0;
  double z_max = 1.0;
  int subdivisions = 1;  // quadrature sub-cells per cell and axis, for sharply peaked pdfs
};

enum class PlaneDomain {
  Square,    // [0,1]^2, cells in x and y
  Disk,      // unit disk, cells linear in r^2 and phi
  Triangle,  // barycentrics b1, b2 >= 0, b1 + b2 <= 1; cells linear in s^2 = (b1 + b2)^2 and
             // t = b2 / (b1 + b2)
};

class Chi2Grid {
 public:
  static Chi2Grid sphere(const SphereBins& bins = {});
  static Chi2Grid plane(PlaneDomain domain, int a_bins = 32, int b_bins = 64, int subdivisions = 1);

  // Where the pdf is needed: directions (unit vectors) or planar points (z = 0), with the
  // measure each stands for (solid angle or area).
  const std::vector<glm::dvec3>& nodes() const { return nodes_; }
  size_t num_cells() const { return cell_names_.size(); }

  // Integral of the pdf given at nodes() over the whole domain.
  double integral(const std::vector<double>& pdf_at_nodes) const;
  double integral(const std::function<double(const glm::dvec3&)>& pdf) const;

  // Probability mass of each cell.
  std::vector<double> cell_mass(const std::vector<double>& pdf_at_nodes) const;

  // The cell of a point, or -1 when it is not a finite point of the domain (for the sphere:
  // not of unit length within 1e-4).
  int64_t locate(const glm::dvec3& p) const;

  const std::string& cell_name(size_t cell) const { return cell_names_[cell]; }
  bool is_sphere() const { return sphere_; }

 private:
  void add_cell(std::string name, double a0, double a1, double b0, double b1, int sub_a, int sub_b);

  bool sphere_ = true;
  PlaneDomain plane_ = PlaneDomain::Square;
  SphereBins bins_;
  int a_bins_ = 0, b_bins_ = 0;
  std::vector<glm::dvec3> nodes_;
  std::vector<double> weights_;      // measure of each node
  std::vector<uint32_t> node_cell_;  // cell of each node
  std::vector<std::string> cell_names_;
};

struct Chi2Options {
  double alpha = 0.01;        // already Sidak-corrected for the suite
  double min_expected = 5.0;  // cells expecting fewer samples are pooled
  double integral_tolerance = 1e-3;
  int worst_cells = 10;  // listed in the report
};

struct Chi2Result {
  double statistic = 0.0;
  int dof = 0;
  double p_value = 0.0;
  double alpha = 0.0;
  double pdf_integral = 0.0;  // over the whole domain
  size_t samples = 0;
  size_t cells = 0;             // cells in the statistic, the pooled one included
  size_t pooled_cells = 0;      // cells merged into the pooled one
  size_t outside_samples = 0;   // non-finite, off the domain, or not unit directions
  size_t zero_pdf_samples = 0;  // pdf <= 0 or non-finite at a sample
  bool passed = false;
  std::string report;           // summary; with the worst cells when it failed
  std::string summary() const;  // one line
};

// Samples as a kernel writes them: xyz the direction (planar points: x, y, 0), w the pdf the
// code under test reports at the sample. pdf_at_nodes: the pdf at grid.nodes().
Chi2Result chi2_test(const Chi2Grid& grid, const std::vector<glm::vec4>& samples,
                     const std::vector<double>& pdf_at_nodes, const Chi2Options& options = {});

// The same with a host pdf, evaluated at the nodes and at every sample (w is ignored).
Chi2Result chi2_test(const Chi2Grid& grid, const std::vector<glm::vec4>& samples,
                     const std::function<double(const glm::dvec3&)>& pdf,
                     const Chi2Options& options = {});

// Pearson's test of observed against expected counts (same length, expected summing to the
// number of samples); cells expecting < min_expected pooled. Fills statistic, dof, p_value,
// cells, pooled_cells and a report naming the worst cells by `name`.
Chi2Result chi2_counts(const std::vector<double>& observed, const std::vector<double>& expected,
                       const Chi2Options& options, const std::function<std::string(size_t)>& name);

}  // namespace clpt::test
