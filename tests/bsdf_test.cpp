// The glTF BSDF of kernels/bsdf/ (gltf_bsdf.cl, microfacet.cl, fresnel.cl, bsdf.cl), run on
// the device through tests/kernels/bsdf_test.cl:
//   GgxVndf          the visible-normal warp: chi-square against its pdf, sample -> invert;
//   BsdfChi2         ~1M samples of each configuration and incident direction against the
//                    mixture pdf() evaluated on the device (Pearson chi-square, Sidak alpha
//                    0.01 over the suite); samples that are absorbed (weight 0: a reflection
//                    below the horizon, refraction under total internal reflection) or come
//                    from a delta lobe form one more cell, expected to hold 1 - integral(pdf);
//   BsdfSmoothDielectric  delta glass: reflect vs refract frequencies against exact Fresnel
//                    (z-test), exact mirror and Snell directions, weights in both modes;
//   BsdfConsistency  weight = eval |cos| / pdf and pdf() = the sample's pdf, local and through
//                    the world-space wrapper on random shading frames (no light leaks);
//   BsdfEnergy       albedo <= 1, Lambert rho = 1 gives 1, smooth glass white furnace;
//   BsdfReciprocity  f(a, b) = f(b, a) for reflection, the eta^2 rule for refraction in
//                    radiance mode, and importance mode as the adjoint of radiance mode;
//   BsdfLambertLimit specular = 0 is exactly Lambert.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "support/chi2.h"
#include "support/device.h"

