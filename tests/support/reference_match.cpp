#include "support/reference_match.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numeric>

#include "stats/image_stats.h"
#include "support/block_test.h"
#include "support/device.h"

namespace clpt::test {

std::vector<Image> render_batches(const Scene& scene, RenderSettings settings, uint32_t count,
                                  uint32_t seed0) {
  std::vector<Image> batches;
  for (uint32_t b = 0; b < count; ++b) {
    settings.seed = seed0 + b;
    const FilmResult f = Renderer(device_context(), scene, settings).render().film;
    EXPECT_EQ(f.samples_per_pixel, settings.spp) << "seed " << settings.seed;
    EXPECT_EQ(f.dropped_samples, 0u) << "seed " << settings.seed;
    EXPECT_EQ(f.variance_available, integrator_info(settings.integrator).film == FilmKind::SampleSums);
    batches.push_back(f.mean);
  }
  return batches;
}

ChannelMeans channel_means(const std::vector<Image>& batches) {
  ChannelMeans r{};
  const size_t n = batches[0].rgb.size(), B = batches.size();
  for (int c = 0; c < 3; ++c) {
    std::vector<double> bm;
    for (const Image& b : batches) {
      double s = 0.0;
      for (size_t i = c; i < n; i += 3) s += b.rgb[i];
      bm.push_back(s / double(n / 3));
    }
    const double m = std::accumulate(bm.begin(), bm.end(), 0.0) / double(B);
    double q = 0.0;
    for (double v : bm) q += (v - m) * (v - m);
    r.mean[c] = m;
    r.sigma[c] = std::sqrt(q / double(B - 1) / double(B));
  }
  return r;
}

void expect_matches_reference(const std::vector<Image>& batches, const FilmResult& reference,
                              const std::string& label, uint32_t block, double min_pixel_pass) {
  ASSERT_GE(batches.size(), 2u);
  const Image ref_var = variance_of_mean(reference.variance, reference.samples_per_pixel);
  const BlockTestResult t = block_means_test(batches, reference.mean, ref_var, block);
  EXPECT_EQ(t.failed, 0u) << label << ": " << t.summary();
  std::cout << "[ figures  ] " << label << " blocks: " << t.summary() << "\n";

  const uint32_t w = reference.mean.width, h = reference.mean.height;
  const size_t n = size_t(w) * h * 3, B = batches.size();
  Image mean(w, h), var(w, h);
  for (size_t i = 0; i < n; ++i) {
    double m = 0.0, q = 0.0;
    for (const Image& b : batches) m += b.rgb[i];
    m /= double(B);
    for (const Image& b : batches) q += (b.rgb[i] - m) * (b.rgb[i] - m);
    mean.rgb[i] = float(m);
    var.rgb[i] = float(q / double(B - 1) / double(B));
  }
  const ZTestResult z = z_test(mean, &var, reference.mean, &ref_var);
  EXPECT_GE(z.pass_fraction(), min_pixel_pass)
      << label << ": " << z.failed() << " of " << z.tested << " pixel-channels fail |z| < "
      << z.threshold << " (max |z| " << z.max_abs_z << ")";
  std::cout << "[ figures  ] " << label << " pixels: " << z.failed() << " of " << z.tested
            << " fail |z| < " << z.threshold << ", max |z| " << z.max_abs_z << "\n";

  const ChannelMeans bm = channel_means(batches);
  for (int c = 0; c < 3; ++c) {
    double rm = 0.0, rv = 0.0;
    for (size_t i = c; i < n; i += 3) rm += reference.mean.rgb[i], rv += ref_var.rgb[i];
    rm /= double(n / 3);
    rv /= double(n / 3) * double(n / 3);
    const double image_z = (bm.mean[c] - rm) / std::sqrt(bm.sigma[c] * bm.sigma[c] + rv);
    EXPECT_LT(std::fabs(image_z), 4.0) << label << " channel " << c << ": " << bm.mean[c]
                                       << " reference " << rm;
    std::cout << "[ figures  ] " << label << " channel " << c << ": " << bm.mean[c]
              << " reference " << rm << " z " << image_z << "\n";
  }
}

}  // namespace clpt::test
