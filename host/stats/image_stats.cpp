#include "stats/image_stats.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "util/error.h"

namespace clpt {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string size_text(const Image& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height);
}

void require_same_size(const Image& a, const char* a_name, const Image& b, const char* b_name) {
  if (a.width != b.width || a.height != b.height || a.rgb.size() != b.rgb.size())
    throw Error(ExitCode::Usage, std::string("image sizes differ: ") + a_name + " is " +
                                     size_text(a) + ", " + b_name + " is " + size_text(b));
}

double relative_squared_error(double v, double r) {
  const double d = v - r, s = std::fabs(r) + kRelMseOffset;
  return (d * d) / (s * s);
}

}  // namespace

ImageSummary summarize(const Image& image) {
  ImageSummary s;
  s.width = image.width;
  s.height = image.height;
  std::array<double, 3> sum{};
  std::array<size_t, 3> count{};
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    const float v = image.rgb[i];
    if (std::isnan(v)) ++s.nan_count;
    else if (std::isinf(v)) ++s.inf_count;
    else {
      sum[i % 3] += v;
      ++count[i % 3];
    }
  }
  const size_t total = count[0] + count[1] + count[2];
  s.finite_mean = total ? (sum[0] + sum[1] + sum[2]) / double(total) : kNaN;
  for (int c = 0; c < 3; ++c) s.channel_finite_mean[c] = count[c] ? sum[c] / double(count[c]) : kNaN;
  return s;
}

ImageComparison compare_images(const Image& image, const Image& reference) {
  require_same_size(image, "image", reference, "reference");
  ImageComparison c;
  c.image = summarize(image);
  c.reference = summarize(reference);
  double rel = 0.0, sq = 0.0, smape = 0.0, max_diff = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    const double v = image.rgb[i], r = reference.rgb[i];
    if (!std::isfinite(v) || !std::isfinite(r)) continue;
    const double d = v - r, ad = std::fabs(d);
    rel += relative_squared_error(v, r);
    sq += d * d;
    smape += ad / (std::fabs(v) + std::fabs(r) + kSmapeOffset);
    max_diff = std::max(max_diff, ad);
    ++n;
  }
  c.compared = n;
  if (n == 0) {
    c.rel_mse = c.mse = c.rmse = c.smape = c.max_abs_diff = kNaN;
  } else {
    c.rel_mse = rel / double(n);
    c.mse = sq / double(n);
    c.rmse = std::sqrt(c.mse);
    c.smape = smape / double(n);
    c.max_abs_diff = max_diff;
  }
  return c;
}

Image relative_squared_error(const Image& image, const Image& reference) {
  require_same_size(image, "image", reference, "reference");
  Image out(image.width, image.height);
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    const double v = image.rgb[i], r = reference.rgb[i];
    out.rgb[i] = (std::isfinite(v) && std::isfinite(r))
                     ? static_cast<float>(relative_squared_error(v, r))
                     : std::numeric_limits<float>::quiet_NaN();
  }
  return out;
}

double ZTestResult::pass_fraction() const { return tested ? double(passed) / double(tested) : kNaN; }

double sidak_z_threshold(double alpha, size_t n) {
  if (!(alpha > 0.0 && alpha < 1.0))
    throw Error(ExitCode::Usage, "z-test significance must lie strictly between 0 and 1, not " +
                                     std::to_string(alpha));
  if (n == 0) n = 1;
  // p = 1 − (1 − α)^(1/n), written to keep its precision for large n.
  const double p = -std::expm1(std::log1p(-alpha) / double(n));
  // P(|Z| > t) = erfc(t / √2) falls monotonically in t; bisect it (erfc keeps full relative
  // precision far into the tail, so this is exact to double precision for any n).
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 200 && hi - lo > 0.0; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid == lo || mid == hi) break;
    if (std::erfc(mid / std::sqrt(2.0)) > p) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