namespace clpt::bsdf_test {
namespace {

using test::Chi2Grid;
using test::Chi2Options;
using test::Chi2Result;
using test::SphereBins;

constexpr double kPi = 3.14159265358979323846;
constexpr cl_int kRadiance = 0;    // TRANSPORT_RADIANCE (kernels/bsdf/bsdf_params.h)
constexpr cl_int kImportance = 1;  // TRANSPORT_IMPORTANCE

// ---------------------------------------------------------------------------------------
// Configurations and the device side

struct Config {
  glm::vec3 base{0.8f, 0.6f, 0.4f};
  glm::vec3 spec_color{1.0f};
  float metallic = 0.0f;
  float roughness = 1.0f;
  float specular = 1.0f;
  float transmission = 0.0f;
  float ior = 1.5f;
  float clearcoat = 0.0f;
  float clearcoat_roughness = 0.0f;
  float iridescence = 0.0f;
  float iridescence_ior = 1.3f;
  float iridescence_thickness = 400.0f;
  float diffuse_transmission = 0.0f;
  glm::vec3 dt_color{1.0f};
  glm::vec3 sheen_color{0.0f};
  float sheen_roughness = 0.0f;
  float anisotropy = 0.0f;  // KHR_materials_anisotropy strength, along local x
  glm::vec3 coat_normal{0.0f, 0.0f, 1.0f};  // the clearcoat's normal, local (normalised there)
};

std::vector<float> pack(const Config& c) {
  return {c.base.x,   c.base.y,    c.base.z,   c.spec_color.x, c.spec_color.y, c.spec_color.z, c.metallic,
          c.roughness, c.specular, c.transmission, c.ior,     c.clearcoat,    c.clearcoat_roughness,
          c.iridescence, c.iridescence_ior, c.iridescence_thickness, c.diffuse_transmission,
          c.dt_color.x, c.dt_color.y, c.dt_color.z, c.sheen_color.x, c.sheen_color.y, c.sheen_color.z,
          c.sheen_roughness, c.anisotropy, c.coat_normal.x, c.coat_normal.y, c.coat_normal.z};
}

Config lambert(glm::vec3 base = glm::vec3(0.8f, 0.5f, 0.2f)) {
  Config c;
  c.base = base;
  c.specular = 0.0f;
  return c;
}
Config metal(float alpha) {
  Config c;
  c.base = {0.95f, 0.64f, 0.54f};
  c.metallic = 1.0f;
  c.roughness = std::sqrt(alpha);
  return c;
}
Config glass(float roughness) {
  Config c;
  c.base = glm::vec3(1.0f);
  c.transmission = 1.0f;
  c.roughness = roughness;
  return c;
}
Config plastic(float roughness, float specular = 1.0f, glm::vec3 spec_color = glm::vec3(1.0f)) {
  Config c;
  c.base = {0.6f, 0.3f, 0.1f};
  c.roughness = roughness;
  c.specular = specular;
  c.spec_color = spec_color;
  return c;
}
Config mixed_metal() {
  Config c;
  c.base = {0.7f, 0.4f, 0.2f};
  c.metallic = 0.5f;
  c.roughness = 0.5f;
  return c;
}
Config half_transmission() {
  Config c;
  c.base = {0.9f, 0.8f, 0.5f};
  c.transmission = 0.5f;
  c.roughness = 0.5f;
  return c;
}

// KHR_materials_clearcoat of weight c and roughness r over another configuration.
Config coated(Config base, float c, float r) {
  base.clearcoat = c;
  base.clearcoat_roughness = r;
  return base;
}
// The same coat with a normal of its own (clearcoatNormalTexture): tilted ~22 degrees.
Config tilted_coat(Config c) {
  c.coat_normal = {0.35f, -0.2f, 1.0f};
  return c;
}
bool tilted(const Config& c) { return c.clearcoat > 0.0f && (c.coat_normal.x != 0.0f || c.coat_normal.y != 0.0f); }

// KHR_materials_iridescence of weight k, film index ior and thickness d (nm) over another.
Config iridescent(Config base, float k, float ior, float d) {
  base.iridescence = k;
  base.iridescence_ior = ior;
  base.iridescence_thickness = d;
  return base;
}

// KHR_materials_diffuse_transmission: a share dt of the diffuse layer, of colour col, crosses.
Config translucent(Config base, float dt, glm::vec3 col) {
  base.diffuse_transmission = dt;
  base.dt_color = col;
  return base;
}

// KHR_materials_sheen of colour col and roughness r over another configuration.
Config sheened(Config base, glm::vec3 col, float r) {
  base.sheen_color = col;
  base.sheen_roughness = r;
  return base;
}

// KHR_materials_anisotropy of strength s over another configuration (direction: local x).
Config anisotropic(Config base, float s) {
  base.anisotropy = s;
  return base;
}

glm::vec4 direction(double cos_theta, double phi = 0.7) {
  const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  return glm::vec4(float(s * std::cos(phi)), float(s * std::sin(phi)), float(cos_theta), 0.0f);
}

const cl::Program& bsdf_program() {
  return test::test_program("kernels/bsdf_test.cl");
}

struct Samples {
  std::vector<glm::vec4> dir_pdf;  // wi, pdf_w
  std::vector<glm::vec4> weight;   // weight, is_delta
};

// n samples; wo holds one direction for all or one per sample.
Samples sample(const Config& c, cl_int mode, const std::vector<glm::vec4>& wo, uint32_t seed,
               uint32_t n) {
  cl::Context& ctx = test::device_context();
  cl::Buffer cfg = cl::Buffer::from_vector(ctx, pack(c));
  cl::Buffer wo_buf = cl::Buffer::from_vector(ctx, wo);
  cl::Buffer dir_pdf(ctx, n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "bsdf samples");
  cl::Buffer weight(ctx, n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "bsdf weights");
  cl::Kernel kernel(bsdf_program(), "bsdf_sample_random");
  kernel.args(0, cfg, mode, wo_buf, cl_uint(wo.size() == 1 ? 0 : 1), cl_uint(seed), dir_pdf, weight,
              cl_uint(n));
  kernel.launch(ctx, n);
  return {dir_pdf.read_vector<glm::vec4>(n), weight.read_vector<glm::vec4>(n)};
}

// (f |cos|, pdf) at pairs; wo one direction for all or one per wi.
std::vector<glm::vec4> eval_pairs(const Config& c, cl_int mode, const std::vector<glm::vec4>& wo,
                                  const std::vector<glm::vec4>& wi) {
  cl::Context& ctx = test::device_context();
  const cl_uint n = cl_uint(wi.size());
  cl::Buffer cfg = cl::Buffer::from_vector(ctx, pack(c));
  cl::Buffer wo_buf = cl::Buffer::from_vector(ctx, wo);
  cl::Buffer wi_buf = cl::Buffer::from_vector(ctx, wi);
  cl::Buffer out(ctx, n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "bsdf values");
  cl::Kernel kernel(bsdf_program(), "bsdf_eval_pairs");
  kernel.args(0, cfg, mode, wo_buf, cl_uint(wo.size() == 1 ? 0 : 1), wi_buf, out, n);
  kernel.launch(ctx, n);
  return out.read_vector<glm::vec4>(n);
}

std::vector<double> pdf_at(const Config& c, const glm::vec4& wo,
                           const std::vector<glm::dvec3>& points) {
  std::vector<glm::vec4> wi(points.size());
  for (size_t i = 0; i < points.size(); ++i) wi[i] = glm::vec4(glm::vec3(points[i]), 0.0f);
  const std::vector<glm::vec4> v = eval_pairs(c, kRadiance, {wo}, wi);
  std::vector<double> pdf(v.size());
  for (size_t i = 0; i < v.size(); ++i) pdf[i] = v[i].w;
  return pdf;
}

double suite_alpha() {
  const ::testing::TestSuite* suite = ::testing::UnitTest::GetInstance()->current_test_suite();
  return test::sidak_alpha(0.01, suite ? suite->total_test_count() : 1);
}

// Exact unpolarised Fresnel reflectance in double, cos_i >= 0, eta = eta_t / eta_i.
double fresnel_exact(double cos_i, double eta) {
  const double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0) return 1.0;
  const double cos_t = std::sqrt(1.0 - sin2_t);
  const double a = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const double b = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5 * (a * a + b * b);
}

// ---------------------------------------------------------------------------------------
// Chi-square with an "absorbed or delta" cell

// A rotation taking `axis` to +z (for grids with their pole on a sharp lobe).
glm::dmat3 rotation_to_pole(glm::dvec3 axis) {
  axis = glm::normalize(axis);
  const glm::dvec3 helper = std::fabs(axis.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  const glm::dvec3 x = glm::normalize(glm::cross(helper, axis));
  const glm::dvec3 y = glm::cross(axis, x);
  return glm::transpose(glm::dmat3(x, y, axis));  // rows x, y, axis
}

// Counts samples per cell of `grid` (after rotating them by R), plus one cell for samples
// that are absorbed (pdf_w 0, weight 0) or delta, expected to hold 1 - integral(pdf).
// Fails on samples that are not finite unit directions, non-delta samples whose own pdf is
// not positive, and a pdf integrating to more than 1.
Chi2Result bsdf_chi2(const Chi2Grid& grid, const Samples& s, const std::vector<double>& pdf_nodes,
                     const glm::dmat3& R, double alpha) {
  const std::vector<double> mass = grid.cell_mass(pdf_nodes);
  double integral = 0.0;
  for (double m : mass) integral += m;
  std::vector<double> observed(mass.size() + 1, 0.0);
  size_t bad = 0, delta = 0, absorbed = 0;
  std::string first_bad;
  for (size_t i = 0; i < s.dir_pdf.size(); ++i) {
    const glm::vec4& d = s.dir_pdf[i];
    const glm::vec4& w = s.weight[i];
    if (w.w != 0.0f) {
      ++delta;
      observed.back() += 1.0;
      continue;
    }
    if (d.w == 0.0f && w.x == 0.0f && w.y == 0.0f && w.z == 0.0f) {
      ++absorbed;
      observed.back() += 1.0;
      continue;
    }
    const int64_t cell = grid.locate(R * glm::dvec3(d.x, d.y, d.z));
    if (cell < 0 || !(d.w > 0.0f) || !std::isfinite(d.w) || !std::isfinite(w.x + w.y + w.z)) {
      if (bad++ == 0)
        first_bad = "#" + std::to_string(i) + " (" + std::to_string(d.x) + ", " +
                    std::to_string(d.y) + ", " + std::to_string(d.z) + ") pdf " +
                    std::to_string(d.w) + " weight " + std::to_string(w.x);
      continue;
    }
    observed[size_t(cell)] += 1.0;
  }
  const double n = double(s.dir_pdf.size());
  std::vector<double> expected(observed.size());
  for (size_t c = 0; c < mass.size(); ++c) expected[c] = n * mass[c];
  expected.back() = n * std::max(0.0, 1.0 - integral);
  Chi2Options options;
  options.alpha = alpha;
  Chi2Result r = test::chi2_counts(observed, expected, options, [&](size_t c) {
    return c < mass.size() ? grid.cell_name(c) : std::string("absorbed or delta");
  });
  r.pdf_integral = integral;
  r.samples = s.dir_pdf.size();
  r.outside_samples = bad;
  const bool chi2_ok = r.passed;
  r.passed = chi2_ok && bad == 0 && integral <= 1.0 + 1e-3;
  r.report = r.summary() + "; absorbed " + std::to_string(absorbed) + ", delta " +
             std::to_string(delta) + "\n" + (bad ? std::to_string(bad) + " bad samples, e.g. " + first_bad + "\n" : "") +
             (integral > 1.0 + 1e-3 ? "pdf integrates to more than 1\n" : "") + r.report;
  return r;
}

struct Chi2Case {
  std::string name;
  Config config;
  double cos_o;
  int z_bins = 32, phi_bins = 64, subdivisions = 4;
  // Pole of the grid: 0 the normal, 1 the mirror direction, 2 the refracted direction; the
  // band then spans cos in [band_min, 1] around it.
  int pole = 0;
  double band_min = -1.0;
  double band_max = 1.0;  // pole 0 only: a band [band_min, band_max] of cos(theta)
};

class BsdfChi2 : public ::testing::TestWithParam<Chi2Case> {};

TEST_P(BsdfChi2, MatchesPdf) {
  const Chi2Case& c = GetParam();
  const glm::vec4 wo = direction(c.cos_o);
  glm::dmat3 R(1.0);
  if (c.pole == 1) R = rotation_to_pole(glm::dvec3(-wo.x, -wo.y, wo.z));
  if (c.pole == 2) {
    const double eta = c.cos_o > 0 ? c.config.ior : 1.0 / c.config.ior;
    const glm::dvec3 w(wo), n(0, 0, c.cos_o > 0 ? 1 : -1);
    const double ci = glm::dot(w, n), s2 = (1 - ci * ci) / (eta * eta);
    R = rotation_to_pole(-w / eta + (ci / eta - std::sqrt(1 - s2)) * n);
  }
  SphereBins bins;
  bins.z_bins = c.z_bins;
  bins.phi_bins = c.phi_bins;
  bins.subdivisions = c.subdivisions;
  bins.z_min = c.band_min;
  bins.z_max = c.band_max;
  const Chi2Grid grid = Chi2Grid::sphere(bins);
  // pdf at the grid's nodes, rotated back into the BSDF's frame.
  std::vector<glm::dvec3> nodes(grid.nodes().size());
  const glm::dmat3 Rt = glm::transpose(R);
  for (size_t k = 0; k < nodes.size(); ++k) nodes[k] = Rt * grid.nodes()[k];
  const uint32_t seed = uint32_t(std::hash<std::string>()(c.name));
  const Samples s = sample(c.config, kRadiance, {wo}, seed, 1u << 20);
  const Chi2Result r = bsdf_chi2(grid, s, pdf_at(c.config, wo, nodes), R, suite_alpha());
  std::cout << "[ chi2     ] " << c.name << ": " << r.report.substr(0, r.report.find('\n')) << "\n";
  EXPECT_TRUE(r.passed) << r.report;
}

std::vector<Chi2Case> chi2_cases() {
  std::vector<Chi2Case> v;
  auto add = [&](const std::string& name, const Config& cfg, std::vector<double> cosines) {
    for (double c : cosines) {
      std::string n = name + "_cos" + (c < 0 ? "m" : "") + std::to_string(int(std::lround(std::fabs(c) * 100)));
      Chi2Case k{n, cfg, c};
      // At grazing incidence a sharp lobe is ~0.3 degrees wide in azimuth (alpha 0.05, cos
      // 0.05): cells of 0.7 degrees, so the quadrature of the pdf resolves it.
      if (std::fabs(c) < 0.1) {
        k.z_bins = 16;
        k.phi_bins = 512;
        // Rough glass refracting at grazing incidence: its pdf has an integrable kink at the
        // edge of the refraction cone; finer quadrature.
        if (cfg.transmission > 0 && cfg.roughness > 0.5f) k.subdivisions = 8;
      }
      v.push_back(k);
    }
  };
  add("Lambert", lambert(), {0.99, 0.5, 0.05});
  add("MetalAlpha005", metal(0.05f), {0.9, 0.5, 0.05});
  add("MetalAlpha03", metal(0.3f), {0.9, 0.5, 0.05});
  add("MetalAlpha1", metal(1.0f), {0.9, 0.5, 0.05});
  // Inside, the critical angle is at cos 0.745: -0.6 and -0.2 are beyond it.
  add("RoughGlass03", glass(0.3f), {0.8, 0.3, 0.05, -0.9, -0.6, -0.2});
  add("RoughGlass07", glass(0.7f), {0.8, 0.3, 0.05, -0.9, -0.6, -0.2});
  add("MixedMetallic05", mixed_metal(), {0.8, 0.3, 0.05});
  add("Specular05", plastic(0.4f, 0.5f), {0.8, 0.3, 0.05});
  add("ColouredSpecular", plastic(0.3f, 1.0f, glm::vec3(1.0f, 0.6f, 0.2f)), {0.8, 0.3, 0.05});
  add("ColouredSpecularClamped", plastic(0.3f, 0.8f, glm::vec3(30.0f, 10.0f, 1.0f)), {0.8, 0.05});
  add("HalfTransmission", half_transmission(), {0.7, 0.1, -0.7});
  add("DeltaCoatOverDiffuse", plastic(0.0f), {0.8, 0.05});
  add("DeltaGlassHalfDiffuse", [] { Config c = half_transmission(); c.roughness = 0.0f; return c; }(), {0.8, -0.5});
  // KHR_materials_clearcoat: the coat's own GGX lobe over each kind of base.
  add("ClearcoatPlastic", coated(plastic(0.6f), 1.0f, 0.3f), {0.8, 0.3, 0.05});
  add("ClearcoatMetal", coated(metal(0.3f), 0.7f, 0.25f), {0.8, 0.3, 0.05});
  add("DeltaClearcoatMetal", coated(metal(0.3f), 1.0f, 0.0f), {0.8, 0.05});
  add("ClearcoatGlass", coated(glass(0.3f), 0.8f, 0.4f), {0.8, 0.3, -0.6});
  add("ClearcoatOverDeltaCoat", coated(plastic(0.0f), 0.5f, 0.2f), {0.8, 0.05});
  // clearcoatNormalTexture: the coat's lobe in a frame of its own, over each kind of base.
  add("TiltedClearcoatPlastic", tilted_coat(coated(plastic(0.6f), 1.0f, 0.3f)), {0.8, 0.3, 0.05});
  add("TiltedDeltaClearcoatMetal", tilted_coat(coated(metal(0.3f), 1.0f, 0.0f)), {0.8, 0.05});
  add("TiltedClearcoatGlass", tilted_coat(coated(glass(0.3f), 0.8f, 0.4f)), {0.8, 0.3, -0.6});
  add("TiltedClearcoatOverDeltaCoat", tilted_coat(coated(plastic(0.0f), 0.5f, 0.2f)), {0.8, 0.05});
  // KHR_materials_iridescence: the film changes reflectances, so the glass's split between
  // reflection and refraction (sampled by the film's r) is what can go wrong.
  add("IridescentMetal", iridescent(metal(0.3f), 1.0f, 1.3f, 400.0f), {0.8, 0.3});
  add("IridescentPlastic", iridescent(plastic(0.4f), 1.0f, 1.8f, 300.0f), {0.8, 0.3});
  add("IridescentGlass", iridescent(glass(0.3f), 1.0f, 1.5f, 500.0f), {0.8, 0.3, -0.9, -0.6});
  // KHR_materials_diffuse_transmission: a cosine lobe on the far side, from either side.
  add("DiffuseTransmission", translucent(plastic(0.5f), 0.6f, {0.9f, 0.5f, 0.2f}), {0.8, 0.3, 0.05, -0.7});
  add("DiffuseTransmissionCoated", coated(translucent(plastic(0.0f), 0.4f, glm::vec3(1.0f)), 0.8f, 0.3f), {0.8, 0.2});
  add("DiffuseTransmissionHalfMetal", translucent(mixed_metal(), 1.0f, {0.3f, 0.8f, 0.6f}), {0.7, -0.4});
  // KHR_materials_sheen: a uniform lobe over the base, under a coat, on glass and on a mirror.
  add("Sheen", sheened(plastic(0.5f), {0.9f, 0.6f, 0.3f}, 0.5f), {0.8, 0.3, 0.05});
  add("SmoothSheenOverMetal", sheened(metal(0.3f), {0.5f, 0.5f, 1.0f}, 0.1f), {0.8, 0.05});
  add("SheenUnderClearcoat", coated(sheened(plastic(0.6f), glm::vec3(1.0f), 0.8f), 0.7f, 0.3f), {0.8, 0.3});
  add("SheenOnGlass", sheened(glass(0.3f), {1.0f, 0.8f, 0.8f}, 0.4f), {0.8, -0.6});
  add("SheenOverDeltaCoat", sheened(plastic(0.0f), glm::vec3(0.7f), 0.3f), {0.8, 0.1});
  // KHR_materials_anisotropy: stretched GGX on the metal, the coat, the glass (both ways).
  add("AnisotropicMetal", anisotropic(metal(0.1f), 0.8f), {0.8, 0.3, 0.05});
  add("AnisotropicPlastic", anisotropic(plastic(0.4f), 0.5f), {0.8, 0.3});
  add("AnisotropicRoughGlass", anisotropic(glass(0.3f), 0.7f), {0.8, 0.3, -0.9, -0.6});
  add("AnisotropicClearcoatMetal", coated(anisotropic(metal(0.2f), 1.0f), 0.6f, 0.3f), {0.8, 0.2});
  // Sharp lobes once more, on a fine grid with its pole on the lobe.
  auto add_pole = [&](const std::string& name, const Config& cfg, double cos_o, int pole, double band_min) {
    Chi2Case k{name, cfg, cos_o};
    k.pole = pole;
    k.band_min = band_min;
    k.subdivisions = 2;
    v.push_back(k);
  };
  add_pole("MetalAlpha005_mirror_pole_cos90", metal(0.05f), 0.9, 1, 0.9);
  add_pole("MetalAlpha005_mirror_pole_cos50", metal(0.05f), 0.5, 1, 0.9);
  add_pole("MetalAlpha03_mirror_pole_cos50", metal(0.3f), 0.5, 1, 0.5);
  // (A pole on a refracted lobe puts the horizon, where the pdf jumps, across the cells at
  // an angle; the quadrature then misses by ~8 %. Refraction is tested on the plain grid.)
  // Grazing incidence: the lobes hug the horizon; a band of fine cells in cos(theta).
  auto add_band = [&](const std::string& name, const Config& cfg, double cos_o, double z0, double z1) {
    Chi2Case k{name, cfg, cos_o};
    k.band_min = z0;
    k.band_max = z1;
    k.z_bins = 16;
    k.phi_bins = 512;  // the lobe is ~0.3 degrees wide in azimuth at alpha 0.05, cos 0.05
    v.push_back(k);
  };
  add_band("MetalAlpha005_grazing_band_cos5", metal(0.05f), 0.05, 0.0, 0.25);
  add_band("RoughGlass03_grazing_band_cos5", glass(0.3f), 0.05, -0.5, 0.5);
  add_band("ColouredSpecular_grazing_band_cos5", plastic(0.3f, 1.0f, glm::vec3(1.0f, 0.6f, 0.2f)), 0.05, 0.0, 0.5);
  return v;
}

INSTANTIATE_TEST_SUITE_P(Bsdf, BsdfChi2, ::testing::ValuesIn(chi2_cases()),
                         [](const ::testing::TestParamInfo<Chi2Case>& info) { return info.param.name; });

// ---------------------------------------------------------------------------------------
// GgxVndf: the visible-normal warp as a warp.cl-style triple

struct VndfCase {
  glm::vec2 alpha;  // along x, along y (equal: isotropic)
  double cos_o;
  double z_min = 0.0;
};

std::vector<double> vndf_pdf_at(const glm::vec4& wo, glm::vec2 alpha, const std::vector<glm::dvec3>& h) {
  cl::Context& ctx = test::device_context();
  const cl_uint n = cl_uint(h.size());
  std::vector<glm::vec4> p(n);
  for (size_t i = 0; i < n; ++i) p[i] = glm::vec4(glm::vec3(h[i]), 0.0f);
  cl::Buffer in = cl::Buffer::from_vector(ctx, p);
  cl::Buffer out(ctx, n * sizeof(float), CL_MEM_WRITE_ONLY, nullptr, "vndf pdf");
  cl::Kernel kernel(bsdf_program(), "ggx_vndf_pdf_at");
  kernel.args(0, wo, alpha, in, out, n);
  kernel.launch(ctx, n);
  const std::vector<float> v = out.read_vector<float>(n);
  return std::vector<double>(v.begin(), v.end());
}

TEST(GgxVndf, Chi2AndInvert) {
  // alpha 0.05: the band cos(theta_h) > 0.98 holds the peak (1 - cos ~ alpha^2 / 2).
  // The anisotropic ones (KHR_materials_anisotropy): wo at azimuth 0.7 rad, off both axes.
  const VndfCase cases[] = {{glm::vec2(0.05f), 0.9, 0.98}, {glm::vec2(0.3f), 0.5}, {glm::vec2(1.0f), 0.05},
                            {glm::vec2(0.3f), 0.999}, {glm::vec2(0.05f), 0.05, 0.98},
                            {{0.6f, 0.08f}, 0.7}, {{0.08f, 0.6f}, 0.3}, {{1.0f, 0.15f}, 0.8},
                            {{0.2f, 0.8f}, 0.05}};
  const double alpha_test = test::sidak_alpha(0.01, int(std::size(cases)));
  cl::Context& ctx = test::device_context();
  for (const VndfCase& c : cases) {
    const glm::vec4 wo = direction(c.cos_o);
    const cl_uint n = 1u << 20;
    cl::Buffer out(ctx, n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "vndf samples");
    cl::Kernel kernel(bsdf_program(), "ggx_vndf_sample_random");
    kernel.args(0, wo, c.alpha, cl_uint(77), out, n);
    kernel.launch(ctx, n);
    SphereBins bins;
    bins.z_min = c.z_min;  // h is in the upper hemisphere
    // Fine cells where the lobe is narrow: a small alpha, or grazing wo over an anisotropic one.
    bins.subdivisions = std::min(c.alpha.x, c.alpha.y) < 0.1f || (c.alpha.x != c.alpha.y && c.cos_o < 0.1) ? 4 : 1;
    const Chi2Grid grid = Chi2Grid::sphere(bins);
    Chi2Options options;
    options.alpha = alpha_test;
    const Chi2Result r =
        test::chi2_test(grid, out.read_vector<glm::vec4>(n), vndf_pdf_at(wo, c.alpha, grid.nodes()), options);
    std::cout << "[ chi2     ] vndf alpha " << c.alpha.x << "," << c.alpha.y << " cos " << c.cos_o << ": " << r.summary() << "\n";
    EXPECT_TRUE(r.passed) << r.report;

    // sample -> invert returns u.
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<float> U(1e-3f, 1.0f - 1e-3f);
    std::vector<glm::vec2> u(10000);
    for (glm::vec2& x : u) x = glm::vec2(U(rng), U(rng));
    cl::Buffer ub = cl::Buffer::from_vector(ctx, u);
    cl::Buffer hb(ctx, u.size() * sizeof(glm::vec4), CL_MEM_READ_WRITE, nullptr, "h");
    cl::Kernel ks(bsdf_program(), "ggx_vndf_sample_at");
    ks.args(0, wo, c.alpha, ub, hb, cl_uint(u.size()));
    ks.launch(ctx, u.size());
    cl::Buffer back(ctx, u.size() * sizeof(glm::vec2), CL_MEM_WRITE_ONLY, nullptr, "u back");
    cl::Kernel ki(bsdf_program(), "ggx_vndf_invert_at");
    ki.args(0, wo, c.alpha, hb, back, cl_uint(u.size()));
    ki.launch(ctx, u.size());
    const std::vector<glm::vec2> ub2 = back.read_vector<glm::vec2>(u.size());
    double worst = 0.0;
    for (size_t i = 0; i < u.size(); ++i) {
      const double dx = std::fabs(double(ub2[i].x) - u[i].x);
      double dy = std::fabs(double(ub2[i].y) - u[i].y);
      dy = std::min(dy, 1.0 - dy);
      worst = std::max(worst, std::isfinite(dx + dy) ? std::max(dx, dy) : HUGE_VAL);
    }
    std::cout << "[ invert   ] vndf u -> h -> u: max error " << worst << "\n";
    EXPECT_LE(worst, 1e-3);
  }
}

// ---------------------------------------------------------------------------------------
// BsdfSmoothDielectric

TEST(BsdfSmoothDielectric, FresnelFrequenciesAndDirections) {
  const Config c = glass(0.0f);
  const double cosines[] = {0.95, 0.5, 0.1, -0.95, -0.8, -0.7, -0.3};
  const double z_crit = 5.0;  // |z| < 5: Sidak alpha 0.01 over 7 directions needs ~3.2
  constexpr uint32_t n = 200000;
  for (double cos_o : cosines) {
    const glm::vec4 wo = direction(cos_o);
    const double eta = cos_o > 0 ? c.ior : 1.0 / c.ior;
    const double F = fresnel_exact(std::fabs(cos_o), eta);
    for (cl_int mode : {kRadiance, kImportance}) {
      const Samples s = sample(c, mode, {wo}, 1234 + uint32_t(mode), n);
      size_t reflected = 0, wrong = 0;
      double worst_dir = 0.0;
      const glm::dvec3 w(wo);
      const double ci = std::fabs(w.z), s2 = (1 - ci * ci) / (eta * eta);
      const glm::dvec3 nrm(0, 0, cos_o > 0 ? 1 : -1);
      const glm::dvec3 mirror(-w.x, -w.y, w.z);
      const glm::dvec3 refracted =
          s2 < 1 ? -w / eta + (ci / eta - std::sqrt(1 - s2)) * nrm : glm::dvec3(0.0);
      for (uint32_t i = 0; i < n; ++i) {
        const glm::dvec3 wi(s.dir_pdf[i]);
        const glm::dvec3 wt(s.weight[i]);
        if (s.weight[i].w != 1.0f) {
          ++wrong;
          continue;
        }
        const bool refl = wi.z * w.z > 0;
        reflected += refl;
        worst_dir = std::max(worst_dir, glm::length(wi - (refl ? mirror : refracted)));
        const double expected_w = refl ? 1.0 : (mode == kRadiance ? 1.0 / (eta * eta) : 1.0);
        if (std::fabs(wt.x - expected_w) > 1e-5 * expected_w || wt.y != wt.x || wt.z != wt.x) ++wrong;
      }
      const double z = (double(reflected) - n * F) / std::sqrt(std::max(n * F * (1 - F), 1e-300));
      std::cout << "[ fresnel  ] cos " << cos_o << " mode " << mode << ": reflected "
                << double(reflected) / n << " vs F " << F << " (z " << (F < 1 ? z : 0.0)
                << "), direction error " << worst_dir << "\n";
      EXPECT_EQ(wrong, 0u) << "samples not delta or with a wrong weight";
      if (F >= 1.0)
        EXPECT_EQ(reflected, n) << "total internal reflection";
      else
        EXPECT_LT(std::fabs(z), z_crit) << "cos " << cos_o;
      EXPECT_LT(worst_dir, 2e-6) << "not the exact mirror / refraction direction";
    }
    // eval and pdf leave the deltas out: 0 at the mirror direction and everywhere else.
    const std::vector<glm::vec4> wis = {glm::vec4(-wo.x, -wo.y, wo.z, 0), direction(0.3, 2.0),
                                        direction(-0.3, 2.0)};
    for (const glm::vec4& v : eval_pairs(c, kRadiance, {wo}, wis))
      EXPECT_EQ(glm::vec4(0.0f), v) << "eval/pdf of a delta BSDF must be 0";
  }
}

// ---------------------------------------------------------------------------------------
// BsdfConsistency

std::vector<glm::vec4> random_directions(size_t n, uint64_t seed, bool upper_only = false) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<glm::vec4> v(n);
  for (glm::vec4& w : v) {
    const double z = upper_only ? 0.001 + 0.999 * U(rng) : 2 * U(rng) - 1, phi = 2 * kPi * U(rng);
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    w = glm::vec4(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z), 0.0f);
  }
  return v;
}

