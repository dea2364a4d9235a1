// ImageStats: the error figures, the z-test and batch means on hand-made images whose
// answers are known exactly, and the z-test's behaviour on seeded random images.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "stats/image_stats.h"
#include "util/error.h"

namespace clpt::image_stats_test {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

Image filled(uint32_t w, uint32_t h, float v) {
  Image img(w, h);
  for (float& x : img.rgb) x = v;
  return img;
}

Image from_values(uint32_t w, uint32_t h, std::vector<float> values) {
  Image img(w, h);
  EXPECT_EQ(values.size(), img.rgb.size());
  img.rgb = std::move(values);
  return img;
}

// Values exactly representable in binary, so the expectations below are exact in double.
TEST(ImageStats, ErrorFiguresOnKnownValues) {
  // Two pixels; channel-wise (v, r): (0.75, 0.25) (0.5, 0.5) (0, 1) | (2, 0) (0.25, 0.25) (1, 0.5)
  const Image v = from_values(2, 1, {0.75f, 0.5f, 0.0f, 2.0f, 0.25f, 1.0f});
  const Image r = from_values(2, 1, {0.25f, 0.5f, 1.0f, 0.0f, 0.25f, 0.5f});
  const ImageComparison c = compare_images(v, r);
  EXPECT_EQ(c.compared, 6u);
  const double rel = (0.25 / (0.26 * 0.26) + 0.0 + 1.0 / (1.01 * 1.01) + 4.0 / (0.01 * 0.01) +
                      0.0 + 0.25 / (0.51 * 0.51)) / 6.0;
  EXPECT_NEAR(c.rel_mse, rel, 1e-12 * rel);
  const double mse = (0.25 + 0.0 + 1.0 + 4.0 + 0.0 + 0.25) / 6.0;
  EXPECT_DOUBLE_EQ(c.mse, mse);
  EXPECT_DOUBLE_EQ(c.rmse, std::sqrt(mse));
  const double smape = (0.5 / 1.0001 + 0.0 + 1.0 / 1.0001 + 2.0 / 2.0001 + 0.0 + 0.5 / 1.5001) / 6.0;
  EXPECT_NEAR(c.smape, smape, 1e-14);
  EXPECT_EQ(c.max_abs_diff, 2.0);
  EXPECT_DOUBLE_EQ(c.image.finite_mean, 4.5 / 6.0);
  EXPECT_DOUBLE_EQ(c.reference.finite_mean, 2.5 / 6.0);
  EXPECT_DOUBLE_EQ(c.image.channel_finite_mean[0], 1.375);
  EXPECT_DOUBLE_EQ(c.image.channel_finite_mean[1], 0.375);
  EXPECT_DOUBLE_EQ(c.image.channel_finite_mean[2], 0.5);
  EXPECT_EQ(c.image.nan_count + c.image.inf_count + c.reference.nan_count + c.reference.inf_count, 0u);
  EXPECT_EQ(c.image.width, 2u);
  EXPECT_EQ(c.image.height, 1u);

  // relMSE is the mean of the per-pixel relative squared error image.
  const Image e = relative_squared_error(v, r);
  EXPECT_FLOAT_EQ(e.rgb[3], float(4.0 / (0.01 * 0.01)));
  EXPECT_FLOAT_EQ(e.rgb[0], float(0.25 / (0.26 * 0.26)));
  EXPECT_EQ(e.rgb[1], 0.0f);
}

TEST(ImageStats, IdenticalImagesHaveZeroError) {
  const Image a = from_values(1, 1, {0.3f, 7.0f, 0.0f});
  const ImageComparison c = compare_images(a, a);
  EXPECT_EQ(c.rel_mse, 0.0);
  EXPECT_EQ(c.mse, 0.0);
  EXPECT_EQ(c.smape, 0.0);
  EXPECT_EQ(c.max_abs_diff, 0.0);
  EXPECT_EQ(c.compared, 3u);
}

// relMSE uses |r|: a negative reference value does not divide by (r + 0.01)² ≈ 0.
TEST(ImageStats, RelMseDenominatorUsesAbsoluteReference) {
  const Image v = from_values(1, 1, {0.0f, 0.0f, 0.0f});
  const Image r = from_values(1, 1, {-0.25f, 0.25f, 0.0f});
  const ImageComparison c = compare_images(v, r);
  const double rel = (0.0625 / (0.26 * 0.26) * 2.0 + 0.0) / 3.0;
  EXPECT_NEAR(c.rel_mse, rel, 1e-12 * rel);
}

TEST(ImageStats, NonFiniteValuesAreCountedAndLeftOut) {
  const Image v = from_values(2, 1, {kNaN, 1.0f, kInf, -kInf, 2.0f, 0.5f});
  const Image r = from_values(2, 1, {1.0f, 0.5f, 1.0f, 1.0f, kNaN, 0.5f});
  const ImageComparison c = compare_images(v, r);
  EXPECT_EQ(c.image.nan_count, 1u);
  EXPECT_EQ(c.image.inf_count, 2u);
  EXPECT_EQ(c.reference.nan_count, 1u);
  EXPECT_EQ(c.reference.inf_count, 0u);
  EXPECT_EQ(c.compared, 2u);  // (1, 0.5) and (0.5, 0.5)
  EXPECT_DOUBLE_EQ(c.mse, 0.25 / 2.0);
  EXPECT_EQ(c.max_abs_diff, 0.5);
  EXPECT_DOUBLE_EQ(c.image.finite_mean, (1.0 + 2.0 + 0.5) / 3.0);
  EXPECT_TRUE(std::isnan(relative_squared_error(v, r).rgb[0]));

  const Image all_nan = filled(1, 1, kNaN);
  const ImageComparison n = compare_images(all_nan, all_nan);
  EXPECT_EQ(n.compared, 0u);
  EXPECT_TRUE(std::isnan(n.rel_mse));
  EXPECT_TRUE(std::isnan(n.image.finite_mean));
  EXPECT_EQ(n.image.nan_count, 3u);
}

TEST(ImageStats, SizeMismatchIsAUsageErrorNamingBothSizes) {
  const Image a(2, 1), b(1, 2);
  try {
    compare_images(a, b);
    FAIL() << "no error for different sizes";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::Usage);
    EXPECT_NE(std::string(e.what()).find("2x1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("1x2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(relative_squared_error(a, b), Error);
  EXPECT_THROW(z_test(a, &a, b, nullptr), Error);
  EXPECT_THROW(z_test(a, &b, a, nullptr), Error);  // variance of another size
  EXPECT_THROW(batch_mean({a, b}), Error);
}

// Quantiles of the standard normal: P(|Z| > t) = p.
TEST(ImageStats, SidakThresholdMatchesNormalQuantiles) {
  EXPECT_NEAR(sidak_z_threshold(0.05, 1), 1.959963984540054, 1e-12);
  EXPECT_NEAR(sidak_z_threshold(0.01, 1), 2.5758293035489, 1e-12);
  EXPECT_NEAR(sidak_z_threshold(0.01, 0), 2.5758293035489, 1e-12);
  // n = 1000: p = 1 − 0.99^(1/1000) = 1.00502e-5, t = Φ⁻¹(1 − p/2).
  const double p = 1.0 - std::pow(0.99, 1.0 / 1000.0);
  const double t = sidak_z_threshold(0.01, 1000);
  EXPECT_NEAR(std::erfc(t / std::sqrt(2.0)), p, 1e-9 * p);  // p above loses ~1e-11 to cancellation
  EXPECT_NEAR(t, 4.41609, 1e-4);  // two-sided p = 1e-5 is 4.41717; dz = -dp / (2φ(z))
  // Large n keeps its precision (p ≈ 1e-10).
  const double t9 = sidak_z_threshold(0.01, 100000000);
  const double p9 = -std::expm1(std::log1p(-0.01) / 1e8);
  EXPECT_NEAR(std::erfc(t9 / std::sqrt(2.0)), p9, 1e-9 * p9);
  EXPECT_GT(t9, t);
  EXPECT_THROW(sidak_z_threshold(0.0, 10), Error);
  EXPECT_THROW(sidak_z_threshold(1.0, 10), Error);
}

// z = |v − r| / sqrt(var_v + var_r) on hand-made values: exact counts at a given threshold.
TEST(ImageStats, ZTestOnKnownValues) {
  // Differences 0.3, 0.5, 0.9 | 0, 0.2, 2.0 with variances summing to 0.01 → z 3, 5, 9 | 0, 2, 20.
  const Image v = from_values(2, 1, {1.3f, 1.5f, 1.9f, 1.0f, 1.2f, 3.0f});
  const Image r = from_values(2, 1, {1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f});
  const Image var_v = filled(2, 1, 0.004f), var_r = filled(2, 1, 0.006f);
  ZTestOptions o;
  o.threshold = 4.0;
  o.relative_variance_floor = 0.0;
  ZTestResult z = z_test(v, &var_v, r, &var_r, o);
  EXPECT_EQ(z.tested, 6u);
  EXPECT_EQ(z.passed, 3u);  // 3, 0, 2
  EXPECT_EQ(z.failed(), 3u);
  EXPECT_DOUBLE_EQ(z.pass_fraction(), 0.5);
  EXPECT_NEAR(z.max_abs_z, 20.0, 1e-4);
  EXPECT_EQ(z.threshold, 4.0);
  // One variance alone (the other image taken as exact). var 0.004: z = 4.74, 7.91, 14.2 |
  // 0, 3.16, 31.6, so two pass.
  z = z_test(v, &var_v, r, nullptr, o);
  EXPECT_EQ(z.passed, 2u);
  EXPECT_NEAR(z.max_abs_z, 2.0 / std::sqrt(0.004), 1e-3);
  // var 0.006: z = 3.87, 6.45, 11.6 | 0, 2.58, 25.8, so three pass.
  z = z_test(v, nullptr, r, &var_r, o);
  EXPECT_EQ(z.passed, 3u);
  // Šidák threshold for n = 6 when none is given.
  o.threshold = 0.0;
  z = z_test(v, &var_v, r, &var_r, o);
  EXPECT_DOUBLE_EQ(z.threshold, sidak_z_threshold(0.01, 6));
  EXPECT_EQ(z.alpha, 0.01);
  EXPECT_THROW(z_test(v, nullptr, r, nullptr, o), Error);
}

TEST(ImageStats, ZTestVarianceFloorAndNonFinite) {
  // Zero variance: the floor 1e-4·max(|v|,|r|)² gives σ = 1 % of the value.
  const Image r = from_values(1, 1, {2.0f, 0.0f, 2.0f});
  const Image v = from_values(1, 1, {2.01f, 0.0f, 2.2f});  // z = 0.50, 0 (both zero), 9.09
  const Image zero = filled(1, 1, 0.0f);
  ZTestOptions o;
  o.threshold = 4.0;
  ZTestResult z = z_test(v, &zero, r, &zero, o);
  EXPECT_EQ(z.tested, 3u);
  EXPECT_EQ(z.passed, 2u);
  EXPECT_NEAR(z.max_abs_z, 0.2 / (0.01 * 2.2), 1e-4);
  // Negative variances count as 0, so the floor decides again.
  const Image negative = filled(1, 1, -1.0f);
  z = z_test(v, &negative, r, nullptr, o);
  EXPECT_EQ(z.passed, 2u);

  const Image vn = from_values(1, 1, {kNaN, 1.0f, 1.0f});
  const Image varn = from_values(1, 1, {1.0f, kInf, 1.0f});
  z = z_test(vn, &varn, from_values(1, 1, {1.0f, 1.0f, 1.0f}), nullptr, o);
  EXPECT_EQ(z.tested, 1u);
  EXPECT_EQ(z.skipped, 2u);
  EXPECT_EQ(z.passed, 1u);

  const Image nan_only = filled(1, 1, kNaN);
  z = z_test(nan_only, &zero, nan_only, nullptr);
  EXPECT_EQ(z.tested, 0u);
  EXPECT_TRUE(std::isnan(z.pass_fraction()));
}

// A simulated render: each pixel-channel's mean and variance of the mean from `spp` normal
// samples around mu·scale with standard deviation 0.5·mu.
struct Simulated {
  Image mean, var_mean;
};

Simulated simulate(const Image& mu, int spp, double scale, std::mt19937& rng) {
  Simulated s{Image(mu.width, mu.height), Image(mu.width, mu.height)};
  for (size_t i = 0; i < mu.rgb.size(); ++i) {
    std::normal_distribution<double> d(mu.rgb[i] * scale, 0.5 * mu.rgb[i]);
    double sum = 0.0, sq = 0.0;
    for (int k = 0; k < spp; ++k) {
      const double x = d(rng);
      sum += x;
      sq += x * x;
    }
    const double m = sum / spp;
    s.mean.rgb[i] = float(m);
    s.var_mean.rgb[i] = float((sq - spp * m * m) / (spp - 1) / spp);
  }
  return s;
}

Image random_truth(uint32_t w, uint32_t h, std::mt19937& rng) {
  Image mu(w, h);
  std::uniform_real_distribution<float> u(0.1f, 2.0f);
  for (float& x : mu.rgb) x = u(rng);
  return mu;
}

TEST(ImageStats, ZTestPassesSameDistributionAndFailsShifted) {
  std::mt19937 rng(20261122);
  const Image mu = random_truth(32, 32, rng);
  const Simulated ref = simulate(mu, 1024, 1.0, rng);
  const Simulated same = simulate(mu, 64, 1.0, rng);
  const ZTestResult ok = z_test(same.mean, &same.var_mean, ref.mean, &ref.var_mean);
  EXPECT_EQ(ok.tested, 32u * 32u * 3u);
  EXPECT_GE(ok.pass_fraction(), 0.99) << "max |z| " << ok.max_abs_z << " threshold " << ok.threshold;

  // A 50 % bias is about 7.8σ of the difference per pixel-channel (σ of the mean 6.25 % at
  // 64 spp, 1.6 % at 1024), far beyond the Šidák threshold (≈ 4.6 for 3072 tests).
  const Simulated biased = simulate(mu, 64, 1.5, rng);
  const ZTestResult bad = z_test(biased.mean, &biased.var_mean, ref.mean, &ref.var_mean);
  EXPECT_LT(bad.pass_fraction(), 0.5);
  EXPECT_GT(bad.failed(), 0u);
}

// With the exact variances, z is |N(0, 1)|: the fraction below 1.96 is 95 % within binomial
// noise (σ ≈ 0.2 % over 12288 tests). A z computed with the wrong variance (one image's only,
// no square root, σ instead of σ²) moves it far outside 5σ.
TEST(ImageStats, ZTestIsCalibrated) {
  std::mt19937 rng(7);
  const uint32_t w = 64, h = 64;
  const Image mu = random_truth(w, h, rng);
  Image v(w, h), r(w, h), var_v(w, h), var_r(w, h);
  for (size_t i = 0; i < mu.rgb.size(); ++i) {
    const double sv = 0.05 * mu.rgb[i], sr = 0.03 * mu.rgb[i];
    v.rgb[i] = float(std::normal_distribution<double>(mu.rgb[i], sv)(rng));
    r.rgb[i] = float(std::normal_distribution<double>(mu.rgb[i], sr)(rng));
    var_v.rgb[i] = float(sv * sv);
    var_r.rgb[i] = float(sr * sr);
  }
  ZTestOptions o;
  o.threshold = 1.959963984540054;
  o.relative_variance_floor = 0.0;
  const ZTestResult z = z_test(v, &var_v, r, &var_r, o);
  const double n = double(z.tested), sigma = std::sqrt(0.95 * 0.05 / n);
  EXPECT_NEAR(z.pass_fraction(), 0.95, 5.0 * sigma);
}

TEST(ImageStats, MeansAndVariances) {
  const Image a = from_values(2, 1, {1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f});
  EXPECT_DOUBLE_EQ(image_mean(a), 3.5);
  EXPECT_DOUBLE_EQ(mean_variance(a), 3.5);
  EXPECT_TRUE(std::isnan(image_mean(from_values(1, 1, {1.0f, kNaN, 1.0f}))));
  EXPECT_TRUE(std::isnan(image_mean(Image())));

  const Image vm = variance_of_mean(a, 4);
  EXPECT_EQ(vm.rgb[0], 0.25f);
  EXPECT_EQ(vm.rgb[5], 1.5f);
  EXPECT_EQ(variance_of_mean(a, 0).rgb[3], 0.0f);

  EXPECT_DOUBLE_EQ(efficiency(0.25, 2.0), 2.0);
  EXPECT_TRUE(std::isinf(efficiency(0.0, 2.0)));
}

// Three batches with means 1, 2, 3 (per channel 1/2/3, 2/3/4, ...): mean 2, sd 1, σ = 1/√3.
TEST(ImageStats, BatchMeanAndSigma) {
  std::vector<Image> batches;
  for (float m : {1.0f, 2.0f, 3.0f})
    batches.push_back(from_values(2, 1, {m - 1, m, m + 1, m + 1, m, m - 1}));
  const BatchMean b = batch_mean(batches);
  EXPECT_EQ(b.batches, 3u);
  EXPECT_DOUBLE_EQ(b.mean, 2.0);
  EXPECT_DOUBLE_EQ(b.sigma, 1.0 / std::sqrt(3.0));
  for (int c = 0; c < 3; ++c) {
    EXPECT_DOUBLE_EQ(b.channel_mean[c], 2.0);
    EXPECT_DOUBLE_EQ(b.channel_sigma[c], 1.0 / std::sqrt(3.0));
  }
  EXPECT_THROW(batch_mean({batches[0]}), Error);
  // Identical batches: σ = 0.
  EXPECT_EQ(batch_mean({batches[1], batches[1]}).sigma, 0.0);
}

// Batch σ is a real standard error: for i.i.d. noisy batches, z = (mean − truth)/σ is
// Student t with B − 1 = 15 degrees of freedom, E[z²] = 15/13. Over 400 seeded trials the
// mean of z² has sd ≈ 0.09; a σ without its 1/√B would give E[z²] ≈ 0.07.
TEST(ImageStats, BatchSigmaIsAStandardError) {
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 0.1f);
  double sum_z2 = 0.0;
  const int trials = 400;
  for (int t = 0; t < trials; ++t) {
    std::vector<Image> batches;
    for (int b = 0; b < 16; ++b) {
      Image img(4, 4);
      for (float& x : img.rgb) x = 1.0f + noise(rng);
      batches.push_back(std::move(img));
    }
    const BatchMean m = batch_mean(batches);
    const double z = (m.mean - 1.0) / m.sigma;
    sum_z2 += z * z;
  }
  EXPECT_NEAR(sum_z2 / trials, 15.0 / 13.0, 0.4);
}

}  // namespace
}  // namespace clpt::image_stats_test
