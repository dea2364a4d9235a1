// The conformance matrix (issue 14): every estimator against a high-spp pt reference, on
// small scenes of one object (tests/support/stage.h) covering every material class and every
// light kind, parametrised over one estimator list rather than copied per integrator (the
// shape of Mitsuba 3's test_integrators.py).
//
// A cell is (estimator, material, light). The full product (9 x 13 x 8) would not fit the
// suite's time, so the cells form a covering design: each material is lit by one light kind,
// the kinds in rotation so that every one appears, plus the pairs the issue named; every
// estimator renders every such scene, so each meets every material and every light kind
// (MatrixDesign.CoversEveryPair checks it) and one pt reference per scene serves them all. Each cell renders B independent batches and compares, per region
// (the object, the floor around it, the rest), the mean over the batches of the region's
// channel-mean radiance with the reference's: Student-t with B - 1 degrees of freedom and the
// reference's own variance, Sidak-corrected over every region of every cell (alpha 0.01);
// and for pt (MIS), bdpt and vcm a per-pixel test of the same kind, 99 % of each cell's
// pixel-channels passing.
// Biased estimators (pm) pass when the relative difference is within the cell's stated bound
// (docs/TESTING.md) plus that threshold's noise; what an estimator cannot see by design is
// masked, with the reason.
//
// CLPT_MATRIX_VERBOSE=1 prints every region's figures, including cells that pass;
// CLPT_MATRIX_DUMP=DIR writes each cell's reference and first batch there as EXR.
#include <gtest/gtest.h>

#include <boost/math/distributions/students_t.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "integrators/integrator.h"
#include "io/image_io.h"
#include "support/reference_match.h"
#include "support/reference_render.h"
#include "support/stage.h"