std::vector<std::pair<std::string, Config>> consistency_configs() {
  return {{"lambert", lambert()},          {"metal_0.05", metal(0.05f)},
          {"metal_0.3", metal(0.3f)},      {"metal_1", metal(1.0f)},
          {"glass_0.3", glass(0.3f)},      {"glass_0.7", glass(0.7f)},
          {"mixed", mixed_metal()},        {"specular_0.5", plastic(0.4f, 0.5f)},
          {"coloured_specular", plastic(0.3f, 1.0f, glm::vec3(1.0f, 0.6f, 0.2f))},
          {"half_transmission", half_transmission()},
          {"delta_coat", plastic(0.0f)},
          {"clearcoat_plastic", coated(plastic(0.6f), 1.0f, 0.3f)},
          {"clearcoat_metal", coated(metal(0.3f), 0.7f, 0.25f)},
          {"delta_clearcoat_metal", coated(metal(0.3f), 1.0f, 0.0f)},
          {"clearcoat_glass", coated(glass(0.3f), 0.8f, 0.4f)},
          {"clearcoat_over_delta_coat", coated(plastic(0.0f), 0.5f, 0.2f)},
          {"tilted_clearcoat_plastic", tilted_coat(coated(plastic(0.6f), 1.0f, 0.3f))},
          {"tilted_delta_clearcoat_metal", tilted_coat(coated(metal(0.3f), 1.0f, 0.0f))},
          {"tilted_clearcoat_glass", tilted_coat(coated(glass(0.3f), 0.8f, 0.4f))},
          {"tilted_clearcoat_over_delta_coat", tilted_coat(coated(plastic(0.0f), 0.5f, 0.2f))},
          {"iridescent_metal", iridescent(metal(0.3f), 1.0f, 1.3f, 400.0f)},
          {"iridescent_plastic", iridescent(plastic(0.4f), 0.7f, 1.8f, 300.0f)},
          {"iridescent_glass", iridescent(glass(0.3f), 1.0f, 1.5f, 500.0f)},
          {"translucent_plastic", translucent(plastic(0.5f), 0.6f, {0.9f, 0.5f, 0.2f})},
          {"translucent_coated", coated(translucent(plastic(0.4f), 0.4f, glm::vec3(1.0f)), 0.8f, 0.3f)},
          {"translucent_half_metal", translucent(mixed_metal(), 1.0f, {0.3f, 0.8f, 0.6f})},
          {"coated_iridescent_plastic", coated(iridescent(plastic(0.4f), 1.0f, 1.4f, 250.0f), 1.0f, 0.2f)},
          {"sheen_plastic", sheened(plastic(0.5f), {0.9f, 0.6f, 0.3f}, 0.5f)},
          {"smooth_sheen_metal", sheened(metal(0.3f), {0.5f, 0.5f, 1.0f}, 0.1f)},
          {"sheen_coated", coated(sheened(plastic(0.6f), glm::vec3(1.0f), 0.8f), 0.7f, 0.3f)},
          {"sheen_glass", sheened(glass(0.3f), {1.0f, 0.8f, 0.8f}, 0.4f)},
          {"sheen_delta_coat", sheened(plastic(0.0f), glm::vec3(0.7f), 0.3f)},
          {"anisotropic_metal", anisotropic(metal(0.1f), 0.8f)},
          {"anisotropic_smooth_metal", anisotropic(metal(0.0f), 0.6f)},
          {"anisotropic_plastic", anisotropic(plastic(0.4f), 0.5f)},
          {"anisotropic_glass", anisotropic(glass(0.3f), 0.7f)},
          {"anisotropic_smooth_glass", anisotropic(glass(0.0f), 1.0f)},
          {"anisotropic_coated_metal", coated(anisotropic(metal(0.2f), 1.0f), 0.6f, 0.3f)}};
}

