// Image statistics for judging a renderer as an estimator: error against a reference
// (relMSE, MSE, RMSE, SMAPE), NaN/Inf counts, a per-pixel z-test with a Šidák-corrected
// threshold, image means with a σ from independent batches, and efficiency.
//
// All functions are pure: they read images and return numbers. Sums are taken in double.
// Every function that takes two or more images throws Error(ExitCode::Usage), naming both
// sizes, when their sizes differ. The formulas are written out in docs/clpt-diff.md.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "io/image.h"

namespace clpt {

// The offset in relMSE's denominator, (|r| + kRelMseOffset)², so that black reference pixels
// do not divide by zero (../shared/TESTING.md: relMSE = mean((v − r)² / (r + 0.01)²)).
inline constexpr double kRelMseOffset = 0.01;
// The offset in SMAPE's denominator, |v| + |r| + kSmapeOffset.
inline constexpr double kSmapeOffset = 1e-4;
// Default z-test variance floor, relative to the larger value squared (see ZTestOptions).
inline constexpr double kRelativeVarianceFloor = 1e-4;

// One image on its own. NaN and ±Inf are counted per pixel-channel (3 per pixel).
struct ImageSummary {
  uint32_t width = 0, height = 0;
  size_t nan_count = 0;        // pixel-channels that are NaN
  size_t inf_count = 0;        // pixel-channels that are +Inf or −Inf
  double finite_mean = 0.0;    // mean of the finite pixel-channels; NaN when there are none
  std::array<double, 3> channel_finite_mean{};  // the same per channel (R, G, B)
};

ImageSummary summarize(const Image& image);

// An image v against a reference r. The error figures are means over the pixel-channels
// where both v and r are finite (`compared` of them); NaN when there are none. Non-finite
// values are reported by the two summaries' counts, never folded into the error figures.
struct ImageComparison {
  ImageSummary image, reference;
  size_t compared = 0;        // pixel-channels with both values finite
  double rel_mse = 0.0;       // mean((v − r)² / (|r| + 0.01)²)
  double mse = 0.0;           // mean((v − r)²)
  double rmse = 0.0;          // sqrt(mse)
  double smape = 0.0;         // mean(|v − r| / (|v| + |r| + 1e-4)), in [0, 1)
  double max_abs_diff = 0.0;  // max |v − r|
};

ImageComparison compare_images(const Image& image, const Image& reference);

// Per pixel-channel relative squared error (v − r)² / (|r| + 0.01)², NaN where either value
// is not finite. relMSE is the mean of this image's finite values.
Image relative_squared_error(const Image& image, const Image& reference);

// ---- Per-pixel z-test ------------------------------------------------------------------
//
// For each pixel-channel, z = |v − r| / sqrt(max(var_v + var_r, floor)), where var_v and
// var_r are the variances of the two MEAN estimates (sample variance / spp), either of
// which may be absent (taken as 0: that image is treated as exact). The floor is
// relative_variance_floor · max(|v|, |r|)²: with the default 1e-4 the standard deviation
// used is never below 1 % of the pixel's value. That only matters for pixels whose
// estimated variance is (nearly) zero — emitters seen directly, black background, or
// pixels whose few samples happened to be equal — where float accumulation over many
// samples can move the mean by a few 1e-3 relative and would otherwise give huge z from a
// harmless rounding difference. Where both values are 0 the difference is 0 and z = 0.
//
// The threshold t is Šidák-corrected for the n pixel-channels tested: each test has size
// p = 1 − (1 − α)^(1/n) and t solves P(|Z| > t) = p for a standard normal Z, so under the
// null hypothesis (same expectation, z ≈ N(0, 1)) the chance that ANY pixel-channel fails
// is α. Counting the three channels of a pixel as separate tests makes t slightly larger
// than counting pixels; since channels of one pixel are positively correlated, that errs
// on the conservative side. z is close to normal only when the variances are estimated
// from enough samples (t-distributed with spp − 1 degrees of freedom otherwise): use
// spp ≥ 32 or so for the image under test.

struct ZTestOptions {
  double alpha = 0.01;       // family-wise significance
  double threshold = 0.0;    // > 0: use this |z| threshold instead of the Šidák one
  double relative_variance_floor = kRelativeVarianceFloor;
};

struct ZTestResult {
  size_t tested = 0;        // pixel-channels with v, r and the given variances all finite
  size_t passed = 0;        // of those, |z| < threshold
  size_t skipped = 0;       // pixel-channels not tested (a non-finite value or variance)
  double threshold = 0.0;   // the |z| threshold used
  double alpha = 0.0;       // the family-wise α it was derived from (0 when given)
  double max_abs_z = 0.0;   // largest |z| among the tested pixel-channels

  size_t failed() const { return tested - passed; }
  // passed / tested; NaN when nothing was tested.
  double pass_fraction() const;
};

// image_var_mean and reference_var_mean are per-pixel variances of the mean estimates; pass
// nullptr for an image without one (at least one must be given: Error(Usage) otherwise).
// Negative variances are taken as 0.
ZTestResult z_test(const Image& image, const Image* image_var_mean, const Image& reference,
                   const Image* reference_var_mean, const ZTestOptions& options = {});

// t with P(|Z| > t) = 1 − (1 − alpha)^(1/n) for a standard normal Z. n = 1 gives the plain
// two-sided quantile (1.959964 for α = 0.05, 2.575829 for α = 0.01). n = 0 is taken as 1.
// Throws Error(Usage) unless 0 < alpha < 1.
double sidak_z_threshold(double alpha, size_t n);

// ---- Means, variances, efficiency ------------------------------------------------------

// Mean of all pixel-channels (NaN and Inf propagate: a broken pixel is not hidden).
double image_mean(const Image& image);

// Mean of a per-pixel variance image over all pixel-channels. For a variance-of-the-mean
// image (sample variance / spp) of an unbiased render, this is its expected MSE.
double mean_variance(const Image& variance);

// Per-pixel variance of the mean estimate from the sample variance of one sample and the
// samples per pixel: sample_variance / spp (all zero for spp 0). This is what EXR
// "variance.*" channels hold.
Image variance_of_mean(const Image& sample_variance, uint64_t spp);

// The mean of B independent renders (batches) and its standard error σ: the batch means
// m_b are i.i.d., so σ = sd(m_b) / sqrt(B) with the B − 1 sample standard deviation, and
// (mean − expected) / σ is ~N(0, 1) (Student t with B − 1 degrees of freedom) when the
// renderer is unbiased. Needs B ≥ 2 images of one size (Error(Usage) otherwise).
struct BatchMean {
  double mean = 0.0, sigma = 0.0;   // over all pixel-channels
  std::array<double, 3> channel_mean{}, channel_sigma{};
  size_t batches = 0;
};

BatchMean batch_mean(const std::vector<Image>& batches);

// Efficiency = 1 / (relMSE · seconds): higher is better; +Inf when relMSE or seconds is 0.
double efficiency(double rel_mse, double seconds);

}  // namespace clpt