namespace clpt::conformance_matrix_test {
namespace {

using test::StageLight;
using test::StageMaterial;

constexpr uint32_t kSize = 24;
constexpr uint64_t kReferenceSpp = 8192;
constexpr uint32_t kBatches = 16;

struct Estimator {
  const char* name;
  const char* integrator;
  uint32_t direct;  // dev::DirectStrategy for pt
  uint64_t spp;     // per batch
  // The relative bias the estimator's regions may show, with its reason: pm's kNN density
  // estimation (50 photons), sppm's radius after 64 passes, ic's interpolation between
  // records (docs/TESTING.md); 0: unbiased.
  double bias_bound;
  // Per-pixel test: only for the MIS estimators. A single strategy is heavy-tailed by
  // construction somewhere in the matrix (BSDF sampling of the small panel, light sampling
  // of the environment through rough glass, lt's connections through glass and glossy
  // metal): 16 batches then see a pixel's rare large samples in none or one of them, and
  // the batches' spread says nothing of its variance (measured: 3 to 26 % of the pixels of
  // such cells beyond the threshold, while their region means agree).
  bool per_pixel;
};

const std::vector<Estimator>& estimators() {
  static const std::vector<Estimator> list = {
      {"pt_mis", "pt", 0, 64, 0.0, true},     {"pt_light", "pt", 1, 64, 0.0, false},
      {"pt_bsdf", "pt", 2, 64, 0.0, false},   {"lt", "lt", 0, 64, 0.0, false},
      {"bdpt", "bdpt", 0, 24, 0.0, true},     {"pm", "pm", 0, 8, 0.10, false},
      {"sppm", "sppm", 0, 64, 0.05, false},   {"mlt", "mlt", 0, 64, 0.0, false},
      {"vcm", "vcm", 0, 24, 0.0, true},     {"ic", "ic", 0, 64, 0.05, false},
  };
  return list;
}

const std::vector<StageMaterial>& materials() {
  static const std::vector<StageMaterial> list = {
      StageMaterial::Lambert,       StageMaterial::Metal005,       StageMaterial::Metal03,
      StageMaterial::Metal1,        StageMaterial::GlassSmooth,    StageMaterial::GlassRough,
      StageMaterial::GlassAbsorbing, StageMaterial::GlassSheet,    StageMaterial::Specular,
      StageMaterial::NormalMap,     StageMaterial::AlphaMask,      StageMaterial::AlphaBlend,
      StageMaterial::EmissiveTexture, StageMaterial::Clearcoat,   StageMaterial::IridescentGlass,
      StageMaterial::Translucent,   StageMaterial::Sheen,          StageMaterial::Anisotropic,
      StageMaterial::DispersiveGlass,
  };
  return list;
}

const std::vector<StageLight>& lights() {
  static const std::vector<StageLight> list = {
      StageLight::AreaDown, StageLight::AreaUp,  StageLight::AreaSide,    StageLight::AreaDouble,
      StageLight::Point,    StageLight::Spot,    StageLight::Directional, StageLight::Environment,
  };
  return list;
}

struct Cell {
  size_t estimator;
  StageMaterial material;
  StageLight light;
};

// pt, the reference, cannot find a delta light's caustic through smooth glass (a path
// L -> specular -> diffuse -> camera has no NEE and no BSDF-sampled way to hit a point), so
// smooth glass never meets a delta light here; bdpt and the photon mappers would be right
// and the reference wrong.
bool allowed(StageMaterial m, StageLight l) {
  return !(m == StageMaterial::GlassSmooth && test::stage_light_is_delta(l));
}

// The scenes: each material once, with the lights in rotation (every light kind appears),
// then the pairs issue 14 reported. Every estimator renders every scene, so a scene's pt
// reference serves all of them.
std::vector<std::pair<StageMaterial, StageLight>> scenes() {
  std::vector<std::pair<StageMaterial, StageLight>> list;
  auto add = [&](StageMaterial m, StageLight l) {
    for (const auto& p : list)
      if (p.first == m && p.second == l) return;
    list.push_back({m, l});
  };
  const size_t nl = lights().size();
  for (size_t i = 0; i < materials().size(); ++i) {
    size_t k = i % nl;
    while (!allowed(materials()[i], lights()[k])) k = (k + 1) % nl;
    add(materials()[i], lights()[k]);
  }
  add(StageMaterial::Lambert, StageLight::AreaUp);
  add(StageMaterial::GlassRough, StageLight::AreaDown);
  add(StageMaterial::GlassAbsorbing, StageLight::AreaDown);
  // The clearcoat's glossy highlight of an area light (its row above has the spot light).
  add(StageMaterial::Clearcoat, StageLight::AreaDown);
  // The film on rough glass under the area light too (its row above has the directional).
  add(StageMaterial::IridescentGlass, StageLight::AreaDown);
  // Light through the translucent object into its shadow on the floor.
  add(StageMaterial::Translucent, StageLight::AreaDown);
  // The brushed metal's stretched highlight of the area light (its row above has AreaUp).
  add(StageMaterial::Anisotropic, StageLight::AreaDown);
  return list;
}

std::vector<Cell> design() {
  std::vector<Cell> cells;
  for (const auto& [m, l] : scenes())
    for (size_t e = 0; e < estimators().size(); ++e) cells.push_back({e, m, l});
  return cells;
}

std::string cell_name(const Cell& c) {
  return std::string(estimators()[c.estimator].name) + "_" + test::stage_material_name(c.material) +
         "_" + test::stage_light_name(c.light);
}

// Regions an estimator cannot see by design, with the reason (empty: none).
std::string masked(const Cell& c, int region) {
  const std::string e = estimators()[c.estimator].name;
  if (e == "lt" && c.material == StageMaterial::GlassSmooth && region == test::REGION_OBJECT)
    return "lt cannot connect the camera to a delta surface: what the camera sees in smooth glass";
  return "";
}

size_t total_tests() { return design().size() * test::REGION_COUNT; }

double threshold() {
  const double per_test = 1.0 - std::pow(0.99, 1.0 / double(total_tests()));
  return boost::math::quantile(
      boost::math::complement(boost::math::students_t(double(kBatches - 1)), per_test / 2.0));
}

double region_mean(const Image& img, const std::vector<uint8_t>& regions, int r) {
  double sum = 0.0;
  size_t n = 0;
  for (uint32_t y = 0; y < img.height; ++y)
    for (uint32_t x = 0; x < img.width; ++x) {
      if (regions[size_t(y) * img.width + x] != r) continue;
      const float* p = img.pixel(x, y);
      sum += (double(p[0]) + p[1] + p[2]) / 3.0;
      ++n;
    }
  return n ? sum / double(n) : 0.0;
}

// Variance of the reference's region mean: per-pixel variances of the mean, pixels independent.
double region_mean_variance(const FilmResult& ref, const std::vector<uint8_t>& regions, int r) {
  double sum = 0.0;
  size_t n = 0;
  for (uint32_t y = 0; y < ref.variance.height; ++y)
    for (uint32_t x = 0; x < ref.variance.width; ++x) {
      if (regions[size_t(y) * ref.variance.width + x] != r) continue;
      const float* v = ref.variance.pixel(x, y);
      // The channel mean's variance, bounded by assuming full correlation between channels.
      const double sd = (std::sqrt(double(v[0])) + std::sqrt(double(v[1])) + std::sqrt(double(v[2]))) / 3.0;
      sum += sd * sd / double(ref.samples_per_pixel);
      ++n;
    }
  return n ? sum / (double(n) * double(n)) : 0.0;
}

bool verbose() {
  const char* v = std::getenv("CLPT_MATRIX_VERBOSE");
  return v && *v && std::string(v) != "0";
}

class ConformanceMatrix : public ::testing::TestWithParam<Cell> {};

TEST_P(ConformanceMatrix, AgreesWithPtReference) {
  const Cell c = GetParam();
  const Estimator& est = estimators()[c.estimator];
  const std::string scene_label = "matrix_" + test::stage_material_name(c.material) + "_" +
                                  test::stage_light_name(c.light);
  auto build = [&] { return test::stage_scene(c.material, c.light); };
  const FilmResult ref = test::pt_reference(scene_label + " stage-v2", build,
                                            test::stage_settings(c.light, "pt", kReferenceSpp, kSize), 1);
  ASSERT_EQ(ref.dropped_samples, 0u);
  RenderSettings s = test::stage_settings(c.light, est.integrator, est.spp, kSize);
  s.direct = est.direct;
  if (std::string(est.integrator) == "pm") {
    s.pm.photons = 100000;
    s.pm.caustic_photons = 200000;
  }
  // mmlt: paths per path length, b to a few per cent per batch (the batches see its error)
  if (std::string(est.integrator) == "mlt") s.mlt.bootstrap = 5000;
  // vcm: a quarter of a pixel footprint at the object, so that merging's bias stays far
  // below the batches' noise (the estimator is tested as unbiased).
  if (std::string(est.integrator) == "vcm") s.vcm.radius = 0.006f;
  if (std::string(est.integrator) == "sppm") {
    s.sppm.photons = 16384;
    s.sppm.radius = 0.012f;  // half a pixel footprint at the object: the blur bias stays small
  }
  const std::vector<Image> batches = test::render_batches(build(), s, kBatches, 100);
  const std::vector<uint8_t> regions = test::stage_regions(c.material, kSize);
  if (const char* dir = std::getenv("CLPT_MATRIX_DUMP")) {
    write_image(std::string(dir) + "/" + scene_label + "_ref.exr", ref.mean, ImageMetadata{});
    write_image(std::string(dir) + "/" + cell_name(c) + ".exr", batches[0], ImageMetadata{});
  }
  const double t_max = threshold();
  for (int r = 0; r < test::REGION_COUNT; ++r) {
    const std::string why = masked(c, r);
    std::vector<double> m(kBatches);
    double mean = 0.0;
    for (uint32_t b = 0; b < kBatches; ++b) mean += (m[b] = region_mean(batches[b], regions, r));
    mean /= kBatches;
    double var = 0.0;
    for (double v : m) var += (v - mean) * (v - mean);
    var /= double(kBatches - 1) * kBatches;
    const double reference = region_mean(ref.mean, regions, r);
    const double ref_var = region_mean_variance(ref, regions, r);
    const double sigma = std::sqrt(var + ref_var + 1e-14);
    const double bound = est.bias_bound * std::fabs(reference);
    const double excess = std::max(0.0, std::fabs(mean - reference) - bound);
    const double t = excess / sigma;
    std::ostringstream line;
    line << cell_name(c) << " " << test::stage_region_name(r) << ": " << mean << " / reference "
         << reference << " = " << (reference != 0.0 ? mean / reference : 0.0) << ", sigma " << sigma
         << ", t " << (mean - reference) / sigma << (bound > 0.0 ? " (beyond the bias bound: " : "")
         << (bound > 0.0 ? std::to_string(t) + ")" : "") << (why.empty() ? "" : " [masked: " + why + "]");
    if (verbose() || (t >= t_max && why.empty())) std::cout << "[ matrix   ] " << line.str() << "\n";
    if (!why.empty()) continue;
    EXPECT_LT(t, t_max) << line.str();
  }

  // Per pixel, for the MIS estimators (Estimator::per_pixel): the batch mean against the
  // reference, Student-t with the batches' spread and the reference's variance,
  // Sidak-corrected over the cell's unmasked pixel-channels. Heavy-tailed pixels (a caustic
  // seen through glass) may fail now and then, so the cell needs 99 % of them to pass: a bias
  // over more than 1 % of the image fails.
  if (!est.per_pixel) return;
  size_t tested = 0, failed = 0;
  double worst = 0.0;
  std::vector<std::pair<size_t, int>> cells;
  for (size_t i = 0; i < regions.size(); ++i)
    if (masked(c, regions[i]).empty())
      for (int ch = 0; ch < 3; ++ch) cells.push_back({i, ch});
  const double per_test = 1.0 - std::pow(0.99, 1.0 / double(std::max<size_t>(cells.size(), 1)));
  const double t_pixel = boost::math::quantile(
      boost::math::complement(boost::math::students_t(double(kBatches - 1)), per_test / 2.0));
  for (const auto& [i, ch] : cells) {
    double mean = 0.0, var = 0.0;
    for (const Image& b : batches) mean += b.rgb[3 * i + ch];
    mean /= kBatches;
    for (const Image& b : batches) var += (b.rgb[3 * i + ch] - mean) * (b.rgb[3 * i + ch] - mean);
    var /= double(kBatches - 1) * kBatches;
    const double r = ref.mean.rgb[3 * i + ch];
    const double rv = ref.variance.rgb[3 * i + ch] / double(ref.samples_per_pixel);
    const double floor = 1e-8 + 1e-6 * std::max(mean * mean, r * r);
    const double tp = std::fabs(mean - r) / std::sqrt(var + rv + floor);
    worst = std::max(worst, tp);
    ++tested;
    failed += tp >= t_pixel;
  }
  const double pass = tested ? 1.0 - double(failed) / double(tested) : 1.0;
  if (verbose() || pass < 0.99)
    std::cout << "[ matrix   ] " << cell_name(c) << " pixels: " << failed << " of " << tested
              << " pixel-channels beyond |t| " << t_pixel << " (max " << worst << ")\n";
  EXPECT_GE(pass, 0.99) << cell_name(c) << ": " << failed << " of " << tested
                        << " pixel-channels fail the per-pixel test";
}

INSTANTIATE_TEST_SUITE_P(Cells, ConformanceMatrix, ::testing::ValuesIn(design()),
                         [](const ::testing::TestParamInfo<Cell>& info) { return cell_name(info.param); });

// The design itself: every estimator meets every material and every light kind, and the
// issue's cases are cells.
TEST(MatrixDesign, CoversEveryPair) {
  std::map<size_t, std::set<int>> mats, lits;
  for (const Cell& c : design()) {
    mats[c.estimator].insert(int(c.material));
    lits[c.estimator].insert(int(c.light));
    EXPECT_TRUE(allowed(c.material, c.light)) << cell_name(c);
  }
  for (size_t e = 0; e < estimators().size(); ++e) {
    EXPECT_EQ(mats[e].size(), materials().size()) << estimators()[e].name;
    EXPECT_EQ(lits[e].size(), lights().size()) << estimators()[e].name;
  }
  std::cout << "[ figures  ] " << design().size() << " cells, " << total_tests()
            << " region tests, |t| threshold " << threshold() << "\n";
}

// The matrix is shaped like the integrator table: every implemented row is one of its
// estimators, or is named here with the reason it is not. A new integrator cannot be left
// out of the matrix unnoticed, and a row named here that joins the matrix must leave the list.
TEST(MatrixDesign, CoversEveryIntegratorOfTheTable) {
  const std::map<std::string, std::string> outside = {
      {"ao", "ambient occlusion is no light transport: nothing for pt to agree with"},
      {"direct", "pt cut at one bounce (its code is pt_render's): the pt rows run it"},
      {"indirect1", "light after exactly one bounce, another quantity: IndirectFurnace and "
                    "IndirectGeneratorsAgree check it"},
  };
  for (const IntegratorInfo& row : integrator_table()) {
    if (!row.implemented) continue;
    const bool in_matrix = std::any_of(estimators().begin(), estimators().end(),
                                       [&](const Estimator& e) { return row.name == std::string(e.integrator); });
    const auto why = outside.find(row.name);
    if (why == outside.end())
      EXPECT_TRUE(in_matrix) << row.name << " is in neither the matrix nor the list of rows left out";
    else
      EXPECT_FALSE(in_matrix) << row.name << " is in the matrix: take it off the list (" << why->second << ")";
  }
}

}  // namespace
}  // namespace clpt::conformance_matrix_test