// rel difference of two colours, relative to the larger one's largest channel.
double rel_diff(glm::dvec3 a, glm::dvec3 b) {
  const double scale = std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z), std::fabs(b.x),
                                 std::fabs(b.y), std::fabs(b.z)});
  if (scale == 0.0) return 0.0;
  const glm::dvec3 d = glm::abs(a - b);
  return std::max({d.x, d.y, d.z}) / scale;
}

double rel_diff(double a, double b) {
  const double scale = std::max(std::fabs(a), std::fabs(b));
  return scale == 0.0 ? 0.0 : std::fabs(a - b) / scale;
}

TEST(BsdfConsistency, WeightIsEvalOverPdf) {
  constexpr size_t n = 10000;
  const std::vector<glm::vec4> wo = random_directions(n, 99);
  for (const auto& [name, c] : consistency_configs()) {
    for (cl_int mode : {kRadiance, kImportance}) {
      const Samples s = sample(c, mode, wo, 4242, n);
      std::vector<glm::vec4> wi(n);
      for (size_t i = 0; i < n; ++i) wi[i] = glm::vec4(glm::vec3(s.dir_pdf[i]), 0.0f);
      const std::vector<glm::vec4> e = eval_pairs(c, mode, wo, wi);
      double worst_w = 0.0, worst_pdf = 0.0;
      size_t used = 0;
      for (size_t i = 0; i < n; ++i) {
        if (s.weight[i].w != 0.0f || s.dir_pdf[i].w == 0.0f) continue;  // delta or absorbed
        ++used;
        worst_pdf = std::max(worst_pdf, rel_diff(s.dir_pdf[i].w, e[i].w));
        const glm::dvec3 expected = e[i].w > 0 ? glm::dvec3(glm::vec3(e[i])) / double(e[i].w)
                                                : glm::dvec3(HUGE_VAL);
        worst_w = std::max(worst_w, rel_diff(glm::dvec3(glm::vec3(s.weight[i])), expected));
      }
      std::cout << "[ consist  ] " << name << " mode " << mode << ": " << used
                << " samples, max rel error weight " << worst_w << ", pdf " << worst_pdf << "\n";
      EXPECT_GT(used, n / 4) << name;
      EXPECT_LE(worst_w, 1e-4) << name;
      EXPECT_LE(worst_pdf, 1e-4) << name;
    }
  }
}

