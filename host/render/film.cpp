#include "render/film.h"

#include <array>

namespace clpt {

Film::Film(const cl::Context& ctx, uint32_t width, uint32_t height, bool splats, bool sums_samples)
    : width_(width),
      height_(height),
      splats_(splats),
      sums_samples_(sums_samples),
      sum_(ctx, size_t(width) * height * sizeof(cl_float4), CL_MEM_READ_WRITE, nullptr, "film"),
      sum_sq_(ctx, size_t(width) * height * sizeof(cl_float4), CL_MEM_READ_WRITE, nullptr,
              "film variance buffer"),
      ray_counts_(ctx, size_t(width) * height * sizeof(cl_uint), CL_MEM_READ_WRITE, nullptr,
                  "ray counter buffer") {
  sum_.fill_zero();
  sum_sq_.fill_zero();
  ray_counts_.fill_zero();
  if (splats_) {
    splat_ = cl::Buffer(ctx, size_t(width) * height * sizeof(cl_float4), CL_MEM_READ_WRITE,
                        nullptr, "splat film");
    splat_.fill_zero();
  }
}

FilmResult Film::resolve(uint64_t spp) const {
  const size_t n = pixels();
  const auto sum = sum_.read_vector<std::array<float, 4>>(n);
  const auto sq = sum_sq_.read_vector<std::array<float, 4>>(n);
  const auto rays = ray_counts_.read_vector<uint32_t>(n);
  std::vector<std::array<float, 4>> splat;
  if (splats_) splat = splat_.read_vector<std::array<float, 4>>(n);
  FilmResult r;
  r.mean = Image(width_, height_);
  r.variance = Image(width_, height_);
  r.samples_per_pixel = spp;
  r.variance_available = sums_samples();
  for (size_t i = 0; i < n; ++i) {
    if (splats_) {
      // N = spp * pixels light paths; each splat already carries the 1 / A_pixel of the
      // pixel's importance relative to the whole film, so sum / spp is the pixel's estimate
      // (kernels/integrators/light_trace.cl, docs/concepts/light-tracing.md).
      r.dropped_samples += static_cast<uint64_t>(splat[i][3]);
      r.rays += rays[i];
      for (int c = 0; c < 3; ++c)
        r.mean.rgb[i * 3 + c] =
            spp ? static_cast<float>((double(sum[i][c]) + double(splat[i][c])) / double(spp)) : 0.0f;
      continue;
    }
    // Dropped samples count as zero radiance, so the estimate stays over all spp samples.
    r.dropped_samples += static_cast<uint64_t>(sum[i][3]);
    r.rays += rays[i];
    for (int c = 0; c < 3; ++c) {
      const double mean = spp ? double(sum[i][c]) / double(spp) : 0.0;
      const double var = spp > 1 ? (double(sq[i][c]) - double(spp) * mean * mean) / double(spp - 1)
                                 : 0.0;
      r.mean.rgb[i * 3 + c] = static_cast<float>(mean);
      r.variance.rgb[i * 3 + c] = static_cast<float>(var > 0.0 ? var : 0.0);
    }
  }
  return r;
}

}  // namespace clpt