ZTestResult z_test(const Image& image, const Image* image_var_mean, const Image& reference,
                   const Image* reference_var_mean, const ZTestOptions& options) {
  require_same_size(image, "image", reference, "reference");
  if (!image_var_mean && !reference_var_mean)
    throw Error(ExitCode::Usage, "z-test: neither image has a variance");
  if (image_var_mean) require_same_size(image, "image", *image_var_mean, "its variance");
  if (reference_var_mean)
    require_same_size(reference, "reference", *reference_var_mean, "its variance");
  if (!(options.relative_variance_floor >= 0.0))
    throw Error(ExitCode::Usage, "z-test: the variance floor must not be negative");

  // z of one pixel-channel; NaN where it cannot be tested.
  auto z_of = [&](size_t i) {
    const double v = image.rgb[i], r = reference.rgb[i];
    const double vv = image_var_mean ? double(image_var_mean->rgb[i]) : 0.0;
    const double vr = reference_var_mean ? double(reference_var_mean->rgb[i]) : 0.0;
    if (!std::isfinite(v) || !std::isfinite(r) || !std::isfinite(vv) || !std::isfinite(vr))
      return kNaN;
    const double m = std::max(std::fabs(v), std::fabs(r));
    const double var = std::max(std::max(vv, 0.0) + std::max(vr, 0.0),
                                options.relative_variance_floor * m * m);
    const double d = std::fabs(v - r);
    return d == 0.0 ? 0.0 : d / std::sqrt(var);  // var == 0 only when v == r == 0
  };
  // Two passes, so that no image-sized buffer of z is kept: the threshold needs n first.
  ZTestResult res;
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    if (std::isnan(z_of(i))) ++res.skipped;
    else ++res.tested;
  }
  if (options.threshold > 0.0) {
    res.threshold = options.threshold;
    res.alpha = 0.0;
  } else {
    res.threshold = sidak_z_threshold(options.alpha, res.tested);
    res.alpha = options.alpha;
  }
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    const double zi = z_of(i);
    if (std::isnan(zi)) continue;
    if (zi < res.threshold) ++res.passed;
    res.max_abs_z = std::max(res.max_abs_z, zi);
  }
  return res;
}

double image_mean(const Image& image) {
  if (image.rgb.empty()) return kNaN;
  double sum = 0.0;
  for (float v : image.rgb) sum += v;
  return sum / double(image.rgb.size());
}

double mean_variance(const Image& variance) { return image_mean(variance); }

Image variance_of_mean(const Image& sample_variance, uint64_t spp) {
  Image out(sample_variance.width, sample_variance.height);
  if (spp == 0) return out;
  for (size_t i = 0; i < out.rgb.size(); ++i)
    out.rgb[i] = static_cast<float>(double(sample_variance.rgb[i]) / double(spp));
  return out;
}

BatchMean batch_mean(const std::vector<Image>& batches) {
  if (batches.size() < 2)
    throw Error(ExitCode::Usage, "batch mean: needs at least 2 batches for a sigma, got " +
                                     std::to_string(batches.size()));
  for (size_t b = 1; b < batches.size(); ++b)
    require_same_size(batches[0], "batch 0", batches[b], "another batch");
  const size_t B = batches.size();
  // Per batch: the mean of each channel and of all pixel-channels.
  std::vector<std::array<double, 4>> m(B);
  for (size_t b = 0; b < B; ++b) {
    std::array<double, 3> sum{};
    const Image& img = batches[b];
    for (size_t i = 0; i < img.rgb.size(); ++i) sum[i % 3] += img.rgb[i];
    const double px = double(img.rgb.size() / 3);
    for (int c = 0; c < 3; ++c) m[b][c] = px > 0 ? sum[c] / px : kNaN;
    m[b][3] = px > 0 ? (sum[0] + sum[1] + sum[2]) / (3.0 * px) : kNaN;
  }
  std::array<double, 4> mean{}, sigma{};
  for (int k = 0; k < 4; ++k) {
    double s = 0.0;
    for (size_t b = 0; b < B; ++b) s += m[b][k];
    mean[k] = s / double(B);
    double ss = 0.0;
    for (size_t b = 0; b < B; ++b) ss += (m[b][k] - mean[k]) * (m[b][k] - mean[k]);
    sigma[k] = std::sqrt(ss / double(B - 1) / double(B));
  }
  BatchMean r;
  r.batches = B;
  r.mean = mean[3];
  r.sigma = sigma[3];
  for (int c = 0; c < 3; ++c) {
    r.channel_mean[c] = mean[c];
    r.channel_sigma[c] = sigma[c];
  }
  return r;
}

double efficiency(double rel_mse, double seconds) {
  const double x = rel_mse * seconds;
  return x == 0.0 ? std::numeric_limits<double>::infinity() : 1.0 / x;
}

}  // namespace clpt