// Through the world-space wrapper on random shading frames. The sampled wi is rounded by
// the local -> world transform and back, so eval and pdf are taken at a direction a few ulps
// away from the one sampled: the tolerance is 1e-4 for 99.9 % of samples and 1e-2 for all
// but the grazing ones (GGX at alpha 0.09 changes by ~1e-5 per ulp of direction near its
// peak; the rest are samples within ~1e-6 of the horizon, where cos / pdf is ill-conditioned:
// a direction's ~1e-7 rounding is a relative 1e-7 / cos there). Grazing: the product of wo's
// and wi's cosines with the normal that shades below 1e-5 (seen: 4.6e-7 with an error of
// 1.6 %, tilted_clearcoat_over_delta_coat, after session 28 changed the samples' azimuths);
// those count only against the 99.9 %.
TEST(BsdfConsistency, WorldWrapperAndNoLeaks) {
  constexpr uint32_t n = 10000;
  cl::Context& ctx = test::device_context();
  for (const auto& [name, c] : consistency_configs()) {
    for (cl_int mode : {kRadiance, kImportance}) {
      cl::Buffer cfg = cl::Buffer::from_vector(ctx, pack(c));
      cl::Buffer out(ctx, 4 * n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "world check");
      cl::Kernel kernel(bsdf_program(), "bsdf_world_check");
      kernel.args(0, cfg, mode, cl_uint(31 + mode), out, n);
      kernel.launch(ctx, n);
      const std::vector<glm::vec4> r = out.read_vector<glm::vec4>(4 * n);
      size_t used = 0, loose = 0, leaks = 0, reverse_wrong = 0, grazing = 0;
      double worst = 0.0;
      for (uint32_t i = 0; i < n; ++i) {
        const glm::vec4 ws = r[4 * i], ev = r[4 * i + 1], sides = r[4 * i + 2], wi = r[4 * i + 3];
        const bool nonzero = ws.x > 0 || ws.y > 0 || ws.z > 0;
        // A non-zero sample must agree with the geometric normal about its side: same side
        // as wo for reflection (by the shading normal), the other for transmission.
        if (nonzero && sides.z == 0.0f && sides.x * sides.y <= 0.0f) ++leaks;
        if (nonzero && sides.z != 0.0f && sides.x == 0.0f) ++leaks;
        if (sides.z != 0.0f || !nonzero) continue;
        ++used;
        // The reverse density must not depend on whether the normals were oriented: after a
        // refraction wi lies on the other side (the bdpt rough-glass bias of issue 14).
        reverse_wrong += rel_diff(double(wi.w), double(sides.w)) > 1e-4;
        const double e1 = ev.w > 0 ? 1.0 : 0.0;
        const double err = std::max(
            rel_diff(double(ws.w), double(ev.w)),
            e1 > 0 ? rel_diff(glm::dvec3(glm::vec3(ws)), glm::dvec3(glm::vec3(ev)) / double(ev.w)) : 1.0);
        if (std::fabs(sides.y) >= 1e-5f)
          worst = std::max(worst, err);
        else
          ++grazing;
        loose += err > 1e-4;
      }
      std::cout << "[ world    ] " << name << " mode " << mode << ": " << used << " samples, "
                << loose << " beyond 1e-4, max rel error " << worst << " (" << grazing
                << " grazing samples aside), leaks " << leaks
                << ", reverse pdfs off " << reverse_wrong << "\n";
      EXPECT_EQ(leaks, 0u) << name;
      EXPECT_LE(reverse_wrong, used / 1000) << name;
      // A smooth anisotropic lobe is GGX_ALPHA_DELTA (1e-3) wide across its direction: the
      // ~1e-7 a direction loses in the world frame's round trip moves h.y / alpha by 1e-4,
      // and D by up to a few % in the lobe's tail (seen: 0.5 % and 1.2 %, in a third of the
      // samples). Its weights are exact in the local frame (BsdfConsistency above); here
      // only sides and reverse densities are held to account.
      if (c.anisotropy > 0.0f && c.roughness == 0.0f) continue;
      EXPECT_LE(loose, used / 1000) << name;
      EXPECT_LE(worst, 1e-2) << name;
    }
  }
}

// Next-event estimation takes f |cos| and the BSDF's density from one call
// (bsdf_eval_cos_pdf: one frame, one set of lobes); it must give what the two separate calls
// give: f everywhere, the density wherever f is not 0, in every configuration and mode. The
// same arithmetic runs in both, so the figures agree to the last bit on PoCL (seen: all
// equal); the bound leaves room for a compiler that contracts the two copies differently.
TEST(BsdfConsistency, EvalWithPdfIsEvalAndPdf) {
  constexpr uint32_t n = 4000;
  cl::Context& ctx = test::device_context();
  for (const auto& [name, c] : consistency_configs()) {
    for (cl_int mode : {kRadiance, kImportance}) {
      cl::Buffer cfg = cl::Buffer::from_vector(ctx, pack(c));
      cl::Buffer out(ctx, 2 * n * sizeof(glm::vec4), CL_MEM_WRITE_ONLY, nullptr, "eval pdf");
      cl::Kernel kernel(bsdf_program(), "bsdf_eval_pdf_check");
      kernel.args(0, cfg, mode, cl_uint(57 + mode), out, n);
      kernel.launch(ctx, n);
      const std::vector<glm::vec4> r = out.read_vector<glm::vec4>(2 * n);
      size_t nonzero = 0, exact = 0, wrong = 0;
      for (uint32_t i = 0; i < n; ++i) {
        const glm::vec4 one = r[2 * i], two = r[2 * i + 1];
        const bool black = !(two.x > 0 || two.y > 0 || two.z > 0);
        if (black) {  // the density is not asked for there
          wrong += glm::vec3(one) != glm::vec3(0.0f);
          continue;
        }
        ++nonzero;
        exact += one == two;
        const double err = std::max(rel_diff(double(one.w), double(two.w)),
                                    rel_diff(glm::dvec3(glm::vec3(one)), glm::dvec3(glm::vec3(two))));
        wrong += err > 1e-5;
      }
      EXPECT_EQ(wrong, 0u) << name << " mode " << mode << ": " << nonzero << " non-zero, " << exact
                           << " equal to the last bit";
      if (c.roughness > 0.0f) {
        EXPECT_GT(nonzero, n / 10) << name;  // the check saw the lobes
      }
    }
  }
}

// ---------------------------------------------------------------------------------------
// BsdfEnergy

struct Moments {
  glm::dvec3 mean{0.0}, var{0.0};
};

Moments weight_moments(const Samples& s) {
  Moments m;
  const double n = double(s.weight.size());
  for (const glm::vec4& w : s.weight) m.mean += glm::dvec3(glm::vec3(w));
  m.mean /= n;
  for (const glm::vec4& w : s.weight) {
    const glm::dvec3 d = glm::dvec3(glm::vec3(w)) - m.mean;
    m.var += d * d;
  }
  m.var /= (n - 1.0);
  return m;
}

TEST(BsdfEnergy, AlbedoAtMostOne) {
  std::vector<std::pair<std::string, Config>> configs = consistency_configs();
  // White versions: the largest albedos.
  Config white_plastic = plastic(0.3f);
  white_plastic.base = glm::vec3(1.0f);
  Config white_plastic_rough = plastic(1.0f);
  white_plastic_rough.base = glm::vec3(1.0f);
  Config white_delta_coat = plastic(0.0f);
  white_delta_coat.base = glm::vec3(1.0f);
  Config white_metal = metal(0.3f);
  white_metal.base = glm::vec3(1.0f);
  Config white_metal_smooth = metal(0.0f);
  white_metal_smooth.base = glm::vec3(1.0f);
  Config bright_specular = plastic(0.2f, 1.0f, glm::vec3(100.0f));
  bright_specular.base = glm::vec3(1.0f);
  configs.insert(configs.end(), {{"white_plastic_0.3", white_plastic},
                                 {"white_plastic_1", white_plastic_rough},
                                 {"white_delta_coat", white_delta_coat},
                                 {"white_metal_0.3", white_metal},
                                 {"white_metal_0", white_metal_smooth},
                                 {"f0_1_plastic", bright_specular},
                                 {"smooth_glass", glass(0.0f)},
                                 {"white_clearcoat_plastic", coated(white_plastic, 1.0f, 0.5f)},
                                 {"white_delta_clearcoat", coated(white_plastic_rough, 1.0f, 0.0f)},
                                 {"white_clearcoat_metal", coated(white_metal_smooth, 1.0f, 0.8f)},
                                 {"white_iridescent_metal_0", iridescent(white_metal_smooth, 1.0f, 1.3f, 300.0f)},
                                 {"white_iridescent_metal_0.3", iridescent(white_metal, 1.0f, 2.0f, 600.0f)},
                                 {"white_iridescent_plastic", iridescent(white_plastic, 1.0f, 1.8f, 400.0f)},
                                 {"white_iridescent_delta_coat", iridescent(white_delta_coat, 1.0f, 1.3f, 150.0f)},
                                 {"iridescent_smooth_glass", iridescent(glass(0.0f), 1.0f, 1.5f, 500.0f)},
                                 {"white_translucent_plastic", translucent(white_plastic, 0.5f, glm::vec3(1.0f))},
                                 {"white_translucent_delta_coat", translucent(white_delta_coat, 0.8f, glm::vec3(1.0f))},
                                 {"white_sheen_plastic_0.3", sheened(white_plastic, glm::vec3(1.0f), 0.3f)},
                                 {"white_sheen_lambert_0.05", sheened(lambert(glm::vec3(1.0f)), glm::vec3(1.0f), 0.05f)},
                                 {"white_sheen_lambert_1", sheened(lambert(glm::vec3(1.0f)), glm::vec3(1.0f), 1.0f)},
                                 {"white_sheen_delta_coat", sheened(white_delta_coat, glm::vec3(1.0f), 0.6f)},
                                 {"white_sheen_metal_0", sheened(white_metal_smooth, glm::vec3(1.0f), 0.2f)},
                                 {"white_sheen_under_clearcoat", coated(sheened(white_plastic, glm::vec3(1.0f), 0.5f), 1.0f, 0.3f)},
                                 {"white_anisotropic_metal_0", anisotropic(white_metal_smooth, 1.0f)},
                                 {"white_anisotropic_metal_0.3", anisotropic(white_metal, 0.7f)},
                                 {"white_anisotropic_plastic", anisotropic(white_plastic, 0.9f)},
                                 {"white_tilted_clearcoat_plastic", tilted_coat(coated(white_plastic, 1.0f, 0.5f))},
                                 {"white_tilted_delta_clearcoat", tilted_coat(coated(white_plastic_rough, 1.0f, 0.0f))},
                                 {"white_tilted_delta_clearcoat_over_mirror", tilted_coat(coated(white_metal_smooth, 1.0f, 0.0f))}});
  for (const auto& [name, c] : configs) {
    double worst = 0.0;
    for (int k = 0; k < 10; ++k) {
      // cos from 0.05 to 1; glass also from the inside.
      double cos_o = 0.05 + 0.95 * k / 9.0;
      if (c.transmission > 0 && k % 2) cos_o = -cos_o;
      // Importance mode: its albedo at w is the share of light arriving from w that leaves
      // (the adjoint's), which is what must stay <= 1. A coat with a normal of its own is a
      // shading normal inside the BSDF, whose adjoint gains by wi.z / wo.z as any shading
      // normal's does (Veach 1997 §5.3: up to 2.6 here at grazing wo); its radiance albedo,
      // the coat's own in its frame plus the base beneath, is what stays <= 1 (from outside:
      // inside glass, radiance carries the 1 / eta^2 of refraction).
      if (tilted(c) && cos_o < 0) continue;
      const Samples s = sample(c, tilted(c) ? kRadiance : kImportance, {direction(cos_o)}, 500 + k, 16384);
      const Moments m = weight_moments(s);
      const double a = std::max({m.mean.x, m.mean.y, m.mean.z});
      worst = std::max(worst, a);
      EXPECT_LT(a, 1.01) << name << " cos " << cos_o;
      EXPECT_GE(std::min({m.mean.x, m.mean.y, m.mean.z}), 0.0) << name;
    }
    std::cout << "[ energy   ] " << name << ": max albedo " << worst << "\n";
  }
}

TEST(BsdfEnergy, LambertWhiteIsOne) {
  for (double cos_o : {1.0, 0.5, 0.05}) {
    const Samples s = sample(lambert(glm::vec3(1.0f)), kRadiance, {direction(cos_o)}, 7, 16384);
    const Moments m = weight_moments(s);
    const double sigma = std::sqrt(m.var.x / 16384.0);
    std::cout << "[ energy   ] lambert white cos " << cos_o << ": " << m.mean.x << " +- " << sigma << "\n";
    EXPECT_NEAR(m.mean.x, 1.0, std::max(4.0 * sigma, 1e-5));
  }
}

// A white diffuse layer (specular 0) that transmits a share dt of what it scatters: reflected
// and transmitted together carry everything, from either side, and the transmitted share of
// the samples is dt (the two lobes' albedos are 1 - dt and dt, each a cosine lobe).
TEST(BsdfEnergy, DiffuseTransmissionWhiteIsOne) {
  constexpr uint32_t n = 16384;
  for (double cos_o : {1.0, 0.5, 0.05, -0.7}) {
    const Config c = translucent(lambert(glm::vec3(1.0f)), 0.3f, glm::vec3(1.0f));
    const Samples s = sample(c, kRadiance, {direction(cos_o)}, 9, n);
    const Moments m = weight_moments(s);
    double through = 0.0;
    for (size_t i = 0; i < n; ++i) through += (s.dir_pdf[i].z * cos_o < 0 ? s.weight[i].x : 0.0) / n;
    const double sigma = std::sqrt(m.var.x / n);
    std::cout << "[ energy   ] white diffuse transmission 0.3, cos " << cos_o << ": " << m.mean.x
              << " +- " << sigma << ", through " << through << "\n";
    EXPECT_NEAR(m.mean.x, 1.0, std::max(4.0 * sigma, 1e-5)) << "cos " << cos_o;
    EXPECT_NEAR(through, 0.3, 4.0 * std::sqrt(0.3 * 0.7 / n)) << "cos " << cos_o;
  }
}

// Smooth glass, white: every sample carries R or T, so R + T = 1 exactly in importance mode;
// in radiance mode refraction is scaled by 1 / eta^2: mean = F + (1 - F) / eta^2.
TEST(BsdfEnergy, SmoothGlassWhiteFurnace) {
  constexpr uint32_t n = 1u << 16;
  for (double cos_o : {0.9, 0.4, 0.05, -0.9, -0.6}) {
    const double eta = cos_o > 0 ? 1.5 : 1.0 / 1.5;
    const double F = fresnel_exact(std::fabs(cos_o), eta);
    const Moments imp = weight_moments(sample(glass(0.0f), kImportance, {direction(cos_o)}, 3, n));
    EXPECT_NEAR(imp.mean.x, 1.0, 1e-5) << "cos " << cos_o;
    const Moments rad = weight_moments(sample(glass(0.0f), kRadiance, {direction(cos_o)}, 4, n));
    const double expected = F + (1 - F) / (eta * eta), sigma = std::sqrt(rad.var.x / n);
    std::cout << "[ furnace  ] smooth glass cos " << cos_o << ": importance " << imp.mean.x
              << ", radiance " << rad.mean.x << " vs " << expected << " +- " << sigma << "\n";
    EXPECT_NEAR(rad.mean.x, expected, 5.0 * sigma + 1e-6) << "cos " << cos_o;
  }
}

// ---------------------------------------------------------------------------------------
// BsdfReciprocity

// f = eval / |cos_i| at pairs.
std::vector<glm::dvec3> f_values(const Config& c, cl_int mode, const std::vector<glm::vec4>& wo,
                                 const std::vector<glm::vec4>& wi) {
  const std::vector<glm::vec4> e = eval_pairs(c, mode, wo, wi);
  std::vector<glm::dvec3> f(e.size());
  for (size_t i = 0; i < e.size(); ++i) f[i] = glm::dvec3(glm::vec3(e[i])) / std::fabs(double(wi[i].z));
  return f;
}

// Precision: f is float; at a pair and its reverse the half vector is computed from the same
// two floats (reflection: a + b = b + a exactly) or, for refraction, as a + eta b against
// b + a / eta, a few ulps apart. GGX at alpha 0.09 near its peak changes by ~1e-5 relative per
// ulp of h. Near the critical angle 1 - F cancels and the float inputs themselves decide
// whether a pair refracts at all (cos_t^2 = (eta^2 - 1 + cos_i^2) / eta^2 is ill-conditioned
// there), but f is then tiny: pairs may differ by more than 1e-4 in 0.5 % of the cases, by
// more than 1e-2 only where f < 1e-3 (lobe peaks are of order 1 to 1e2). Pairs with f ~ 1e-4
// differing by ~2 % were seen at glass 0.3 (e.g. a = (0.506, 0.837, 0.209),
// b = (-0.223, -0.448, -0.866)): not yet explained; see the report of the commit.
TEST(BsdfReciprocity, ReflectionAndRefraction) {
  constexpr size_t n = 20000;
  const std::vector<glm::vec4> a = random_directions(n, 11), b = random_directions(n, 12);
  for (const auto& [name, c] : consistency_configs()) {
    const std::vector<glm::dvec3> ab = f_values(c, kRadiance, a, b), ba = f_values(c, kRadiance, b, a);
    const std::vector<glm::dvec3> ab_imp = f_values(c, kImportance, a, b);
    size_t tested = 0, loose = 0, bad = 0, refractions = 0;
    double worst = 0.0;
    for (size_t i = 0; i < n; ++i) {
      double err;
      if (a[i].z * b[i].z > 0) {
        // No eta factor for reflection: importance is the adjoint, f_imp(a, b) = f(b, a), and
        // f symmetric, except for a coat with a normal of its own (a shading normal inside
        // the BSDF: gltf_bsdf.cl), whose radiance f is not.
        err = rel_diff(ab_imp[i], ba[i]);
        if (!tilted(c)) err = std::max(err, rel_diff(ab[i], ba[i]));
      } else {
        // eta of each direction's side: 1 outside (z > 0), ior inside.
        // Diffuse transmission (a thin surface) has none: such configurations have no glass.
        const double ior = c.transmission > 0 ? c.ior : 1.0;
        const double ea = a[i].z > 0 ? 1.0 : ior, eb = b[i].z > 0 ? 1.0 : ior;
        err = rel_diff(ab[i] / (ea * ea), ba[i] / (eb * eb));
        err = std::max(err, rel_diff(ab_imp[i], ba[i]));  // importance is the adjoint
        if (ab[i].x > 0 || ab[i].y > 0 || ab[i].z > 0) ++refractions;
      }
      ++tested;
      const double f_max = std::max({ab[i].x, ab[i].y, ab[i].z, ba[i].x, ba[i].y, ba[i].z});
      if (err > 1e-2 && f_max >= 1e-3 && bad++ < 3)
        std::cout << "  pair a (" << a[i].x << ", " << a[i].y << ", " << a[i].z << ") b (" << b[i].x
                  << ", " << b[i].y << ", " << b[i].z << "): f(a,b) " << ab[i].x << " f(b,a) "
                  << ba[i].x << " f_imp(a,b) " << ab_imp[i].x << "\n";
      loose += err > 1e-4;
      if (f_max >= 1e-3) worst = std::max(worst, err);
    }
    std::cout << "[ recip    ] " << name << ": " << tested << " pairs (" << refractions
              << " refracting), " << loose << " beyond 1e-4, max rel error where f >= 1e-3 "
              << worst << "\n";
    EXPECT_LE(loose, tested / 200) << name;
    EXPECT_EQ(bad, 0u) << name;
    if (c.transmission > 0 && c.roughness > 0.1f) {
      EXPECT_GT(refractions, n / 20) << name;
    }
  }
}

// ---------------------------------------------------------------------------------------
// BsdfLambertLimit: specular 0 (KHR_materials_specular) is exactly Lambert, whatever the
// roughness: f cos = base cos / pi, pdf = cos / pi, and every sample's weight is the base.

TEST(BsdfLambertLimit, SpecularZeroIsLambert) {
  constexpr size_t n = 10000;
  const std::vector<glm::vec4> wo = random_directions(n, 21, true), wi = random_directions(n, 22, true);
  for (float roughness : {0.0f, 0.3f, 1.0f}) {
    Config c = lambert(glm::vec3(0.7f, 0.5f, 0.3f));
    c.roughness = roughness;
    const std::vector<glm::vec4> e = eval_pairs(c, kRadiance, wo, wi);
    double worst = 0.0;
    for (size_t i = 0; i < n; ++i) {
      const double cz = wi[i].z / kPi;
      worst = std::max(worst, rel_diff(glm::dvec3(glm::vec3(e[i])), glm::dvec3(c.base) * cz));
      worst = std::max(worst, rel_diff(double(e[i].w), cz));
    }
    const Samples s = sample(c, kRadiance, wo, 8, n);
    for (size_t i = 0; i < n; ++i) {
      worst = std::max(worst, rel_diff(glm::dvec3(glm::vec3(s.weight[i])), glm::dvec3(c.base)));
      EXPECT_EQ(s.weight[i].w, 0.0f);
    }
    std::cout << "[ lambert  ] specular 0, roughness " << roughness << ": max rel error " << worst << "\n";
    EXPECT_LE(worst, 1e-5);
  }
}

}  // namespace
}  // namespace clpt::bsdf_test
